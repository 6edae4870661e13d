// The command line of the study command (study_main.cc), apart from the model: parsed with
// CLI11 in study_args.cc, which does not depend on the model. study_main.cc includes
// study_args.cc (one translation unit) unless it is compiled with -DMECHGEN_STUDY_ARGS_SEPARATE:
// then study_args.cc is compiled once on its own and linked in (as sweep_args.cc). The checks
// are the command-line layer of every tool (common/cli.h on CLI11, common/numbers.h without it).
#pragma once

#include <string>

#include "common/params.h"

namespace mechgen::study_tool {

/// The options: counts checked, paths as given.
struct Arguments {
  std::string tool = "study";  ///< the tool's name for messages (argv[0])
  std::string study_path;      ///< --study (required)
  std::string csv_path, tolerance_path, envelope_path;
  std::string summary_path, histogram_path;  ///< --summary-csv, --histogram-csv (the statistics)
  bool timings = false;                      ///< --timings: each phase's wall and CPU time on stderr
  int threads = 1;             ///< --threads (default: the cores)
  bool quiet = false;
  std::string shards_path;     ///< --shards (empty: F.shards with --csv F)
  bool no_shards = false;
  long long chunk_size = 0;    ///< --chunk (0: the default)
  long long stop_after = 0;    ///< --stop-after (0: run to the end)
  tools::ParameterOptions params;  ///< --params, --set: the model's parameters before the study's
};

/// Exit status of a usage error (bad arguments: nothing written).
constexpr int kExitUsage = 2;

/**
 * \brief Parses the study command's options.
 * \param[in]  model_name  The model's name, for --help.
 * \param[out] arguments   The options.
 * \return -1 to go on, else the exit status to end with: 0 after --help (printed on stdout),
 *         kExitUsage after a usage error (one line "<tool>: error: ..." on stderr).
 */
int ParseArguments(int argc, char** argv, const std::string& model_name, Arguments* arguments);

}  // namespace mechgen::study_tool
