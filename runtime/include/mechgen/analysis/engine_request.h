/**
 * \file analysis/engine_request.h
 * What the engine command's analyses are asked for (analysis/engine.h runs them): the
 * subcommand and its options with their defaults, independent of the model, so that the
 * command line's parser (tools/engine_args.cc, CLI11) fills one without compiling anything
 * model-dependent. The numbers are checked by whoever fills it (the parser: the ranges its
 * --help lists); the parameters, the engine they make and the pressure table and law together
 * Check(model, request) in analysis/engine.h.
 */
#pragma once

#include <string>

#include "mechgen/analysis/params.h"
#include "mechgen/machines/engine/gas.h"

namespace mechgen::analysis {

/// The engine at constant speed (cycle), the flywheel it needs (flywheel) or its run-up
/// (runup).
struct EngineRequest {
  std::string command;  ///< cycle, flywheel or runup
  double rpm = 3000;
  int samples = 1440;
  std::string table;  ///< the indicator diagram's file (empty: the polytropic-Wiebe law)
  double cs = 0.02;
  double idle_rpm = -1;  ///< <= 0: rpm / 4
  double t_end = 60;
  double dt = 0.002;
  double steady_tol = 1e-5;
  int smoothing = 6;
  bool design = false;  ///< flywheel --design: the design sensitivities (the model's `design`)
  engine::PolytropicWiebeParams wiebe;
  tools::ParameterOptions params;  ///< --params, --set: the model's Params
};

/// Where the engine's CSVs go and how its messages name the command.
struct EngineOutputs {
  std::string tool = "engine";  ///< the command's name in usage errors
  std::string csv;  ///< cycle's and runup's CSV
  std::string loop_csv, sweep_csv, witt_csv;  ///< flywheel's: the energy loop, the C_s sweep, Wittenbauer's
};

}  // namespace mechgen::analysis
