// The flywheel command's options with CLI11 (flywheel_args.h). Independent of the model.
#include "flywheel_args.h"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "common/cli.h"
#include "mechgen/machines/flywheel/energy_loop.h"

namespace mechgen::flywheel_tool {

int ParseArguments(int argc, char** argv, const std::string& model_name, double max_check_samples,
                   Arguments* arguments) {
  Arguments& a = *arguments;
  a.tool = tools::ToolName(argc > 0 ? argv[0] : nullptr);
  CLI::App app{"Flywheel sizing of the mechgen model '" + model_name +
               "': the driving torque at constant speed over a cycle, its energy loop, the "
               "flywheel for a coefficient of speed fluctuation, and a simulated check."};
  app.footer("Exit status: 0 done, 1 the machine cannot be sized (the reason and angle on "
             "stderr; nothing written), the simulated check failed (the loop's CSV and pictures "
             "are still written: they do not depend on it) or an output cannot be written, 2 a "
             "usage error (one line on stderr), 3 the model does not assemble.");
  std::string theta0_text, cycle_text;
  std::vector<std::string> break_texts;
  tools::Number(&app, "--rpm", &a.rpm, tools::Between(1e-3, 1e6), "the mean speed of the input (rev/min)");
  tools::Number(&app, "--cs", &a.cs, tools::NumberRange{flywheel::kMinSpeedFluctuation, 0.5, false, true},
                "the coefficient of speed fluctuation C_s = (w_max - w_min)/w_mean to size for");
  tools::Count(&app, "--samples", &a.samples, 8, 10000000,
               "samples of the cycle (equal angle steps; the energy loop's accuracy: see --help "
               "of the README, fourth order where T_req is smooth)");
  app.add_option("--theta0", theta0_text,
                 "the cycle's start (rad, or with a 'deg' suffix); default the model's range start");
  app.add_option("--cycle", cycle_text,
                 "the cycle (rad, or 'deg'); default the model's range when whole turns, else 360deg");
  app.add_option("--break", break_texts,
                 "an angle (rad, or 'deg') where a switched load makes T_req kink or jump, on a "
                 "sample or between two: the energy loop does not integrate across it (fourth order "
                 "instead of second or first); repeatable. The switches of a model with `dynamics` "
                 "(its EvalSwitchModes) are found and made breaks without it")
      ->allow_extra_args(false);
  app.add_flag("--no-switch-breaks", a.no_switch_breaks,
               "do not make the located switches of the loads breaks of the energy loop");
  app.add_option("--motor", a.motor, "the simulated check's motor: constant (T = T_mean) or shunt "
                                     "(T = T_stall (1 - w/w_0) through w_m, T_mean)")
      ->check(CLI::IsMember({"constant", "shunt"}))
      ->capture_default_str();
  // A slip below 1e-4 is a synchronous motor: a torque line so steep that the check's settling
  // time I w_0 s / T_mean leaves the explicit integrator steps of a hair (1e-300: no end).
  tools::Number(&app, "--slip", &a.slip, tools::NumberRange{1e-4, 1, false, true},
                "shunt motor: the slip 1 - w_m/w_0 at the mean speed");
  app.add_flag("--check", a.check, "simulate the machine with the flywheel (default with `dynamics`)");
  app.add_flag("--no-check", a.no_check, "no simulated check");
  tools::Count(&app, "--check-samples", &a.check_samples, 16, 1000000,
               "the check's speed samples per cycle (equal time steps)");
  tools::Count(&app, "--max-cycles", &a.max_cycles, 3, 100000,
               "the check gives up without a steady cycle after this many cycles, or after 10 "
               "settling times (the machine's inertia with the flywheel over the slope of the mean "
               "load and motor torque against the speed) when that is longer (at most 20000)");
  CLI::Option* steady_fraction =
      tools::Number(&app, "--steady-fraction", &a.steady_fraction, tools::Between(1e-6, 0.1),
                    "the check's steady state: the cycle-mean speed changing per cycle, relative, by "
                    "less than this fraction of the C_s the flywheel is expected to give (over the "
                    "settling time in cycles when that is longer than one), two cycles in a row (the "
                    "drift inside the measured cycle is then that fraction of its w_max - w_min)");
  app.add_option("--steady-tol", a.steady_tol,
                 "instead of --steady-fraction: this relative change of the cycle-mean speed per "
                 "cycle, two cycles in a row")
      ->check(tools::NumberValidator(tools::Between(1e-12, 1e-2)));
  app.add_flag("--design", a.design,
               "also the design sensitivities (the model's `design` section): d/dp of the mean "
               "torque, dE, the machine's mean inertia and the flywheel, and dT_req/d<p> columns "
               "in the CSV (machines/flywheel/cycle_design.h; not with Coulomb friction)");
  app.add_option("--csv", a.csv_path, "write the energy loop (theta, T_req, T_mean, E, ...) to this CSV");
  app.add_option("--png", a.png_path, "draw the torque and energy loop to this PNG (needs gnuplot)");
  app.add_option("--svg", a.svg_path, "draw the torque and energy loop to this SVG (needs gnuplot)");
  tools::AddParameterOptions(&app, &a.params);
  if (const int parsed = tools::Parse(&app, argc, argv, a.tool); parsed >= 0) return parsed;

  if (a.check && a.no_check) return tools::UsageError(a.tool, "--check and --no-check: choose one");
  if (!std::isnan(a.steady_tol) && steady_fraction->count() > 0)
    return tools::UsageError(a.tool, "--steady-tol and --steady-fraction: choose one");
  if (static_cast<double>(a.check_samples) * a.max_cycles > max_check_samples)
    return tools::UsageError(a.tool, "--check-samples x --max-cycles: at most " + tools::FormatNumber(max_check_samples) +
                                         " speed samples in the check (the simulator's limit)");
  auto angle = [&](const std::string& option, const std::string& text, bool positive, double* value) {
    if (!tools::ParseNumber(text, value, /*allow_degrees=*/true) || !(std::abs(*value) <= tools::kMaxPosition) ||
        (positive && !(*value > 0)))
      return tools::UsageError(a.tool, tools::BadValue(option, text,
                                                       std::string(positive ? "an angle > 0" : "an angle") +
                                                           " in rad (or with a 'deg' suffix), at most 1e4"));
    return -1;
  };
  if (!theta0_text.empty())
    if (const int e = angle("--theta0", theta0_text, false, &a.theta0); e >= 0) return e;
  if (!cycle_text.empty())
    if (const int e = angle("--cycle", cycle_text, true, &a.cycle); e >= 0) return e;
  for (const std::string& text : break_texts) {
    double b = 0;
    if (const int e = angle("--break", text, false, &b); e >= 0) return e;
    a.breaks.push_back(b);
  }
  // The pictures' paths (and the CSV's, which gnuplot reads) go into a gnuplot command line.
  for (const auto& [kind, path] : {std::pair<std::string, const std::string*>{"png", &a.png_path},
                                   std::pair<std::string, const std::string*>{"svg", &a.svg_path}}) {
    if (path->empty()) continue;
    for (const std::string* p : {path, static_cast<const std::string*>(&a.csv_path)}) {
      if (p->find_first_of("'\"\\$`\n") != std::string::npos)
        return tools::UsageError(a.tool, tools::BadValue(p == path ? "--" + kind : std::string("--csv"), *p,
                                                         "a path without quotes, $, ` or \\ (gnuplot reads it)"));
    }
  }
  return -1;
}

}  // namespace mechgen::flywheel_tool
