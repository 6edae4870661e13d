// The command line of the statics command (statics_main.cc), apart from the model: parsed
// with CLI11 in statics_args.cc, which does not depend on the model (so that `mechgen statics`
// can answer --help and a bad option before anything is compiled). statics_main.cc includes
// statics_args.cc (one translation unit, as mechgen_add_model() compiles it) unless it is
// compiled with -DMECHGEN_STATICS_ARGS_SEPARATE: then statics_args.cc is compiled on its own
// and linked in. The checks are the command-line layer of every tool (common/cli.h on
// CLI11, common/numbers.h without it); what needs the model (--range's inputs, the step and
// scan limits, --design, rpm on a slide input) statics_main.cc checks.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "common/params.h"

namespace mechgen::statics_tool {

/// The bounds of the counts: --steps stops at 10^6 rows (the CSV is streamed, but the SVG's
/// rows are held in memory); the scans at 10^6 samples.
constexpr long long kMaxSteps = 1000000;
constexpr long long kMaxSamples = 1000000;
constexpr long long kMaxSnapshots = 1000;
/// ScanOptions::kMinSamples (statics/types.h): the fewest samples of a scan.
constexpr long long kMinSamples = 36;
/// Options::max_condition's default (statics/types.h: 1 / kMinRcond, core/constants.h).
constexpr double kDefaultMaxCondition = 1e6;

/// The options: numbers and counts checked; --range as given (text; statics_main.cc checks
/// it against the model).
struct Arguments {
  std::string tool = "statics";  ///< the tool's name for messages (argv[0])
  long long steps = 360;
  std::vector<std::string> ranges;
  std::string csv_path, svg_path;
  std::string plots_prefix, plot_format = "png";
  long long snapshots = 4;
  bool animate = false;
  /// --design: the design-sensitivity columns (a model with a design section).
  bool design = false;
  long long table = 8;
  bool dead_zones = false, equilibria = false;
  long long samples = 360;
  double max_condition = kDefaultMaxCondition;
  /// --speed: the input's constant speed in model units per second (rad/s for an angle, m/s
  /// for a slide; given in rev/min with the suffix rpm, converted here); NaN: not given (the
  /// statics at rest).
  double speed = std::numeric_limits<double>::quiet_NaN();
  bool speed_rpm = false;  ///< --speed was given in rpm (an angle input only)
  tools::ParameterOptions params;  ///< --params, --set: applied to the model's Params
};

/// Exit status of a usage error (bad arguments: nothing written).
constexpr int kExitUsage = 2;

/// "60rpm" -> 2 pi rad/s (as the flywheel's RpmToRadPerSecond: rpm 2 pi / 60), *rpm true;
/// "-3.5" -> -3.5, *rpm false. False if malformed, not finite or |value| > 1e5 per second.
bool ParseSpeed(const std::string& text, double* value, bool* rpm);

/**
 * \brief Parses the statics command's options.
 * \param[in]  model_name  The model's name, for --help.
 * \param[out] arguments   The options.
 * \return -1 to go on, else the exit status to end with: 0 after --help (printed on
 *         stdout), kExitUsage after a usage error (one line "<tool>: error: ..." on stderr).
 */
int ParseArguments(int argc, char** argv, const std::string& model_name, Arguments* arguments);

}  // namespace mechgen::statics_tool
