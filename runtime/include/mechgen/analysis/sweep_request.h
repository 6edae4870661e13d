/**
 * \file analysis/sweep_request.h
 * What a sweep is asked for (analysis/sweep.h runs it): the options with their defaults,
 * independent of the model and of the runtime, so that the command line's parser
 * (tools/sweep_args.cc, CLI11) fills one without compiling anything model-dependent. The counts
 * are checked by whoever fills it (the parser: --steps in 1..kMaxSteps, --table in
 * 0..kMaxSteps + 1); what needs the model (the inputs' names, the step limit, the modes, the
 * design section, the parameters) Check(model, request) in analysis/sweep.h.
 */
#pragma once

#include <string>
#include <vector>

#include "mechgen/analysis/params.h"

namespace mechgen::analysis {

/// The sweep: the inputs along a straight line, staying on one assembly mode.
struct SweepRequest {
  long long steps = 360;  ///< rows = steps + 1
  long long table = 9;    ///< rows of the printed table (0: none)
  /// "input:min:max" (analysis/inputs.h, ParseRange); none: the model's range of every input.
  std::vector<std::string> ranges;
  /// The input speeds and accelerations as given: one value or one per input ("deg" allowed).
  std::vector<std::string> qd_text, qdd_text;
  std::string mode;  ///< a named assembly mode (the model's assembly_modes:); empty: the default
  /// The design-sensitivity columns d<output>/d<parameter> (a model with a design section).
  bool design = false;
  /// What the sweep does at a singular configuration: stop, follow (a change point: on along
  /// the same smooth curve, the branch it was on), switch (a change point: onto the other
  /// curve) or reverse (a dead point: the input turns back).
  std::string at_singular = "stop";
  tools::ParameterOptions params;  ///< --params, --set: applied to the model's Params
};

/// What a sweep writes and how its messages name the command (not the analysis itself).
struct SweepOutputs {
  std::string tool = "sweep";  ///< the command's name in usage errors
  std::string csv_path, svg_path;  ///< empty: not written
  bool animate = true;  ///< the SVG's SMIL animation
  /// The solver's assembler's name in the summary line ("Ceres", "Levenberg-Marquardt").
  const char* assembler_name = "Levenberg-Marquardt";
};

// Exit statuses of the sweep (models/README.md, "Exit statuses of the sweep"):
constexpr int kSweepConverged = 0;   ///< every row converged; the outputs written
constexpr int kSweepError = 1;       ///< model or output error: nothing written
constexpr int kSweepUsage = 2;       ///< bad request: nothing written (one line on stderr)
constexpr int kSweepRowsFailed = 3;  ///< the outputs written, but some rows did not converge

/// The bound on --steps: 10^7 steps make a CSV of a few GB; the sweep itself streams (holds
/// one row, plus the table's rows and a bounded number for the drawing).
constexpr long long kSweepMaxSteps = 10000000;

}  // namespace mechgen::analysis
