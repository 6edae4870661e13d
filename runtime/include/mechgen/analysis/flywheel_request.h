/**
 * \file analysis/flywheel_request.h
 * What the flywheel sizing is asked for (analysis/flywheel.h runs it): the options with their
 * defaults, independent of the model, so that the command line's parser
 * (tools/flywheel_args.cc, CLI11) fills one without compiling anything model-dependent. The
 * numbers are checked by whoever fills it (the parser: the ranges its --help lists); what
 * needs the model (--design, --check on a massless machine, the parameters, the samples
 * against the cycle) Check(model, request) in analysis/flywheel.h.
 */
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "mechgen/analysis/params.h"

namespace mechgen::analysis {

/// --steady-fraction's default (flywheel::CheckOptions::steady_fraction; asserted equal in
/// analysis/flywheel.h).
constexpr double kFlywheelSteadyFraction = 1e-3;
/// The most speed samples the simulated check may take (check_samples x max_cycles): the
/// simulator's max_samples (asserted equal in analysis/flywheel.h).
constexpr double kFlywheelMaxCheckSamples = 100000000;

/// The flywheel of a one-input machine at a mean speed, sized for a coefficient of speed
/// fluctuation C_s from the energy loop, and optionally checked by simulation.
struct FlywheelRequest {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double rpm = 60;                ///< the input's mean speed (rev/min)
  double cs = 0.02;               ///< the C_s to size for
  int samples = 720;              ///< samples of the cycle
  double theta0 = kNaN;           ///< the cycle's start (rad); NaN: the model's range start
  double cycle = kNaN;            ///< the cycle (rad); NaN: the model's default cycle
  std::vector<double> breaks;     ///< where T_req kinks or jumps (rad), in the order given
  bool no_switch_breaks = false;  ///< do not locate the loads' switches
  std::string motor = "constant";  ///< the check's motor: constant or shunt
  double slip = 0.05;
  bool check = false, no_check = false;
  int check_samples = 720, max_cycles = 400;
  double steady_fraction = kFlywheelSteadyFraction;
  double steady_tol = kNaN;  ///< given: the relative change per cycle instead of steady_fraction C_s
  bool design = false;       ///< the design sensitivities (the model's `design` section)
  tools::ParameterOptions params;  ///< --params, --set: applied to the model's Params
};

/// Where the flywheel's CSV goes and how its messages name the command.
struct FlywheelOutputs {
  std::string tool = "flywheel";  ///< the command's name in usage errors
  std::string csv_path;           ///< empty: not written (unless `picture`: then a temporary one)
  bool picture = false;           ///< a picture is drawn from the CSV after Run (tools/flywheel_run.h)
};

/// Where Run left the CSV for the pictures.
struct FlywheelResult {
  bool written = false;   ///< the CSV (or the temporary one) written: the pictures may follow
  std::string csv;        ///< the CSV the pictures read
  std::string temporary;  ///< the temporary CSV to remove afterwards (empty: none)
};

}  // namespace mechgen::analysis
