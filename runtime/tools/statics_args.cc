// The statics command's options with CLI11 (statics_args.h). Independent of the model.
#include "statics_args.h"

#include <cmath>
#include <string>

#include "common/cli.h"

namespace mechgen::statics_tool {

bool ParseSpeed(const std::string& text, double* value, bool* rpm) {
  std::string number = text;
  *rpm = number.size() > 3 && number.compare(number.size() - 3, 3, "rpm") == 0;
  if (*rpm) number.resize(number.size() - 3);
  double v = 0;
  if (!tools::ParseNumber(number, &v)) return false;
  // rev/min -> rad/s as the flywheel tool converts its --rpm (RpmToRadPerSecond).
  if (*rpm) v = v * 2 * 3.141592653589793 / 60;
  if (!(std::abs(v) <= tools::kMaxSpeed)) return false;
  *value = v;
  return true;
}

int ParseArguments(int argc, char** argv, const std::string& model_name, Arguments* arguments) {
  Arguments& a = *arguments;
  a.tool = tools::ToolName(argc > 0 ? argv[0] : nullptr);
  CLI::App app{"Statics of the mechgen model '" + model_name +
               "' along a motion: driving forces (with friction forward and backward), "
               "reactions, V, mechanical advantage, dead zones, equilibria; CSV, table, SVG."};
  app.footer("Exit status: 0 done, 2 a usage error (one line on stderr), 3 the model does not "
             "assemble, 4 an output cannot be written.");
  tools::Count(&app, "--steps", &a.steps, 1, kMaxSteps, "number of steps (rows = steps + 1)");
  app.add_option("--range", a.ranges,
                 "input:min:max, input by name or index; values in model units (radians), "
                 "or with a 'deg' suffix (e.g. theta_crank:0:180deg), min and max in "
                 "[-1e4, 1e4]. Default: the model's range of every input");
  std::string speed_text;
  app.add_option("--speed", speed_text,
                 "the statics along the motion at this constant speed of the swept input (the "
                 "first input that moves along the range; the others move with it along the "
                 "line): the loads that read a velocity (<coordinate>_dot, dampers, viscous "
                 "friction) taken at qd, the dependent velocities K qd, t = 0; the kinetostatics "
                 "without the inertia forces. In rad/s for an angle input, m/s for a slide, or "
                 "rev/min with an 'rpm' suffix for an angle (e.g. 60rpm, as the flywheel's "
                 "--rpm); negative: the input turning back; |speed| <= 1e5 per second. Default: "
                 "at rest (qd = 0)")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            double v = 0;
            bool rpm = false;
            if (ParseSpeed(text, &v, &rpm)) return {};
            return "bad value " + tools::Quote(text) +
                   ": expected a number in [-1e5, 1e5] (rad/s or m/s), or with 'rpm' in "
                   "[-954929, 954929]";
          },
          "SPEED[rpm]", ""));
  app.add_option("--csv", a.csv_path, "write every row to this CSV file (plot it with "
                                      "runtime/tools/plot_statics.gnuplot)");
  app.add_option("--svg", a.svg_path, "write the mechanism at a few configurations to this SVG "
                                      "file: the reactions (red) and the applied loads, springs and "
                                      "weights (blue) as arrows, curved arrows and zig-zags with their "
                                      "magnitudes and a force scale");
  app.add_option("--plots", a.plots_prefix,
                 "draw with gnuplot (on PATH) PREFIX_drive.<format>, the driving forces (and "
                 "with friction to run in +q and -q) and the reaction magnitudes against the "
                 "input (plot_statics.gnuplot), and PREFIX_bearings.<format>, the polar diagram "
                 "of each ground bearing's load: the force of the ground on the moving link, "
                 "fixed frame (plot_bearings.gnuplot); from the --csv file, else PREFIX.csv");
  app.add_option("--plot-format", a.plot_format, "png or svg (default png)")
      ->check(CLI::IsMember({"png", "svg"}));
  tools::Count(&app, "--snapshots", &a.snapshots, 1, kMaxSnapshots,
               "configurations drawn in the SVG (their labels placed so that none overlap; "
               "1: one configuration per picture)");
  app.add_flag("--animate", a.animate, "add the animated copy of the sweep to the SVG");
  app.add_flag("--design", a.design,
               "add the CSV columns ddrive_<q>/d<p>, dR/d<p>, dV/d<p>: the derivatives without friction "
               "with respect to the model's design parameters (its `design` section)");
  tools::Count(&app, "--table", &a.table, 0, kMaxSteps + 1,
               "print this many rows to stdout (0: none)");
  app.add_flag("--dead-zones", a.dead_zones,
               "scan each input's range for self-locking intervals (T_back T0 <= 0), at rest");
  app.add_flag("--equilibria", a.equilibria,
               "find the configurations where Q = 0 along the range, with their stability, at "
               "rest");
  tools::Count(&app, "--samples", &a.samples, kMinSamples, kMaxSamples,
               "samples of the dead-zone and equilibrium scans; at least 36, and at most 10 "
               "deg apart along an angle input");
  tools::Number(&app, "--max-condition", &a.max_condition, tools::Between(1, 1e16),
                "forces are withheld (status singular) where cond_1(Phi_phi) exceeds this");
  tools::AddParameterOptions(&app, &a.params);
  const int parsed = tools::Parse(&app, argc, argv, a.tool);
  if (parsed >= 0) return parsed;
  if (!speed_text.empty() && !ParseSpeed(speed_text, &a.speed, &a.speed_rpm))
    return tools::UsageError(a.tool, tools::BadValue("--speed", speed_text, "SPEED[rpm]"));
  return -1;
}

}  // namespace mechgen::statics_tool
