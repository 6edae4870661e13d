// The command line of the flywheel command (flywheel_main.cc), apart from the model: parsed with
// CLI11 in flywheel_args.cc, which does not depend on the model. flywheel_main.cc includes
// flywheel_args.cc (one translation unit) unless it is compiled with -DMECHGEN_TOOL_ARGS_SEPARATE:
// then flywheel_args.cc is compiled once on its own and linked in (mechgen_tool_args in the build
// tree: mechgen_view, the driver and mechgen_add_model()'s tools; `mechgen flywheel` keeps the
// object in its cache for every model, so that a model's first run does not compile CLI11 again).
// The checks are the command-line layer of every tool (common/cli.h on CLI11, common/numbers.h
// without it); what needs the model (--design without a `design` section, --check without
// `dynamics`, --samples against the model's cycle, the parameters) is checked by flywheel_main.cc.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "mechgen/analysis/flywheel_request.h"

namespace mechgen::flywheel_tool {

/// The default of --steady-fraction: machines/flywheel/machine_cycle.h's
/// CheckOptions::steady_fraction (flywheel_main.cc asserts they agree).
constexpr double kDefaultSteadyFraction = analysis::kFlywheelSteadyFraction;

/// The options: the request (analysis/flywheel_request.h: numbers checked here) and the outputs
/// (the CSV and the pictures).
struct Arguments : analysis::FlywheelRequest {
  std::string tool = "flywheel";  ///< the tool's name for messages (argv[0])
  std::string csv_path, png_path, svg_path;
};

constexpr int kExitUsage = 2;

/// The most speed samples the check may take: the simulator's MinimalOptions::max_samples
/// (flywheel_main.cc asserts that they agree), for the `mechgen` driver, which parses the options
/// before any compile and without the runtime.
constexpr double kMaxCheckSamples = analysis::kFlywheelMaxCheckSamples;

/**
 * \brief Parses the flywheel command's options.
 * \param[in]  model_name         The model's name, for --help.
 * \param[in]  max_check_samples  The most speed samples the check may take (--check-samples x
 *                                --max-cycles): the simulator's max_samples.
 * \param[out] arguments          The options.
 * \return -1 to go on, else the exit status to end with: 0 after --help (printed on stdout),
 *         kExitUsage after a usage error (one line "<tool>: error: ..." on stderr).
 */
int ParseArguments(int argc, char** argv, const std::string& model_name, double max_check_samples,
                   Arguments* arguments);

}  // namespace mechgen::flywheel_tool
