// The command line of the sweep command (sweep_main.cc), apart from the model: parsed with
// CLI11 in sweep_args.cc, which does not depend on the model. sweep_main.cc includes
// sweep_args.cc (one translation unit, as mechgen_add_model() compiles it) unless it is
// compiled with -DMECHGEN_SWEEP_ARGS_SEPARATE: then sweep_args.cc is compiled once on its
// own and linked in (`mechgen sweep` keeps that object in its cache for every model, so
// that a model's first run does not compile CLI11 again). The checks are the command-line
// layer of every tool (common/cli.h on CLI11, common/numbers.h without it).
#pragma once

#include <string>
#include <vector>

#include "common/params.h"

namespace mechgen::sweep_tool {

/// The options: counts checked; --range, --qd, --qdd as given (text; sweep_main.cc checks
/// them against the model).
struct Arguments {
  std::string tool = "sweep";  ///< the tool's name for messages (argv[0])
  long long steps = 360;
  long long table = 9;
  std::vector<std::string> ranges;
  std::vector<std::string> qd_text, qdd_text;
  std::string csv_path, svg_path;
  std::string mode;  ///< a named assembly mode (the model's assembly_modes:); empty: the default
  bool no_animation = false;
  /// --design: the design-sensitivity columns d<output>/d<parameter> (a model with a design
  /// section).
  bool design = false;
  /// What the sweep does at a singular configuration (--at-singular): stop, follow (a change
  /// point: on along the same smooth curve, the branch it was on), switch (a change point: onto
  /// the other curve) or reverse (a dead point: the input turns back).
  std::string at_singular = "stop";
  tools::ParameterOptions params;  ///< --params, --set: applied to the model's Params
};

/// Exit status of a usage error (bad arguments: nothing written).
constexpr int kExitUsage = 2;

/// The bound on --steps: 10^7 steps make a CSV of a few GB; the sweep itself streams (holds
/// one row, plus the table's rows and a bounded number for the drawing).
constexpr long long kMaxSteps = 10000000;

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
