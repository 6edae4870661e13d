// The statics command's model-dependent part, RunStatics(model, arguments): one source for the
// per-model tool <model>_statics (statics_main.cc, M the generated model's type, fixed sizes)
// and for the runtime instantiated once for the model view (M = mechgen::ViewModel,
// core/view_runtime.h; the library mechgen_runtime_view, `mechgen_view statics`). It checks the
// options against the model, assembles, sweeps the statics (rows streamed to the CSV: one
// record held, plus the table's rows and, for the drawing, every row), prints the table, the
// counts, the dead zones and the equilibria, and writes the outputs whole or not at all. Exit
// statuses as statics_main.cc says.
//
// --params/--set read the view's parameter table (common/view_params.h); --svg draws from the
// model's description (statics/svg.h, io/svg.h); --design reads its Design and StaticsDesign
// (ModelCalls<M>: the generated EvalDesignDerivatives and EvalStaticsDesign).
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "common/gnuplot.h"
#include "common/inputs.h"
#include "common/numbers.h"
#include "common/params.h"
#include "common/view_params.h"
#include "statics_args.h"

#include "mechgen/core/model_calls.h"
#include "mechgen/io/output_file.h"
#include "mechgen/position/solver.h"
#include "mechgen/statics/columns.h"
#include "mechgen/statics/dead_zones.h"
#include "mechgen/statics/equilibrium.h"
#include "mechgen/statics/svg.h"
#include "mechgen/statics/sweep.h"

namespace mechgen::statics_tool {

namespace run_internal {

constexpr double kDegToRad = 0.017453292519943295;
namespace fs = std::filesystem;
namespace tools = mechgen::tools;

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
std::string Describe(const M& model, int j, double value) {
  char buffer[64];
  if (ModelCalls<M>::QIsAngle(model, j)) {
    std::snprintf(buffer, sizeof(buffer), "%.4f deg", value / kDegToRad);
  } else {
    std::snprintf(buffer, sizeof(buffer), "%.6g m", value);
  }
  return buffer;
}

}  // namespace run_internal

/**
 * \brief The statics command on `model` with the parsed `args` (statics_args.h).
 * \tparam M          A generated model with statics (the per-model tool) or mechgen::ViewModel.
 * \tparam Assembler  The solver's assembler (position/assembler.h): CeresAssembler in the
 *                    per-model tool, NewtonAssembler without Ceres and for the view.
 * \return The exit status (0, 1, kExitUsage, 3 the model does not assemble).
 */
template <class M, class Assembler = position::NewtonAssembler>
int RunStatics(const M& model, const Arguments& args) {
  using C = ModelCalls<M>;
  using Types = ModelTypes<M>;
  using Record = statics::StaticsRecord<M>;
  using namespace run_internal;
  const char* const name = C::Name(model);
  const int nq = C::Nq(model);
  const std::string& tool = args.tool;
  if constexpr (C::kView) {
    // A model without statics (the per-model tool has none to be run on).
    if (!C::HasStatics(model)) {
      std::cerr << "error: the model '" << name
                << "' was generated without statics; add `forces` to its outputs' quantities\n";
      return kExitUsage;
    }
  }
  const int steps = static_cast<int>(args.steps), samples = static_cast<int>(args.samples);
  const int table_rows = static_cast<int>(args.table);
  const bool dead_zones = args.dead_zones, equilibria = args.equilibria, design = args.design;
  std::string csv_path = args.csv_path;
  const std::string& svg_path = args.svg_path;
  const std::string& plots_prefix = args.plots_prefix;
  const std::string& plot_format = args.plot_format;
  const std::vector<std::string>& ranges = args.ranges;
  typename Types::Params params = C::DefaultParams(model);
  if (std::string why; !tools::ApplyModelParameters(args.params, model, &params, &why))
    return tools::UsageError(tool, why);

  typename Types::VecQ q_begin = Eigen::Map<const typename Types::VecQ>(C::QMin(model), nq);
  typename Types::VecQ q_end = Eigen::Map<const typename Types::VecQ>(C::QMax(model), nq);
  for (const std::string& text : ranges) {
    int j = 0;
    double min = 0, max = 0;
    std::string error;
    if (!tools::ParseRange(model, text, &j, &min, &max, &error)) return tools::UsageError(tool, error);
    q_begin(j) = min;
    q_end(j) = max;
  }
  // A step longer than the position solver accepts would make every row invalid_input: a
  // units mistake, refused here as by the sweep (position::CheckInputSteps).
  if (const auto check = position::CheckInputSteps(q_begin, q_end, nq, steps); !check.ok())
    return tools::UsageError(tool, tools::RangeStepError(model, check));
  // --speed: the swept input (the first that moves; the first input when none does) at that
  // speed, the others with it along the line: qd = speed (q_end - q_begin) / its range.
  typename Types::VecQ qd = statics::internal::Zeros<typename Types::VecQ>(nq);
  const bool at_speed = !std::isnan(args.speed);
  if (at_speed) {
    int swept = 0;
    for (int j = nq - 1; j >= 0; --j)
      if (q_end(j) != q_begin(j)) swept = j;
    if (args.speed_rpm && !C::QIsAngle(model, swept))
      return tools::UsageError(tool, std::string("--speed: rpm is for an angle input; the swept "
                                                 "input ") + C::QName(model, swept) +
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
  const bool reads_speed = at_speed && statics::StaticsFeatures<M>::kReadsSpeed && C::ReadsSpeed(model);
  if (reads_speed && args.design)
    return tools::UsageError(tool, "--design with --speed: the design derivatives are those of "
                                   "the statics at rest, and the model's loads read a velocity; "
                                   "leave out one of them");
  // A scan too coarse for its range (statics::ScanOptions::kMaxAngleStep) would report what
  // its few samples happen to show as converged: refused before anything is computed.
  statics::ScanOptions scan;
  scan.samples = samples;
  if (dead_zones || equilibria) {
    for (int j = 0; j < nq; ++j) {
      const double angle = std::abs(q_end(j) - q_begin(j));
      if (!C::QIsAngle(model, j) || scan.ResolvesAngle(angle)) continue;
      const double needed = std::ceil(angle / statics::ScanOptions::kMaxAngleStep);
      return tools::UsageError(
          tool, tools::BadValue("--samples", std::to_string(samples),
                                "at least " + tools::FormatNumber(needed) + " for the " +
                                    tools::FormatNumber(angle / kDegToRad) + " deg of " +
                                    C::QName(model, j) + " (at most 10 deg per sample)"));
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
  if (design && !(statics::StaticsFeatures<M>::kHasDesign && C::HasStaticsDesign(model)))
    return tools::UsageError(tool, std::string("--design: the model ") + name +
                                       " has no design section; add design: [parameter, ...] to it and "
                                       "generate it again");
  statics::Options options;
  options.max_condition = args.max_condition;
  options.design = design;
  std::string error;
  if (!options.IsValid(&error)) return tools::UsageError(tool, error);

  mechgen::position::PositionSolver<M, Assembler> solver(model, mechgen::position::Options(), params);
  mechgen::position::Summary assembly;
  if (solver.AssembleDefault(&assembly) != mechgen::position::Status::kConverged) {
    std::cerr << "error: cannot assemble " << name << " at its assembly configuration: "
              << mechgen::position::FormatSummary(assembly) << "\n";
    return 3;
  }
  const auto assembled = solver.state();
  if (C::LoopFree(model)) {
    std::printf("mechgen statics of '%s': no closed loop (every coordinate is an input); ", name);
  } else {
    std::printf("mechgen statics of '%s': assembled (branch %+d); ", name, assembly.branch);
  }
  for (int j = 0; j < nq; ++j) {
    std::printf("%s%s %s -> %s", j ? ", " : "", C::QName(model, j), Describe(model, j, q_begin(j)).c_str(),
                Describe(model, j, q_end(j)).c_str());
  }
  std::printf(" in %d steps; %d friction joint(s), %d reaction component(s)\n", steps,
              C::NumFriction(model), C::NumReactions(model));
  if (const std::string changed = tools::ChangedModelParameters(model, params); !changed.empty())
    std::printf("parameters set: %s\n", changed.c_str());
  // Every run says where the statics take what reads a velocity (at rest, or at --speed).
  const std::string speed_note = statics::SpeedNote<M>(model, velocities);
  if (!speed_note.empty()) std::printf("note: %s\n", speed_note.c_str());
  if (at_speed && (dead_zones || equilibria))
    std::printf("note: the dead-zone and equilibrium scans are at rest (qd = 0)\n");
  std::printf("\n");

  // Each output whole or absent (io/output_file.h: a temporary file renamed on success), both
  // closed, every write checked, before either is renamed into place; a failed write (a full
  // disk, /dev/full) exits 1 with one line. The CSV is opened before the sweep: its rows are
  // streamed.
  mechgen::OutputFile csv, svg;
  auto failed = [&error]() {
    std::cerr << "error: " << error << "\n";
    return 1;
  };
  const std::vector<statics::StaticsColumn<M>> csv_columns = statics::StaticsColumns<M>(model, design);
  if (!csv_path.empty()) {
    if (!csv.Open(csv_path, &error)) return failed();
    mechgen::WriteCsvHeader(csv_columns, csv.stream(),
                            mechgen::Described(mechgen::CsvAbout(
                                std::string(name) + "_statics", name,
                                speed_note.empty() ? std::string("statics sweep")
                                                   : "statics sweep (" + speed_note + ")",
                                statics::kStaticsSigns)));
  }

  // The sweep, streamed: each row goes to the CSV as it is evaluated; kept are the table's
  // rows, the drawing's (every row) and the first failures, and the counts.
  const size_t rows = static_cast<size_t>(std::max(steps, 1)) + 1;
  const std::vector<size_t> table_indices = mechgen::TableRowIndices(rows, table_rows);
  std::vector<Record> table_records, svg_records, failed_rows;
  size_t next_table = 0;
  int singular = 0, evaluations = 0;
  std::array<double, statics::StaticsTypes<M>::kMaxQ> largest{}, with_friction{};
  // Timing: the sweep's time without this tool's handling of each row (CSV formatting, keeping
  // the table's and drawing's rows), which the figure printed leaves out.
  double output_seconds = 0;
  auto row = [&](int i, const Record& r) {
    const auto t0 = std::chrono::steady_clock::now();
    const size_t index = static_cast<size_t>(i);
    if (!csv_path.empty()) mechgen::WriteCsvRow(csv_columns, r, csv.stream());
    if (next_table < table_indices.size() && table_indices[next_table] == index) {
      table_records.push_back(r);
      ++next_table;
    }
    if (!svg_path.empty()) svg_records.push_back(r);
    singular += r.status == statics::Status::kSingular;
    evaluations += r.evaluations;
    if (r.status != statics::Status::kConverged && failed_rows.size() < 3) failed_rows.push_back(r);
    for (int j = 0; j < nq; ++j) {
      if (r.drives[j].status != statics::Status::kConverged) continue;
      largest[j] = std::max(largest[j], std::abs(r.drives[j].drive));
      with_friction[j] = std::max({with_friction[j], std::abs(r.drives[j].drive_plus),
                                   std::abs(r.drives[j].drive_minus)});
    }
    output_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  const auto start = std::chrono::steady_clock::now();
  int failures = 0;
  if constexpr (C::kView) {
    // The instantiation in mechgen_runtime_view (core/view_runtime.h: ViewStaticsRowFn).
    statics::StaticsRowFn<M> row_fn = row;
    failures = statics::StaticsSweepRows(options, &solver, q_begin, q_end, steps, mechgen::SweepOptions(),
                                         velocities, row_fn);
  } else {
    failures = statics::StaticsSweepRows(options, &solver, q_begin, q_end, steps, mechgen::SweepOptions(),
                                         velocities, row);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - output_seconds;
  if (table_rows > 0) {
    const std::vector<statics::StaticsColumn<M>> columns = statics::StaticsColumns<M>(model);
    mechgen::PrintTableRows(columns, table_records, std::cout);
    std::cout << "units: " << TableUnits(columns) << "\n\n";
  }
  const int row_count = static_cast<int>(rows);
  std::printf("%d/%d rows converged, %d singular (forces withheld); %.1f statics evaluations "
              "per row; %.2f us/row (position, coefficients and statics)\n",
              row_count - failures, row_count, singular, double(evaluations) / std::max(row_count, 1),
              1e6 * seconds / std::max(row_count, 1));
  const bool friction = statics::StaticsFeatures<M>::kHasFriction && C::HasFriction(model);
  for (int j = 0; j < nq; ++j) {
    const char* unit = C::QIsAngle(model, j) ? "N m" : "N";
    std::printf("  max |drive_%s| = %.6g %s", C::QName(model, j), largest[j], unit);
    if (friction)
      std::printf(" without friction, %.6g %s with friction (running in +%s or -%s)",
                  with_friction[j], unit, C::QName(model, j), C::QName(model, j));
    std::printf("\n");
  }
  if (failures > 0) {
    for (const Record& r : failed_rows) {
      std::printf("  %s = %s: %s (%s)\n", C::QName(model, 0),
                  Describe(model, 0, r.kinematics.q(0)).c_str(), statics::RowStatus(r),
                  r.frictionless.summary.reason);
    }
  }

  if (dead_zones && !friction) {
    std::printf("dead zones: none, the model has no friction (self-locking needs friction)\n");
  } else if (dead_zones) {
    for (int j = 0; j < nq; ++j) {
      if (q_begin(j) == q_end(j)) continue;
      solver.AssembleDefault(nullptr);
      solver.MoveTo(assembled.q, nullptr);
      std::vector<statics::DeadZone> zones;
      statics::ScanSummary summary;
      statics::FindDeadZones(options, scan, &solver, j, q_begin(j), q_end(j), &zones, &summary);
      std::printf("dead zones of %s (self-locking: the load cannot drive it back): %zu (%s%s%s)\n",
                  C::QName(model, j), zones.size(), statics::ToString(summary.status),
                  summary.reason[0] ? ": " : "", summary.reason);
      std::printf("  scan step %s: a zone or gap narrower than one step may be missed\n",
                  Describe(model, j, (q_end(j) - q_begin(j)) / samples).c_str());
      for (const statics::DeadZone& z : zones) {
        std::printf("  %s%s .. %s%s\n", Describe(model, j, z.begin).c_str(),
                    z.begin_located ? "" : " (range end)", Describe(model, j, z.end).c_str(),
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
    for (int j = 0; j < nq; ++j)
      std::printf("%s %s", j ? "," : "", Describe(model, j, (q_end(j) - q_begin(j)) / samples).c_str());
    std::printf(": two equilibria closer than one step may be missed\n");
    for (const statics::Equilibrium<M>& e : found) {
      std::printf("  ");
      for (int j = 0; j < nq; ++j)
        std::printf("%s%s = %s", j ? ", " : "", C::QName(model, j), Describe(model, j, e.q(j)).c_str());
      // Along the line of the inputs; for one input in N m/rad (an angle) or N/m (a slide).
      std::printf(": stiffness %.6g%s, %s\n", e.stiffness,
                  nq == 1 ? (C::QIsAngle(model, 0) ? " N m/rad" : " N/m") : "",
                  std::isnan(e.stiffness) ? "stability unknown"
                                          : (e.stable ? "stable" : "unstable"));
    }
  }

  if (!svg_path.empty()) {
    if (!svg.Open(svg_path, &error)) return failed();
    mechgen::SvgOptions svg_options;
    svg_options.animate = args.animate;
    svg_options.snapshots = static_cast<int>(args.snapshots);
    svg_options.title = std::string("mechgen statics: ") + name;
    if (reads_speed)
      svg_options.title += " at --speed (the reactions at that speed; the loads drawn at rest)";
    statics::WriteStaticsSvg(model, solver.params(), svg_records, svg_options, svg.stream());
  }
  if ((!csv_path.empty() && !csv.Close(&error)) || (!svg_path.empty() && !svg.Close(&error)) ||
      (!csv_path.empty() && !csv.Commit(&error)) || (!svg_path.empty() && !svg.Commit(&error))) {
    return failed();
  }
  if (!csv_path.empty()) {
    std::printf("wrote %s (%d rows x %zu columns)\n", csv_path.c_str(), row_count, csv_columns.size());
  }
  if (!svg_path.empty()) std::printf("wrote %s\n", svg_path.c_str());
  if (!plots_prefix.empty()) {
    std::fflush(stdout);
    const std::string drive = plots_prefix + "_drive." + plot_format;
    if (!tools::RunGnuplot(gnuplot, scripts / kPlotScripts[0], csv_path, plot_format, drive, &error))
      return failed();
    std::printf("wrote %s (driving forces and reaction magnitudes against %s)\n", drive.c_str(),
                C::QName(model, 0));
    if (statics::GroundBearings<M>(model).empty()) {
      if (statics::StaticsFeatures<M>::kHasReactions && C::HasReactions(model) &&
          !(statics::internal::HasJointLinks<M>::value && C::HasJointLinks(model)))
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

}  // namespace mechgen::statics_tool
