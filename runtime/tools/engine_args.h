// The command line of the engine command (engine_main.cc), apart from the model: parsed with CLI11
// in engine_args.cc, which does not depend on the model. engine_main.cc includes engine_args.cc
// (one translation unit) unless it is compiled with -DMECHGEN_TOOL_ARGS_SEPARATE: then
// engine_args.cc is compiled once on its own and linked in (mechgen_tool_args in the build tree:
// mechgen_view, the driver and mechgen_add_model()'s tools; `mechgen engine` keeps the object in
// its cache for every model, so that a model's first run does not compile CLI11 again). The checks
// are the command-line layer of every tool (common/cli.h on CLI11, common/numbers.h without it);
// the pressure table's file and the law's parameters together are checked by engine_main.cc
// (machines/engine/gas.h).
#pragma once

#include <string>

#include "mechgen/analysis/engine_request.h"

namespace mechgen::engine_tool {

// The limits of the options (--help lists them).
constexpr double kMinRpm = 1e-3;      // below it w^2 (and so dE/(C_s w^2)) runs off the numbers
constexpr double kMaxRpm = 1e5;
constexpr double kMaxTime = 1e6;      // s
constexpr double kMaxPressure = 1e9;  // Pa

/// The options: the request (analysis/engine_request.h: numbers checked here against their
/// ranges, the subcommand) and the CSVs (their default names from the model's).
struct Arguments : analysis::EngineRequest {
  std::string tool = "engine";  ///< for messages (argv[0])
  std::string csv, loop_csv, sweep_csv, witt_csv;
};

/// Exit status of a usage error (bad arguments: nothing written).
constexpr int kExitUsage = 2;

/**
 * \brief Parses the engine command's options (they may come before or after the subcommand).
 * \param[in]  model_name        The model's name, for --help and the CSVs' default names.
 * \param[in]  model_has_design  Whether the model has a `design` section (--design needs it).
 * \param[out] a                 The options.
 * \return -1 to go on, else the exit status to end with: 0 after --help (printed on stdout),
 *         kExitUsage after a usage error (one line "<tool>: error: ..." on stderr).
 */
int ParseArguments(int argc, char** argv, const std::string& model_name, bool model_has_design,
                   Arguments* a);

}  // namespace mechgen::engine_tool
