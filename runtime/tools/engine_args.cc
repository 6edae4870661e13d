// The engine command's options with CLI11 (engine_args.h). Independent of the model.
#include "engine_args.h"

#include <string>

#include "common/cli.h"
#include "mechgen/io/format.h"
#include "mechgen/machines/flywheel/energy_loop.h"

namespace mechgen::engine_tool {

int ParseArguments(int argc, char** argv, const std::string& model_name, bool model_has_design,
                   Arguments* a) {
  a->tool = tools::ToolName(argc > 0 ? argv[0] : nullptr);
  auto UsageError = [a](const std::string& message) { return tools::UsageError(a->tool, message); };
  using tools::Between;
  using tools::Positive;

  CLI::App app{std::string("Crank torque, bearing loads, flywheel sizing and run-up of the engine "
                           "model '") +
               model_name + "' (Paul 6.8-6.9). Options may come before or after the subcommand."};
  app.footer(
      "Exit status: 0 done, 1 a computation failed, 2 a usage error; no output file is written "
      "unless the whole computation succeeded.");
  app.require_subcommand(1);
  CLI::App* cycle = app.add_subcommand(
      "cycle", "torque, pressures, side thrusts, bearing loads (and shaking) over one cycle at "
               "constant --rpm; harmonics and power smoothing");
  CLI::App* flywheel = app.add_subcommand(
      "flywheel", "energy loop at constant --rpm, J_fly for --cs, checked by simulating the "
                  "periodic steady state; C_s against J_fly");
  CLI::App* runup = app.add_subcommand(
      "runup", "from --idle-rpm against the load that balances the engine at --rpm, until the "
               "cycle mean speed settles or --t-end");
  // Every option is the parent's, so that it may follow the subcommand (fallthrough); an
  // option another subcommand uses is accepted and ignored.
  for (CLI::App* sub : {cycle, flywheel, runup}) sub->fallthrough();

  const std::string general = "Options";
  tools::Number(&app, "--rpm", &a->rpm, Between(kMinRpm, kMaxRpm),
                "crank speed (cycle, flywheel) or the target speed (runup)")
      ->group(general);
  tools::Count(&app, "--samples", &a->samples, 16, 1000000, "samples per cycle")->group(general);
  const std::string& model = model_name;
  app.add_option("--csv", a->csv, "cycle, runup: the CSV (default " + model + "_<subcommand>.csv)")
      ->group(general);
  tools::Count(&app, "--smoothing", &a->smoothing, 1, 64,
               "cycle: power smoothing for 1..max(K, cylinders)")
      ->group(general);
  app.add_flag("--design", a->design,
               "flywheel: also d/dp of the mean torque, dE, I and J_fly for the model's design "
               "parameters (its `design` section), the pressure a given function of the crank "
               "angle: needs --table (the parametric law's pressure moves with r, l and bore)")
      ->group(general);
  tools::Number(&app, "--cs", &a->cs, tools::NumberRange{mechgen::flywheel::kMinSpeedFluctuation, 1, false, true},
                "flywheel: the prescribed C_s = (w_max - w_min)/w_mean")
      ->group(general);
  app.add_option("--loop", a->loop_csv, "flywheel: the energy loop CSV (default " + model +
                                            "_energy_loop.csv)")
      ->group(general);
  app.add_option("--sweep", a->sweep_csv,
                 "flywheel: C_s against J_fly CSV (default " + model + "_cs_sweep.csv)")
      ->group(general);
  app.add_option("--wittenbauer", a->witt_csv,
                 "flywheel: the steady cycle CSV (default " + model + "_wittenbauer.csv)")
      ->group(general);
  app.add_option("--idle-rpm", a->idle_rpm, "runup: the starting speed (default rpm/4)")
      ->check(tools::NumberValidator(Between(kMinRpm, kMaxRpm)))->group(general);
  tools::Number(&app, "--t-end", &a->t_end, Positive(kMaxTime), "runup: end time (s)")
      ->group(general);
  tools::Number(&app, "--dt", &a->dt, Positive(kMaxTime),
                "runup: CSV row spacing (s); at least --t-end / 1e8")
      ->group(general);
  tools::Number(&app, "--steady-tol", &a->steady_tol, Between(1e-12, 0.5),
                "runup: stop when the cycle mean speed changes by less than this (relative)")
      ->group(general);

  // The pressure law, one for every cylinder at its own cycle angle from firing TDC.
  const std::string law =
      "Pressure law (--table, or the polytropic cycle with a Wiebe heat release; bore, stroke "
      "and rod from the model)";
  engine::PolytropicWiebeParams& w = a->wiebe;
  tools::AddParameterOptions(&app, &a->params);
  app.add_option("--table", a->table,
                 "indicator diagram: rows 'angle_deg,p_gauge_Pa' over the cycle (a header line "
                 "is skipped)")
      ->group(law);
  tools::Number(&app, "--cr", &w.compression_ratio, Positive(1000), "compression ratio")
      ->group(law);
  tools::Number(&app, "--p-intake", &w.p_intake, Positive(kMaxPressure),
                "absolute intake pressure (Pa)")
      ->group(law);
  tools::Number(&app, "--p-ambient", &w.p_ambient, Positive(kMaxPressure),
                "absolute ambient pressure (Pa; gauge 0)")
      ->group(law);
  tools::Number(&app, "--n", &w.n, Positive(10), "polytropic exponent")->group(law);
  double burn_start_deg = -15, burn_duration_deg = 60;
  CLI::Option* burn_start =
      tools::Number(&app, "--burn-start", &burn_start_deg, tools::Magnitude(720),
                    "start of the burn (deg from firing TDC)")
          ->group(law);
  CLI::Option* burn_duration =
      tools::Number(&app, "--burn-duration", &burn_duration_deg, Positive(720),
                    "duration of the burn (deg)")
          ->group(law);
  tools::Number(&app, "--wiebe-a", &w.wiebe_a, Positive(100), "Wiebe efficiency parameter a")
      ->group(law);
  tools::Number(&app, "--wiebe-m", &w.wiebe_m, tools::NonNegative(100), "Wiebe form factor m")
      ->group(law);
  tools::Number(&app, "--heat", &w.heat, tools::NonNegative(1e9),
                "heat released per cylinder and cycle (J)")
      ->group(law);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    // The whole help (every option is the parent's), also after a subcommand.
    std::cout << app.get_formatter()->make_help(&app, app.get_name(), CLI::AppFormatMode::Normal);
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.get_formatter()->make_help(&app, app.get_name(), CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::ParseError& e) {
    std::string extra;  // what CLI11 could not place, in command-line order
    for (const std::string& word : app.remaining(true)) extra += " " + word;
    if (app.get_subcommands().empty()) {
      // CLI11 reports a stray word before the subcommand check: name the subcommands.
      for (const std::string& word : app.remaining())
        if (!word.empty() && word[0] != '-')
          return UsageError("unknown subcommand '" + word + "': cycle, flywheel or runup");
      return UsageError("a subcommand is required: cycle, flywheel or runup");
    }
    if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr)
      return UsageError("unknown option or stray argument:" + extra);
    return UsageError(e.what());
  }
  a->command = app.get_subcommands().front()->get_name();
  // The run-up's time stepping must advance (t + dt > t) and its rows stay bounded.
  std::string error;
  if (a->command == "runup" &&
      !tools::CheckTimeStep("--dt", tools::FormatNumber(a->dt), a->dt, a->t_end, 1e8, &error))
    return UsageError(error);
  if (burn_start->count() > 0) w.burn_start = internal::FromDegrees(burn_start_deg);
  if (burn_duration->count() > 0) w.burn_duration = internal::FromDegrees(burn_duration_deg);
  if (a->design && a->command != "flywheel")
    return UsageError("--design: the flywheel subcommand only (its mean torque, dE, I and J_fly)");
  if (a->design && !model_has_design)
    return UsageError("--design: the model has no `design` section (tools/make_engine.py --design "
                      "writes one)");
  if (a->design && a->table.empty())
    return UsageError("--design needs --table: the derivatives hold the pressure trace p(theta) "
                      "fixed, which an indicator diagram is and the parametric law (its volume "
                      "depends on r, l and bore) is not");
  if (a->csv.empty() && a->command != "flywheel") a->csv = model + "_" + a->command + ".csv";
  if (a->loop_csv.empty()) a->loop_csv = model + "_energy_loop.csv";
  if (a->sweep_csv.empty()) a->sweep_csv = model + "_cs_sweep.csv";
  if (a->witt_csv.empty()) a->witt_csv = model + "_wittenbauer.csv";
  return -1;
}


}  // namespace mechgen::engine_tool
