// The command line of the statics command (statics_main.cc), apart from the model: parsed with
// CLI11 in statics_args.cc, which does not depend on the model (so that `mechgen statics` can
// answer --help and a bad option before anything is compiled). statics_main.cc includes
// statics_args.cc (one translation unit) unless it is compiled with -DMECHGEN_TOOL_ARGS_SEPARATE:
// then statics_args.cc is compiled once on its own and linked in (mechgen_tool_args in the build
// tree: mechgen_view, the driver and mechgen_add_model()'s tools; `mechgen statics` keeps the
// object in its cache for every model, so that a model's first run does not compile CLI11 again).
// The checks are the command-line layer of every tool (common/cli.h on CLI11, common/numbers.h
// without it); what needs the model (--range's inputs, the step and scan limits, --design, rpm on a
// slide input) statics_main.cc checks.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "mechgen/analysis/statics_request.h"

namespace mechgen::statics_tool {

/// The bounds of the counts (analysis/statics_request.h).
constexpr long long kMaxSteps = analysis::kStaticsMaxSteps;
constexpr long long kMaxSamples = analysis::kStaticsMaxSamples;
constexpr long long kMaxSnapshots = 1000;
/// ScanOptions::kMinSamples (statics/types.h): the fewest samples of a scan.
constexpr long long kMinSamples = analysis::kStaticsMinSamples;
/// Options::max_condition's default (statics/types.h: 1 / kMinRcond, core/constants.h).
constexpr double kDefaultMaxCondition = analysis::kStaticsDefaultMaxCondition;

/// The options: the request (analysis/statics_request.h: numbers and counts checked here;
/// --range as given, checked against the model by analysis::Check) and the outputs.
struct Arguments : analysis::StaticsRequest {
  std::string tool = "statics";  ///< the tool's name for messages (argv[0])
  std::string csv_path, svg_path;
  std::string plots_prefix, plot_format = "png";
  long long snapshots = 4;
  bool animate = false;
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
