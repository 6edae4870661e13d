// The command line of the simulate command (simulate_main.cc), apart from the model: parsed with
// CLI11 in simulate_args.cc, which does not depend on the model, so that `mechgen simulate MODEL
// --help` and a bad option are answered before the model is generated or compiled
// (generator/driver/tool_args.cc links it into mechgen). simulate_main.cc includes simulate_args.cc
// (one translation unit) unless it is compiled with -DMECHGEN_TOOL_ARGS_SEPARATE: then
// simulate_args.cc is compiled once on its own and linked in (mechgen_tool_args in the build tree:
// mechgen_view, the driver and mechgen_add_model()'s tools; `mechgen simulate` keeps the object in
// its cache for every model, so that a model's first run does not compile CLI11 again). What
// depends on the model is checked by the simulation analysis (mechgen/analysis/simulate.h: Check,
// Run): the number of --q0 and --qd0 values, a --drive's input name, a --drive table's file,
// --friction on and --design against what the model has, the --set and --params names.
#pragma once

#include <string>
#include <vector>

#include "mechgen/analysis/simulate_request.h"

namespace mechgen::simulate_tool {

/// One --drive NAME=LAW as given: the input's name (checked against the model later) and its
/// law, each number inside the tool's limits (analysis/simulate_request.h).
using DriveSpec = analysis::SimulateDrive;

/// The options: the request (analysis/simulate_request.h: each number checked finite and in
/// its range, --q0, --qd0 and --drive parsed) and its outputs (the CSV, the summary).
struct Arguments : analysis::SimulateRequest {
  std::string tool = "simulate";  ///< for messages (argv[0])
  std::string csv;
  bool quiet = false;
};

/// Comma-separated numbers, each finite (with an optional 'deg' suffix); false if not.
bool ParseList(const std::string& text, std::vector<double>* values);

/**
 * \brief Parses the simulate command's options.
 * \param[in]  model_name  The model's name, for --help (and the default CSV's name in it).
 * \param[out] arguments   The options.
 * \return -1 to go on, else the exit status to end with: 0 after --help (printed on
 *         stdout), tools::kExitUsage after a usage error (one line "<tool>: error: ..." on
 *         stderr).
 */
int ParseArguments(int argc, char** argv, const std::string& model_name, Arguments* arguments);

}  // namespace mechgen::simulate_tool
