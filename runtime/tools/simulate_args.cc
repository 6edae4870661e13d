// The simulate command's options with CLI11 (simulate_args.h). Independent of the model.
#include "simulate_args.h"

#include <algorithm>
#include <string>
#include <vector>

#include "common/cli.h"

namespace mechgen::simulate_tool {

bool ParseList(const std::string& text, std::vector<double>* values) {
  return analysis::ParseSimulateList(text, values);
}

namespace {

// The limits of the options (--help lists them; common/numbers.h): positions in model units
// (rad, m), speeds per second; a time step must leave at most kMaxTimeSteps rows over
// --t-end, so that t + dt > t all the way and the CSV stays bounded.
constexpr double kMaxTime = 1e6;  // s
constexpr double kMaxPosition = tools::kMaxPosition;
constexpr double kMaxSpeed = tools::kMaxSpeed;
constexpr double kMaxRows = tools::kMaxTimeSteps;
constexpr double kMinRtol = 1e-14;        // ~50 ulp: below, rounding dominates the error
constexpr double kMaxRtol = 0.1;
constexpr double kMaxAtol = 1;
constexpr long long kMaxIntegratorSteps = 2000000000;

constexpr const char* kDriveForm =
    "NAME=speed:W, NAME=move:Q1:T0:T1, NAME=cycloidal:Q1:T0:T1 (0 <= T0 < T1) or "
    "NAME=table:FILE";

// NAME=speed:W | move:Q1:T0:T1 | cycloidal:Q1:T0:T1 | table:FILE, with W, Q1, T0, T1 inside
// the tool's limits. The name is checked against the model later.
bool ParseDrive(const std::string& text, DriveSpec* drive) {
  DriveSpec d;
  d.text = text;
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) return false;
  d.name = text.substr(0, eq);
  const std::string law = text.substr(eq + 1);
  const size_t colon = law.find(':');
  if (colon == std::string::npos) return false;
  d.kind = law.substr(0, colon);
  const std::string rest = law.substr(colon + 1);
  if (d.kind == "table") {
    d.file = rest;
    if (d.file.empty()) return false;
  } else {
    std::string list = rest;
    std::replace(list.begin(), list.end(), ':', ',');
    if (!ParseList(list, &d.values)) return false;
    if (d.kind == "speed") {
      if (d.values.size() != 1 || !tools::Magnitude(kMaxSpeed).Contains(d.values[0])) return false;
    } else if (d.kind == "move" || d.kind == "cycloidal") {
      if (d.values.size() != 3 || !tools::Magnitude(kMaxPosition).Contains(d.values[0]) ||
          !(d.values[1] >= 0 && d.values[2] > d.values[1] && d.values[2] <= kMaxTime))
        return false;
    } else {
      return false;
    }
  }
  *drive = d;
  return true;
}

}  // namespace

int ParseArguments(int argc, char** argv, const std::string& model, Arguments* a) {
  a->tool = tools::ToolName(argc > 0 ? argv[0] : nullptr);
  CLI::App app{"Simulates the motion of the mechgen model '" + model +
               "' (minimal method, Paul 6.6.1) and writes a CSV."};
  app.footer(
      "Exit status: 0 reached --t-end or a steady state, 1 the run failed (the reason on "
      "stderr), 2 a usage error (one line on stderr).");
  tools::Number(&app, "--t-end", &a->t_end, tools::Positive(kMaxTime), "end time (s)");
  tools::Number(&app, "--dt", &a->dt, tools::Positive(kMaxTime),
                "CSV row spacing (s); at least --t-end / 1e8");
  std::string& q0_text = a->q0_text;
  std::string& qd0_text = a->qd0_text;
  app.add_option("--q0", q0_text,
                 "initial inputs V[,V...] (rad, or e.g. 90deg; m for a slide; |V| <= 1e4; "
                 "default: the assembly)")
      ->check(tools::NumberListValidator(tools::Magnitude(kMaxPosition), true));
  app.add_option("--qd0", qd0_text,
                 "initial speeds V[,V...] (rad/s or m/s, |V| <= 1e5; default 0: from rest)")
      ->check(tools::NumberListValidator(tools::Magnitude(kMaxSpeed), true));
  app.add_option("--method", a->method, "dopri5 or dop853")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            if (text == "dopri5" || text == "dop853") return {};
            return "bad value " + tools::Quote(text) + ": expected dopri5 or dop853";
          },
          "dopri5|dop853", ""))
      ->capture_default_str();
  tools::Number(&app, "--rtol", &a->rtol, tools::Between(kMinRtol, kMaxRtol),
                "integrator relative tolerance");
  tools::Number(&app, "--atol", &a->atol, tools::NonNegative(kMaxAtol),
                "integrator absolute tolerance (model units)");
  tools::Number(&app, "--steady-tol", &a->steady_tol, tools::Between(1e-12, 0.5),
                "stop at a periodic steady state: the mean speed of a revolution of the first "
                "input changes by less than this, relative, twice in a row");
  bool no_steady = false;
  app.add_flag("--no-steady", no_steady, "run to --t-end regardless");
  app.add_flag("--energy-projection", a->energy_projection,
               "keep T + V - W_nc at its initial value (long conservative runs)");
  app.add_flag("--stop-at-speed-zero", a->stop_at_speed_zero,
               "stop where the first input's speed changes sign");
  app.add_option("--friction", a->friction,
                 "Coulomb friction of the model's friction joints: in the free motion with stick "
                 "and slip, in a driven run (every input driven) in the actuator forces; on or off "
                 "(default: on where the model's `friction:` gives a coefficient)")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            if (text == "on" || text == "off") return {};
            return "bad value " + tools::Quote(text) + ": expected on or off";
          },
          "on|off", ""));
  tools::Count(&app, "--max-steps", &a->max_steps, 1, kMaxIntegratorSteps,
               "integrator steps before giving up");
  std::vector<std::string> drive_text;
  app.add_option("--drive", drive_text,
                 "a motion generator NAME=LAW: input NAME (as in the CSV header) follows LAW, "
                 "the other inputs are free; repeat for several. LAW: speed:W (constant speed "
                 "W, rad/s or e.g. 90deg, from the initial value), move:Q1:T0:T1 (rest to rest "
                 "to Q1 between T0 and T1 s, 3-4-5 polynomial), cycloidal:Q1:T0:T1 (the same, "
                 "cycloidal), table:FILE (the clamped cubic spline through the rows t,q of a "
                 "CSV file; a header line is skipped). The CSV gets lambda_NAME, the actuator "
                 "force the law needs.")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            DriveSpec d;
            if (ParseDrive(text, &d)) return {};
            return "bad value " + tools::Quote(text) + ": expected " + kDriveForm;
          },
          "NAME=LAW", ""));
  app.add_option("--csv", a->csv, "write the CSV there (default: " + model + "_simulate.csv)");
  app.add_flag("--quiet", a->quiet, "no summary on stdout");
  app.add_flag("--design", a->design,
               "add the trajectory sensitivities d<q>/d<p> and d<q>_dot/d<p> to the model's design "
               "parameters (its `design` section), integrated with the motion (forward "
               "sensitivity equations); the free motion only, to --t-end (no steady-state stop, "
               "Coulomb friction, energy projection or --drive)");
  tools::AddParameterOptions(&app, &a->params);
  if (const int parsed = tools::Parse(&app, argc, argv, a->tool); parsed >= 0) return parsed;
  a->steady = !no_steady;
  std::string error;
  if (!tools::CheckTimeStep("--dt", tools::FormatNumber(a->dt), a->dt, a->t_end, kMaxRows,
                            &error))
    return tools::UsageError(a->tool, error);
  if (!q0_text.empty()) ParseList(q0_text, &a->q0);
  if (!qd0_text.empty()) ParseList(qd0_text, &a->qd0);
  for (const std::string& text : drive_text) {
    a->drives.emplace_back();
    ParseDrive(text, &a->drives.back());
  }
  return -1;
}

}  // namespace mechgen::simulate_tool
