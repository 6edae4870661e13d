/**
 * \file analysis/statics_request.h
 * What a statics sweep is asked for (analysis/statics.h runs it): the options with their
 * defaults and bounds, independent of the model and of the runtime, so that the command line's
 * parser (tools/statics_args.cc, CLI11) fills one without compiling anything model-dependent.
 * The numbers and counts are checked by whoever fills it (the parser: the bounds below); what
 * needs the model (the inputs' names, the step limit, the scans' resolution, --speed on a
 * slide, --design) Check(model, request) in analysis/statics.h.
 */
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "mechgen/analysis/params.h"

namespace mechgen::analysis {

/// The bounds of the counts: steps stop at 10^6 rows (the CSV is streamed, but the SVG's rows
/// are held in memory); the scans at 10^6 samples.
constexpr long long kStaticsMaxSteps = 1000000;
constexpr long long kStaticsMaxSamples = 1000000;
/// ScanOptions::kMinSamples (statics/types.h, asserted equal in analysis/statics.h): the fewest
/// samples of a scan.
constexpr long long kStaticsMinSamples = 36;
/// Options::max_condition's default (statics/types.h: 1 / kMinRcond, core/constants.h; asserted
/// equal in analysis/statics.h).
constexpr double kStaticsDefaultMaxCondition = 1e6;

/// The statics along the inputs' straight line: the driving forces, the reactions, and the
/// dead-zone and equilibrium scans.
struct StaticsRequest {
  long long steps = 360;  ///< rows = steps + 1
  /// "input:min:max" (analysis/inputs.h, ParseRange); none: the model's range of every input.
  std::vector<std::string> ranges;
  /// The design-sensitivity columns (a model with a design section).
  bool design = false;
  long long table = 8;  ///< rows of the printed table (0: none)
  bool dead_zones = false, equilibria = false;
  long long samples = 360;  ///< the scans' samples
  double max_condition = kStaticsDefaultMaxCondition;
  /// The input's constant speed in model units per second (rad/s for an angle, m/s for a
  /// slide; given in rev/min with the suffix rpm, converted by the parser); NaN: the statics at
  /// rest.
  double speed = std::numeric_limits<double>::quiet_NaN();
  bool speed_rpm = false;  ///< the speed was given in rpm (an angle input only)
  tools::ParameterOptions params;  ///< --params, --set: applied to the model's Params
};

/// What a statics sweep writes and how its messages name the command.
struct StaticsOutputs {
  std::string tool = "statics";  ///< the command's name in usage errors
  std::string csv_path, svg_path;  ///< empty: not written
  bool animate = false;  ///< the force diagram's SMIL animation
  long long snapshots = 4;  ///< the force diagram's snapshots
};

/// What the command's pictures (tools/statics_run.h, --plots) need to know of the model.
struct StaticsPlotFacts {
  std::string first_input;  ///< the first input's name (the driving forces are drawn against it)
  /// The ground bearings' polar diagram: drawn when the model has such bearings, else the line
  /// that says why not.
  bool bearings = false;
  std::string no_bearings;
};

}  // namespace mechgen::analysis
