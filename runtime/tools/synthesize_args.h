// The command line of the synthesize command (synthesize_main.cc), apart from the model: parsed
// with CLI11 in synthesize_args.cc, which does not depend on the model (synthesize_main.cc
// includes it: one translation unit; `mechgen` links it to answer --help and a bad option before
// anything is generated or compiled). The checks are the command-line layer of every tool
// (common/cli.h on CLI11, common/numbers.h without it).
#pragma once

#include <string>

#include "common/params.h"

namespace mechgen::synthesize_tool {

/// The options: counts checked, paths as given.
struct Arguments {
  std::string tool = "synthesize";  ///< the tool's name for messages (argv[0])
  std::string task_path;            ///< --task (required)
  std::string out_dir = "synthesis_out";
  std::string model_path;           ///< --model (empty: from argv[0], `mechgen synthesize MODEL`)
  unsigned long long seed = 1;
  int threads = 1;                  ///< --threads (default: the cores)
  long long evaluations = 0;        ///< --evaluations (0: the task's)
  tools::ParameterOptions params;   ///< --params, --set: the model's parameters before the synthesis
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
