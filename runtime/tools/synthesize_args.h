// The command line of the synthesize command (synthesize_main.cc), apart from the model: parsed
// with CLI11 in synthesize_args.cc, which does not depend on the model (`mechgen` links it to
// answer --help and a bad option before anything is generated or compiled). synthesize_main.cc
// includes synthesize_args.cc (one translation unit) unless it is compiled with
// -DMECHGEN_TOOL_ARGS_SEPARATE: then synthesize_args.cc is compiled once on its own and linked in
// (mechgen_tool_args in the build tree: mechgen_view, the driver and mechgen_add_model()'s tools;
// `mechgen synthesize` keeps the object in its cache for every model, so that a model's first run
// does not compile CLI11 again). The checks are the command-line layer of every tool (common/cli.h
// on CLI11, common/numbers.h without it).
#pragma once

#include <string>

#include "common/params.h"
#include "mechgen/analysis/synthesize_request.h"

namespace mechgen::synthesize_tool {

/// The options: the request (analysis/synthesize_request.h: counts checked here, paths as
/// given; --model empty: the command takes it from `mechgen synthesize MODEL`,
/// synthesize_run.h) and the tool's name.
struct Arguments : analysis::SynthesizeRequest {
  std::string tool = "synthesize";  ///< the tool's name for messages (argv[0])
};

/// Exit status of a usage error (bad arguments: nothing written).
constexpr int kExitUsage = 2;

/**
 * \brief Parses the synthesize command's options.
 * \param[in]  model_name  The model's name, for --help.
 * \param[out] arguments   The options.
 * \return -1 to go on, else the exit status to end with: 0 after --help (printed on stdout),
 *         kExitUsage after a usage error (one line "<tool>: error: ..." on stderr).
 */
int ParseArguments(int argc, char** argv, const std::string& model_name, Arguments* arguments);

}  // namespace mechgen::synthesize_tool
