// The command line of the simulate command (simulate_main.cc), apart from the model: parsed
// with CLI11 in simulate_args.cc, which does not depend on the model, so that `mechgen
// simulate MODEL --help` and a bad option are answered before the model is generated or
// compiled (generator/driver/tool_args.cc links it into mechgen). simulate_main.cc includes
// simulate_args.cc (one translation unit, as mechgen_add_model() and `mechgen simulate`
// compile it). What depends on the model stays in simulate_main.cc: the number of --q0 and
// --qd0 values, a --drive's input name, a --drive table's file, --friction on and --design
// against what the model has, the --set and --params names.
#pragma once

#include <string>
#include <vector>

#include "common/params.h"

namespace mechgen::simulate_tool {

/// One --drive NAME=LAW as given: the input's name (checked against the model later) and its
/// law, each number inside the tool's limits.
struct DriveSpec {
  std::string text;  ///< as given, for messages
  std::string name;
  std::string kind;  ///< speed, move, cycloidal, table
  std::vector<double> values;
  std::string file;  ///< table:FILE (read by the tool)
};

/// The options, each checked finite and in its range; --q0, --qd0 and --drive parsed.
struct Arguments {
  std::string tool = "simulate";  ///< for messages (argv[0])
  double t_end = 10;
  double dt = 0.001;
  double rtol = 1e-8;
  double atol = 1e-10;
  std::string method = "dopri5";
  std::vector<double> q0, qd0;
  std::string q0_text, qd0_text;  ///< as given, for messages
  std::string csv;
  double steady_tol = 1e-4;
  bool steady = true;
  bool energy_projection = false;
  bool stop_at_speed_zero = false;
  std::string friction;  ///< --friction: "on", "off" or "" (the model's friction section)
  bool quiet = false;
  bool design = false;  ///< --design: the trajectory sensitivities (dynamics/sensitivity.h)
  int max_steps = 1000000;
  std::vector<DriveSpec> drives;
  tools::ParameterOptions params;  ///< --params, --set: applied to the model's Params
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
