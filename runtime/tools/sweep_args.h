// The command line of the sweep command (sweep_main.cc), apart from the model: parsed with CLI11 in
// sweep_args.cc, which does not depend on the model. sweep_main.cc includes sweep_args.cc (one
// translation unit) unless it is compiled with -DMECHGEN_TOOL_ARGS_SEPARATE: then sweep_args.cc is
// compiled once on its own and linked in (mechgen_tool_args in the build tree: mechgen_view, the
// driver and mechgen_add_model()'s tools; `mechgen sweep` keeps the object in its cache for every
// model, so that a model's first run does not compile CLI11 again). The checks are the command-line
// layer of every tool (common/cli.h on CLI11, common/numbers.h without it).
#pragma once

#include <string>
#include <vector>

#include "mechgen/analysis/sweep_request.h"

namespace mechgen::sweep_tool {

/// The options: the request (analysis/sweep_request.h: counts checked here; --range, --qd,
/// --qdd as given, checked against the model by analysis::Check) and where the outputs go.
struct Arguments : analysis::SweepRequest {
  std::string tool = "sweep";  ///< the tool's name for messages (argv[0])
  std::string csv_path, svg_path;
  bool no_animation = false;
};

/// Exit status of a usage error (bad arguments: nothing written).
constexpr int kExitUsage = 2;

/// The bound on --steps: 10^7 steps make a CSV of a few GB; the sweep itself streams (holds
/// one row, plus the table's rows and a bounded number for the drawing).
constexpr long long kMaxSteps = analysis::kSweepMaxSteps;

/**
 * \brief Parses the sweep command's options.
 * \param[in]  model_name  The model's name, for --help.
 * \param[in]  max_steps   The largest --steps (--table: up to max_steps + 1).
 * \param[out] arguments   The options.
 * \return -1 to go on, else the exit status to end with: 0 after --help (printed on
 *         stdout), kExitUsage after a usage error (one line "<tool>: error: ..." on stderr).
 */
int ParseArguments(int argc, char** argv, const std::string& model_name, long long max_steps,
                   Arguments* arguments);

}  // namespace mechgen::sweep_tool
