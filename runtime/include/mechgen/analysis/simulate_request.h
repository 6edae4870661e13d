/**
 * \file analysis/simulate_request.h
 * What the simulation is asked for (analysis/simulate.h runs it): the options with their
 * defaults, independent of the model, so that the command line's parser
 * (tools/simulate_args.cc, CLI11) fills one without compiling anything model-dependent. The
 * numbers are checked by whoever fills it (the parser: the ranges its --help lists); what
 * needs the model (the number of q0 and qd0 values, a drive's input and table file, friction
 * on, design, the parameters) Check(model, request) in analysis/simulate.h.
 */
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "mechgen/analysis/numbers.h"
#include "mechgen/analysis/params.h"

namespace mechgen::analysis {

/// One driven input (--drive NAME=LAW) as given: the input's name (checked against the model
/// by Check) and its law, each number inside the parser's limits.
struct SimulateDrive {
  std::string text;  ///< as given, for messages
  std::string name;  ///< the input's name (as in the CSV header)
  std::string kind;  ///< speed, move, cycloidal, table
  std::vector<double> values;  ///< speed: W; move, cycloidal: Q1, T0, T1
  std::string file;  ///< table: the file of rows t,q (read by Run)
};

/// The motion of a model with `dynamics` from t = 0 to t_end: free (the minimal method), some
/// or every input driven (drives), or the free motion with its trajectory sensitivities
/// (design). Angles in rad, slides in m, times in s.
struct SimulateRequest {
  double t_end = 10;
  double dt = 0.001;  ///< the CSV's row spacing
  double rtol = 1e-8;
  double atol = 1e-10;
  std::string method = "dopri5";  ///< dopri5 or dop853
  std::vector<double> q0, qd0;     ///< empty: the model's assembly, from rest
  std::string q0_text, qd0_text;  ///< as given, for messages
  double steady_tol = 1e-4;
  bool steady = true;             ///< stop at a periodic steady state (an angle input)
  bool energy_projection = false;
  bool stop_at_speed_zero = false;
  std::string friction;  ///< "on", "off" or "" (the model's friction section)
  bool design = false;   ///< the trajectory sensitivities (dynamics/sensitivity.h)
  int max_steps = 1000000;
  std::vector<SimulateDrive> drives;
  tools::ParameterOptions params;  ///< --params, --set: applied to the model's Params
};

/// Where the simulation's CSV goes and how its messages name the command.
struct SimulateOutputs {
  std::string tool = "simulate";  ///< the command's name in usage errors
  std::string csv;                ///< the CSV (empty: <model>_simulate.csv)
  bool quiet = false;             ///< no summary on stdout
  /// What Run does not do on this model (through the view, design: Check's text without its
  /// "not reached through the model view yet"): the command's refusal, its return the exit
  /// status (tools/common/not_through_view.h: a usage error, or mechgen's fallback). Unset: a
  /// usage error with Check's text.
  std::function<int(const std::string& what, const std::string& model)> not_through_view;
};

/// Comma-separated numbers, each finite (with an optional 'deg' suffix); false if not.
inline bool ParseSimulateList(const std::string& text, std::vector<double>* values) {
  std::string error;
  return tools::CheckNumberList("", text, tools::Finite(), true, values, &error);
}

}  // namespace mechgen::analysis
