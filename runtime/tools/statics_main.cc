// <model>_statics: the statics command of one generated mechgen model (issue 14).
//
// mechgen_add_model() (cmake/MechgenAddModel.cmake) compiles this one generic file per model
// whose outputs ask for `forces`, with -DMECHGEN_MODEL_INCLUDE="<name>.h"
// -DMECHGEN_MODEL_NAMESPACE=mech::<name>. It assembles the mechanism at the model's assembly
// configuration, sweeps the inputs along a straight line (by default every input over the
// model's kQMin..kQMax) staying on that assembly mode, and at every configuration reports
// the driving forces (without friction and, with friction, forward and backward), the
// reactions, V, the mechanical advantage and a status per row; optionally the dead zones
// (self-locking intervals) and the equilibrium positions along the range. Writes a CSV file,
// a short table and an SVG force diagram (statics/svg.h: the reactions, and the applied loads
// and springs where the model has Model::AppliedLoads). `--plots PREFIX` runs gnuplot on
// the CSV: PREFIX_drive.png (runtime/tools/plot_statics.gnuplot: the driving torque, with
// friction to run in +q and -q, and the reaction magnitudes against the input) and
// PREFIX_bearings.png (plot_bearings.gnuplot: the polar diagram of each ground bearing's
// load); gnuplot missing or the scripts not found: one line, exit 1, before anything is
// computed. Example:
//   slider_crank_friction_statics --steps 720 --csv out/scf.csv --svg out/scf.svg --plots out/scf
// Speed (issue 45): where the model's loads read a velocity (a load of <coordinate>_dot, a
// damper, viscous joint friction; statics::SpeedItems), every run says so on its output and in
// its CSV's first comment line (statics::SpeedNote): at rest they are taken at qd = 0. With
// --speed SPEED the statics are taken along the motion at that constant speed of the swept
// input (the first input that moves; rad/s, m/s, or rev/min with 'rpm' as the flywheel's
// --rpm): the loads at qd and the dependent velocities K qd, t = 0, without the inertia
// forces (the kinetostatics without inertia); the dead-zone and equilibrium scans stay at rest.
// Options are read by statics_args.cc (model-independent, CLI11; the command-line layer of
// every tool, runtime/tools/common/): `--opt=value` or `--opt value`, every number finite and
// in the range --help lists; --steps up to 10^6 (every row is held in memory); --samples from
// 36 (statics::ScanOptions::kMinSamples) and at most 10 deg apart along an angle input, so
// that a scan cannot report what a few samples happen to show as converged. Exit status: 0
// done, 2 a usage error (one line "<tool>: error: ..."), 3 the model does not assemble, 4 an
// output cannot be written.
// A model generated without `forces` builds into a stub that says so (exit status 2).
// Compiled with -DMECHGEN_TOOL_NO_CERES it needs Eigen and CLI11 only: it assembles with the
// Ceres-free PositionSolver (NewtonAssembler, position/assembler.h), as `mechgen statics
// <model.yaml>` builds it (generator/driver/); the Newton polish follows either assembler.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "statics_args.h"
#ifndef MECHGEN_STATICS_ARGS_SEPARATE
#include "statics_args.cc"
#endif

#include "common/gnuplot.h"
#include "common/numbers.h"
#include "mechgen/io/output_file.h"
#ifdef MECHGEN_TOOL_NO_CERES
#include "mechgen/position/solver.h"
#else
#include "mechgen/position/ceres_adapter.h"
#endif
#include "mechgen/statics/columns.h"
#include "mechgen/statics/dead_zones.h"
#include "mechgen/statics/equilibrium.h"
#include "mechgen/statics/svg.h"
#include "mechgen/statics/sweep.h"

#ifndef MECHGEN_MODEL_INCLUDE
#error "compile with -DMECHGEN_MODEL_INCLUDE=\"<name>.h\" -DMECHGEN_MODEL_NAMESPACE=mech::<name>"
#endif
#include MECHGEN_MODEL_INCLUDE

namespace {

constexpr double kDegToRad = 0.017453292519943295;

namespace tools = mechgen::tools;

// "1.5" -> 1.5 (model units, radians for angles); "90deg" -> pi/2. False if malformed.
bool ParseValue(const std::string& text, double* value) {
  return tools::ParseNumber(text, value, /*allow_degrees=*/true);
}

// The argument parser's copies of the runtime's limits (statics_args.h: it does not include
// the runtime).
static_assert(mechgen::statics_tool::kMinSamples == mechgen::statics::ScanOptions::kMinSamples);
static_assert(mechgen::statics_tool::kDefaultMaxCondition == mechgen::kMaxCondition);

// "i:min:max" with i an input index or name -> (index, min, max).
template <class M>
bool ParseRange(const std::string& text, int* index, double* min, double* max,
                std::string* error) {
  const size_t a = text.find(':');
  const size_t b = a == std::string::npos ? a : text.find(':', a + 1);
  if (b == std::string::npos) {
    *error = tools::BadValue("--range", text, "input:min:max");
    return false;
  }
  const std::string name = text.substr(0, a);
  *index = -1;
  for (int j = 0; j < M::kNq; ++j)
    if (name == M::kQNames[j] || name == std::to_string(j)) *index = j;
  if (*index < 0) {
    *error = tools::BadValue("--range", text, "input:min:max") + "; no input named " +
             tools::Quote(name) + "; inputs are";
    for (const char* q : M::kQNames) *error += std::string(" ") + q;
    return false;
  }
  if (!ParseValue(text.substr(a + 1, b - a - 1), min) || !ParseValue(text.substr(b + 1), max) ||
      !(std::abs(*min) <= tools::kMaxPosition) || !(std::abs(*max) <= tools::kMaxPosition)) {
    *error = tools::BadValue("--range", text,
                             "input:min:max with min and max in [-1e4, 1e4] (append 'deg' for "
                             "degrees)");
    return false;
  }
  return true;
}

namespace fs = std::filesystem;

// The pictures of --plots: gnuplot (found on PATH) runs these plot scripts of runtime/tools/
// on the command's own CSV (common/gnuplot.h: where the scripts are looked up).
constexpr const char* kPlotScripts[] = {"plot_statics.gnuplot", "plot_bearings.gnuplot"};

// The units of a table's columns other than its angles (printed in degrees, said by the
// table's unit line) and dimensionless ones: "drive_theta_crank, drive_theta_crank_plus
// [N m]; |F_O|, |F_B| [N]", consecutive columns of one unit together.
template <class Columns>
std::string TableUnits(const Columns& columns) {
  std::string text, unit;
  for (const auto& c : columns) {
    if (c.table_name.empty() || c.angle || c.unit.empty() || c.unit == "1" || c.text) continue;
    if (c.unit != unit && !unit.empty()) text += " [" + unit + "]; ";
    else if (!unit.empty()) text += ", ";
    text += c.table_name;
    unit = c.unit;
  }
  return unit.empty() ? std::string("none") : text + " [" + unit + "]";
}

template <class M>
std::string Describe(int j, double value) {
  char buffer[64];
  if (M::kQIsAngle[j]) {
    std::snprintf(buffer, sizeof(buffer), "%.4f deg", value / kDegToRad);
  } else {
    std::snprintf(buffer, sizeof(buffer), "%.6g m", value);
  }
  return buffer;
}

template <class M>
int Run(int argc, char** argv) {
  namespace statics = mechgen::statics;
  using Types = mechgen::ModelTypes<M>;
  mechgen::statics_tool::Arguments args;
  if (const int parsed = mechgen::statics_tool::ParseArguments(argc, argv, M::kName, &args);
      parsed >= 0)
    return parsed;
  const std::string& tool = args.tool;
  const int steps = static_cast<int>(args.steps), samples = static_cast<int>(args.samples);
  const int table_rows = static_cast<int>(args.table);
  const bool dead_zones = args.dead_zones, equilibria = args.equilibria, design = args.design;
  std::string csv_path = args.csv_path;
  const std::string& svg_path = args.svg_path;
  const std::string& plots_prefix = args.plots_prefix;
  const std::string& plot_format = args.plot_format;
  const std::vector<std::string>& ranges = args.ranges;
  typename M::template ParamsT<double> params;
  if (std::string why; !tools::ApplyParameters(args.params, &params, &why))
    return tools::UsageError(tool, why);

  typename Types::VecQ q_begin = Eigen::Map<const typename Types::VecQ>(M::kQMin.data());
  typename Types::VecQ q_end = Eigen::Map<const typename Types::VecQ>(M::kQMax.data());
  for (const std::string& text : ranges) {
    int j = 0;
    double min = 0, max = 0;
    std::string error;
    if (!ParseRange<M>(text, &j, &min, &max, &error)) return tools::UsageError(tool, error);
    q_begin(j) = min;
    q_end(j) = max;
  }
  // A step longer than the position solver accepts (position::Options::max_input_step)
  // would make every row invalid_input: a units mistake, refused here as by the sweep.
  const double max_step = mechgen::position::Options().max_input_step;
  for (int j = 0; j < M::kNq; ++j) {
    if (!(std::abs(q_end(j) - q_begin(j)) / steps <= max_step)) {
      return tools::UsageError(
          tool, std::string("--range: ") + M::kQNames[j] + " moves " +
                    tools::FormatNumber(std::abs(q_end(j) - q_begin(j)) / steps) +
                    " per step, more than the solver's limit of " +
                    tools::FormatNumber(max_step) + "; use more --steps or a shorter range");
    }
  }
  // --speed: the swept input (the first that moves; the first input when none does) at that
  // speed, the others with it along the line: qd = speed (q_end - q_begin) / its range.
  typename Types::VecQ qd = Types::VecQ::Zero();
  const bool at_speed = !std::isnan(args.speed);
  if (at_speed) {
    int swept = 0;
    for (int j = M::kNq - 1; j >= 0; --j)
      if (q_end(j) != q_begin(j)) swept = j;
    if (args.speed_rpm && !M::kQIsAngle[swept])
      return tools::UsageError(tool, std::string("--speed: rpm is for an angle input; the swept "
                                                 "input ") + M::kQNames[swept] +
                                         " is a slide (give its speed in model length/s)");
    const double range = q_end(swept) - q_begin(swept);
    if (range == 0) {
      qd(swept) = args.speed;
    } else {
      qd = (args.speed / range) * (q_end - q_begin);
      qd(swept) = args.speed;
    }
    if (!qd.allFinite() || !(qd.cwiseAbs().maxCoeff() <= tools::kMaxSpeed))
      return tools::UsageError(tool, "--speed: the other inputs would move faster than 1e5 per "
                                     "second along the range; give a smaller speed");
  }
  const typename Types::VecQ* velocities = at_speed ? &qd : nullptr;
  // What reads a velocity is taken at --speed; the design derivatives (EvalStaticsDesign) and
  // the force diagram's loads (EvalAppliedLoads) only at rest.
  const bool reads_speed = at_speed && statics::StaticsFeatures<M>::kReadsSpeed;
  if (reads_speed && args.design)
    return tools::UsageError(tool, "--design with --speed: the design derivatives are those of "
                                   "the statics at rest, and the model's loads read a velocity; "
                                   "leave out one of them");
  // A scan too coarse for its range (statics::ScanOptions::kMaxAngleStep) would report what
  // its few samples happen to show as converged: refused before anything is computed.
  statics::ScanOptions scan;
  scan.samples = samples;
  if (dead_zones || equilibria) {
    for (int j = 0; j < M::kNq; ++j) {
      const double angle = std::abs(q_end(j) - q_begin(j));
      if (!M::kQIsAngle[j] || scan.ResolvesAngle(angle)) continue;
      const double needed = std::ceil(angle / statics::ScanOptions::kMaxAngleStep);
      return tools::UsageError(
          tool, tools::BadValue("--samples", std::to_string(samples),
                                "at least " + tools::FormatNumber(needed) + " for the " +
                                    tools::FormatNumber(angle / kDegToRad) + " deg of " +
                                    M::kQNames[j] + " (at most 10 deg per sample)"));
    }
  }
  // The pictures asked for: gnuplot and the scripts found, and paths gnuplot's quoted
  // strings can carry, before anything is computed or written.
  fs::path gnuplot, scripts;
  if (!plots_prefix.empty()) {
    if (csv_path.empty()) csv_path = plots_prefix + ".csv";
    for (const std::string& path : {plots_prefix, csv_path}) {
      if (path.find_first_of("'\n") != std::string::npos)
        return tools::UsageError(tool, tools::BadValue("--plots", path,
                                                       "a path without ' or a line break"));
    }
    gnuplot = tools::FindOnPath("gnuplot");
    if (gnuplot.empty()) {
      std::cerr << "error: --plots: gnuplot not found on PATH (install gnuplot, or leave out "
                   "--plots)\n";
      return 1;
    }
    scripts = tools::FindPlotScripts({kPlotScripts[0], kPlotScripts[1]});
    if (scripts.empty()) {
      std::cerr << "error: --plots: " << tools::PlotScriptsNotFound({kPlotScripts[0], kPlotScripts[1]}) << "\n";
      return 1;
    }
  }
  if (design && !mechgen::HasStaticsDesign<M>::value)
    return tools::UsageError(tool, std::string("--design: the model ") + M::kName +
                                       " has no design section; add design: [parameter, ...] to it and "
                                       "generate it again");
  statics::Options options;
  options.max_condition = args.max_condition;
  options.design = design;
  std::string error;
  if (!options.IsValid(&error)) return tools::UsageError(tool, error);

#ifdef MECHGEN_TOOL_NO_CERES
  mechgen::position::PositionSolver<M> solver(mechgen::position::Options(), params);  // Eigen only
#else
  mechgen::position::CeresPositionSolver<M> solver(mechgen::position::Options(), params);
#endif
  mechgen::position::Summary assembly;
  if (solver.AssembleDefault(&assembly) != mechgen::position::Status::kConverged) {
    std::cerr << "error: cannot assemble " << M::kName << " at its assembly configuration: "
              << mechgen::position::FormatSummary(assembly) << "\n";
    return 3;
  }
  const auto assembled = solver.state();
  if constexpr (mechgen::ModelFeatures<M>::kLoopFree) {
    std::printf("mechgen statics of '%s': no closed loop (every coordinate is an input); ", M::kName);
  } else {
    std::printf("mechgen statics of '%s': assembled (branch %+d); ", M::kName, assembly.branch);
  }
  for (int j = 0; j < M::kNq; ++j) {
    std::printf("%s%s %s -> %s", j ? ", " : "", M::kQNames[j], Describe<M>(j, q_begin(j)).c_str(),
                Describe<M>(j, q_end(j)).c_str());
  }
  std::printf(" in %d steps; %d friction joint(s), %d reaction component(s)\n", steps,
              statics::StaticsFeatures<M>::kNumFriction,
              statics::StaticsFeatures<M>::kNumReactions);
  if (const std::string changed = tools::ChangedParameters(params); !changed.empty())
    std::printf("parameters set: %s\n", changed.c_str());
  // Every run says where the statics take what reads a velocity (at rest, or at --speed).
  const std::string speed_note = statics::SpeedNote<M>(velocities);
  if (!speed_note.empty()) std::printf("note: %s\n", speed_note.c_str());
  if (at_speed && (dead_zones || equilibria))
    std::printf("note: the dead-zone and equilibrium scans are at rest (qd = 0)\n");
  std::printf("\n");

  std::vector<statics::StaticsRecord<M>> records;
  const auto start = std::chrono::steady_clock::now();
  const int failures = statics::StaticsSweep(options, &solver, q_begin, q_end, steps, &records,
                                             mechgen::SweepOptions(), velocities);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (table_rows > 0) {
    statics::PrintStaticsTable(records, table_rows, std::cout);
    std::cout << "units: " << TableUnits(statics::StaticsColumns<M>()) << "\n\n";
  }
  const int rows = static_cast<int>(records.size());
  int singular = 0, evaluations = 0;
  for (const auto& r : records) {
    singular += r.status == statics::Status::kSingular;
    evaluations += r.evaluations;
  }
  std::printf("%d/%d rows converged, %d singular (forces withheld); %.1f statics evaluations "
              "per row; %.2f us/row (position, coefficients and statics)\n",
              rows - failures, rows, singular, double(evaluations) / std::max(rows, 1),
              1e6 * seconds / std::max(rows, 1));
  for (int j = 0; j < M::kNq; ++j) {
    double largest = 0, with_friction = 0;
    for (const auto& r : records) {
      if (r.drives[j].status != statics::Status::kConverged) continue;
      largest = std::max(largest, std::abs(r.drives[j].drive));
      with_friction = std::max({with_friction, std::abs(r.drives[j].drive_plus),
                                std::abs(r.drives[j].drive_minus)});
    }
    const char* unit = M::kQIsAngle[j] ? "N m" : "N";
    std::printf("  max |drive_%s| = %.6g %s", M::kQNames[j], largest, unit);
    if (statics::StaticsFeatures<M>::kHasFriction)
      std::printf(" without friction, %.6g %s with friction (running in +%s or -%s)",
                  with_friction, unit, M::kQNames[j], M::kQNames[j]);
    std::printf("\n");
  }
  if (failures > 0) {
    int shown = 0;
    for (const auto& r : records) {
      if (r.status == statics::Status::kConverged || shown++ >= 3) continue;
      std::printf("  %s = %s: %s (%s)\n", M::kQNames[0],
                  Describe<M>(0, r.kinematics.q(0)).c_str(), statics::RowStatus(r),
                  r.frictionless.summary.reason);
    }
  }

  if (dead_zones && !statics::StaticsFeatures<M>::kHasFriction) {
    std::printf("dead zones: none, the model has no friction (self-locking needs friction)\n");
  } else if (dead_zones) {
    for (int j = 0; j < M::kNq; ++j) {
      if (q_begin(j) == q_end(j)) continue;
      solver.AssembleDefault(nullptr);
      solver.MoveTo(assembled.q, nullptr);
      std::vector<statics::DeadZone> zones;
      statics::ScanSummary summary;
      statics::FindDeadZones(options, scan, &solver, j, q_begin(j), q_end(j), &zones, &summary);
      std::printf("dead zones of %s (self-locking: the load cannot drive it back): %zu (%s%s%s)\n",
                  M::kQNames[j], zones.size(), statics::ToString(summary.status),
                  summary.reason[0] ? ": " : "", summary.reason);
      std::printf("  scan step %s: a zone or gap narrower than one step may be missed\n",
                  Describe<M>(j, (q_end(j) - q_begin(j)) / samples).c_str());
      for (const statics::DeadZone& z : zones) {
        std::printf("  %s%s .. %s%s\n", Describe<M>(j, z.begin).c_str(),
                    z.begin_located ? "" : " (range end)", Describe<M>(j, z.end).c_str(),
                    z.end_located ? "" : " (range end)");
      }
    }
  }
  if (equilibria) {
    solver.AssembleDefault(nullptr);
    std::vector<statics::Equilibrium<M>> found;
    statics::ScanSummary summary;
    statics::FindEquilibria(options, scan, &solver, q_begin, q_end, &found, &summary);
    std::printf("equilibrium positions (Q = 0 along the line): %zu (%s%s%s)\n", found.size(),
                statics::ToString(summary.status), summary.reason[0] ? ": " : "", summary.reason);
    std::printf("  scan step");
    for (int j = 0; j < M::kNq; ++j)
      std::printf("%s %s", j ? "," : "", Describe<M>(j, (q_end(j) - q_begin(j)) / samples).c_str());
    std::printf(": two equilibria closer than one step may be missed\n");
    for (const statics::Equilibrium<M>& e : found) {
      std::printf("  ");
      for (int j = 0; j < M::kNq; ++j)
        std::printf("%s%s = %s", j ? ", " : "", M::kQNames[j], Describe<M>(j, e.q(j)).c_str());
      // Along the line of the inputs; for one input in N m/rad (an angle) or N/m (a slide).
      std::printf(": stiffness %.6g%s, %s\n", e.stiffness,
                  M::kNq == 1 ? (M::kQIsAngle[0] ? " N m/rad" : " N/m") : "",
                  std::isnan(e.stiffness) ? "stability unknown"
                                          : (e.stable ? "stable" : "unstable"));
    }
  }

  // Each output whole or absent (io/output_file.h: a temporary file renamed on success), both
  // closed, every write checked, before either is renamed into place; a failed write (a full
  // disk, /dev/full) exits 1 with one line.
  mechgen::OutputFile csv, svg;
  auto failed = [&error]() {
    std::cerr << "error: " << error << "\n";
    return 1;
  };
  if (!csv_path.empty()) {
    if (!csv.Open(csv_path, &error)) return failed();
    statics::WriteStaticsCsv(records, csv.stream(),
                             mechgen::Described(mechgen::CsvAbout(
                                 std::string(M::kName) + "_statics", M::kName,
                                 speed_note.empty() ? std::string("statics sweep")
                                                    : "statics sweep (" + speed_note + ")",
                                 statics::kStaticsSigns)),
                             design);
  }
  if (!svg_path.empty()) {
    if (!svg.Open(svg_path, &error)) return failed();
    mechgen::SvgOptions svg_options;
    svg_options.animate = args.animate;
    svg_options.snapshots = static_cast<int>(args.snapshots);
    svg_options.title = std::string("mechgen statics: ") + M::kName;
    if (reads_speed)
      svg_options.title += " at --speed (the reactions at that speed; the loads drawn at rest)";
    statics::WriteStaticsSvg(solver.params(), records, svg_options, svg.stream());
  }
  if ((!csv_path.empty() && !csv.Close(&error)) || (!svg_path.empty() && !svg.Close(&error)) ||
      (!csv_path.empty() && !csv.Commit(&error)) || (!svg_path.empty() && !svg.Commit(&error))) {
    return failed();
  }
  if (!csv_path.empty()) {
    std::printf("wrote %s (%d rows x %zu columns)\n", csv_path.c_str(), rows,
                statics::StaticsCsvColumns<M>(design).size());
  }
  if (!svg_path.empty()) std::printf("wrote %s\n", svg_path.c_str());
  if (!plots_prefix.empty()) {
    std::fflush(stdout);
    const std::string drive = plots_prefix + "_drive." + plot_format;
    if (!tools::RunGnuplot(gnuplot, scripts / kPlotScripts[0], csv_path, plot_format, drive, &error))
      return failed();
    std::printf("wrote %s (driving forces and reaction magnitudes against %s)\n", drive.c_str(),
                M::kQNames[0]);
    if (statics::GroundBearings<M>().empty()) {
      if constexpr (statics::StaticsFeatures<M>::kHasReactions &&
                    !statics::internal::HasJointLinks<M>::value)
        std::printf("no polar diagram: the model does not name its joints' links (add `scene` to "
                    "the outputs' quantities for the ground bearings' polar diagram)\n");
      else
        std::printf("no polar diagram: the model has no revolute joint with the ground whose "
                    "reaction it computes\n");
    } else {
      const std::string bearings = plots_prefix + "_bearings." + plot_format;
      if (!tools::RunGnuplot(gnuplot, scripts / kPlotScripts[1], csv_path, plot_format, bearings,
                      &error))
        return failed();
      std::printf("wrote %s (polar diagram of the ground bearings' loads: the force of the "
                  "ground on the moving link, fixed frame)\n",
                  bearings.c_str());
    }
  }
  if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout.flush()) {
    std::cerr << "error: cannot write the standard output\n";
    return 1;
  }
  return 0;
}

// The statics command for a model with statics, a stub for one without (a template, so
// that the branch not taken is not instantiated).
template <class M>
int Main(int argc, char** argv) {
  if constexpr (mechgen::statics::StaticsFeatures<M>::kHasStatics) {
    return Run<M>(argc, argv);
  } else {
    (void)argc;
    (void)argv;
    std::cerr << "error: the model '" << M::kName
              << "' was generated without statics; add `forces` to its outputs' quantities\n";
    return 2;
  }
}

}  // namespace

int main(int argc, char** argv) { return Main<MECHGEN_MODEL_NAMESPACE::Model>(argc, argv); }
