/**
 * \file analysis/statics.h
 * The statics sweep as an analysis (issue 43: one analysis layer for every tool): Check(model,
 * request) says what is wrong with a StaticsRequest (analysis/statics_request.h) on this model;
 * Run(model, request, outputs, facts) assembles, sweeps the statics (the rows of the statics
 * column table, statics/columns.h, streamed to the CSV: one record held, plus the table's rows
 * and, for the drawing, every row), prints the table, the counts, the dead zones and the
 * equilibria, draws the force diagram and writes the outputs whole or not at all. Exit
 * statuses: 0 done, 1 an output cannot be written, 2 a usage error (Check's text as
 * "<tool>: error: ..."; a view without statics: one line "error: ..."), 3 the model does not
 * assemble. One source for the fixed-size path (the per-model tool <model>_statics,
 * tools/statics_main.cc) and for the model view (M = ViewModel: runtime/view/analysis.cc,
 * declared in analysis/view_analysis.h; mechgen_view statics).
 *
 * --params/--set read the model's parameter table (analysis/view_params.h); --svg draws from
 * the model's description (statics/svg.h, io/svg.h); --design reads its Design and
 * StaticsDesign (ModelCalls<M>: the generated EvalDesignDerivatives and EvalStaticsDesign).
 */
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <string>
#include <type_traits>
#include <vector>

#include "mechgen/analysis/inputs.h"
#include "mechgen/analysis/numbers.h"
#include "mechgen/analysis/params.h"
#include "mechgen/analysis/statics_request.h"
#include "mechgen/analysis/view_params.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/io/format.h"
#include "mechgen/io/output_file.h"
#include "mechgen/position/solver.h"
#include "mechgen/statics/columns.h"
#include "mechgen/statics/dead_zones.h"
#include "mechgen/statics/equilibrium.h"
#include "mechgen/statics/svg.h"
#include "mechgen/statics/sweep.h"

namespace mechgen::analysis {

static_assert(kStaticsMinSamples == statics::ScanOptions::kMinSamples);
static_assert(kStaticsDefaultMaxCondition == mechgen::kMaxCondition);

namespace statics_internal {

namespace tools = mechgen::tools;

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
    std::snprintf(buffer, sizeof(buffer), "%.4f deg", internal::ToDegrees(value));
  } else {
    std::snprintf(buffer, sizeof(buffer), "%.6g m", value);
  }
  return buffer;
}

/// A StaticsRequest read against the model.
template <class M>
struct Inputs {
  using Types = ModelTypes<M>;
  typename Types::Params params;
  typename Types::VecQ q_begin, q_end, qd;
  bool at_speed = false;     ///< --speed given
  bool reads_speed = false;  ///< and the model's loads read a velocity
  statics::ScanOptions scan;
  statics::Options options;
};

/// Reads the request against the model into *in; the usage error's text, empty when it fits.
template <class M>
std::string Resolve(const M& model, const StaticsRequest& request, Inputs<M>* in) {
  using C = ModelCalls<M>;
  using Types = ModelTypes<M>;
  const char* const name = C::Name(model);
  const int nq = C::Nq(model);
  const int steps = static_cast<int>(request.steps), samples = static_cast<int>(request.samples);
  std::string error;
  in->params = C::DefaultParams(model);
  if (!tools::ApplyModelParameters(request.params, model, &in->params, &error)) return error;

  typename Types::VecQ& q_begin = in->q_begin;
  typename Types::VecQ& q_end = in->q_end;
  q_begin = Eigen::Map<const typename Types::VecQ>(C::QMin(model), nq);
  q_end = Eigen::Map<const typename Types::VecQ>(C::QMax(model), nq);
  for (const std::string& text : request.ranges) {
    int j = 0;
    double min = 0, max = 0;
    if (!tools::ParseRange(model, text, &j, &min, &max, &error)) return error;
    q_begin(j) = min;
    q_end(j) = max;
  }
  // A step longer than the position solver accepts would make every row invalid_input: a
  // units mistake, refused here as by the sweep (position::CheckInputSteps).
  if (const auto check = position::CheckInputSteps(q_begin, q_end, nq, steps); !check.ok())
    return tools::RangeStepError(model, check);
  // --speed: the swept input (the first that moves; the first input when none does) at that
  // speed, the others with it along the line: qd = speed (q_end - q_begin) / its range.
  typename Types::VecQ& qd = in->qd;
  qd = statics::internal::Zeros<typename Types::VecQ>(nq);
  in->at_speed = !std::isnan(request.speed);
  if (in->at_speed) {
    int swept = 0;
    for (int j = nq - 1; j >= 0; --j)
      if (q_end(j) != q_begin(j)) swept = j;
    if (request.speed_rpm && !C::QIsAngle(model, swept))
      return std::string("--speed: rpm is for an angle input; the swept input ") + C::QName(model, swept) +
             " is a slide (give its speed in model length/s)";
    const double range = q_end(swept) - q_begin(swept);
    if (range == 0) {
      qd(swept) = request.speed;
    } else {
      qd = (request.speed / range) * (q_end - q_begin);
      qd(swept) = request.speed;
    }
    if (!qd.allFinite() || !(qd.cwiseAbs().maxCoeff() <= tools::kMaxSpeed))
      return "--speed: the other inputs would move faster than 1e5 per second along the range; give a "
             "smaller speed";
  }
  // What reads a velocity is taken at --speed; the design derivatives (EvalStaticsDesign) and
  // the force diagram's loads (EvalAppliedLoads) only at rest.
  in->reads_speed = in->at_speed && statics::StaticsFeatures<M>::kReadsSpeed && C::ReadsSpeed(model);
  if (in->reads_speed && request.design)
    return "--design with --speed: the design derivatives are those of the statics at rest, and the "
           "model's loads read a velocity; leave out one of them";
  // A scan too coarse for its range (statics::ScanOptions::kMaxAngleStep) would report what
  // its few samples happen to show as converged: refused before anything is computed.
  in->scan.samples = samples;
  if (request.dead_zones || request.equilibria) {
    for (int j = 0; j < nq; ++j) {
      const double angle = std::abs(q_end(j) - q_begin(j));
      if (!C::QIsAngle(model, j) || in->scan.ResolvesAngle(angle)) continue;
      const double needed = std::ceil(angle / statics::ScanOptions::kMaxAngleStep);
      return tools::BadValue("--samples", std::to_string(samples),
                             "at least " + tools::FormatNumber(needed) + " for the " +
                                 tools::FormatNumber(internal::ToDegrees(angle)) + " deg of " +
                                 C::QName(model, j) + " (at most 10 deg per sample)");
    }
  }
  if (request.design && !(statics::StaticsFeatures<M>::kHasDesign && C::HasStaticsDesign(model)))
    return std::string("--design: the model ") + name +
           " has no design section; add design: [parameter, ...] to it and generate it again";
  in->options.max_condition = request.max_condition;
  in->options.design = request.design;
  if (!in->options.IsValid(&error)) return error;
  return "";
}

}  // namespace statics_internal

/// What is wrong with `request` on `model` (the usage error's text, one line), empty when
/// Run can go on: the parameters, the ranges' inputs and steps, --speed (rpm on a slide, the
/// other inputs too fast, with --design on loads that read a velocity), the scans' samples
/// along an angle, --design without a design section, the statics options.
template <class M>
std::string Check(const M& model, const StaticsRequest& request) {
  statics_internal::Inputs<M> in;
  return statics_internal::Resolve(model, request, &in);
}

/// The statics of a view whose shape the runtime has an instantiation sized to
/// (core/view_sized.h: SizedViewModel), run there, its exit status in *status; false (nothing
/// done) for any other view, or one whose `sized` is false. In mechgen_runtime_view
/// (runtime/view/analysis_sized.cc).
bool RunSized(const ViewModel& model, const StaticsRequest& request, const StaticsOutputs& outputs,
              const std::function<int()>& prepare, StaticsPlotFacts* facts, int* status);

/**
 * \brief The statics sweep of `model` asked for by `request`, written to `outputs`.
 * \tparam M          A generated model with statics (the per-model tool) or mechgen::ViewModel.
 * \tparam Assembler  The solver's assembler (position/assembler.h): CeresAssembler in the
 *                    per-model tool, NewtonAssembler without Ceres and for the view.
 * \param prepare  Called once the request is checked, before anything is computed or written
 *                 (the command's --plots: gnuplot and its scripts found); -1 to go on, else
 *                 the exit status to end with.
 * \param facts    Filled with what the command's pictures need of the model (may be null).
 * \return The exit status (0, 1, 2, 3 the model does not assemble; see the file comment).
 */
template <class M, class Assembler = position::NewtonAssembler>
int Run(const M& model, const StaticsRequest& request, const StaticsOutputs& outputs,
        const std::function<int()>& prepare = nullptr, StaticsPlotFacts* facts = nullptr) {
  if constexpr (std::is_same_v<M, ViewModel>) {
    if (int status = 0; RunSized(model, request, outputs, prepare, facts, &status)) return status;
  }
  using C = ModelCalls<M>;
  using Types = ModelTypes<M>;
  using Record = statics::StaticsRecord<M>;
  namespace tools = mechgen::tools;
  const char* const name = C::Name(model);
  const int nq = C::Nq(model);
  if constexpr (C::kView) {
    // A model without statics (the per-model tool has none to be run on).
    if (!C::HasStatics(model)) {
      std::cerr << "error: the model '" << name
                << "' was generated without statics; add `forces` to its outputs' quantities\n";
      return tools::kExitUsage;
    }
  }
  statics_internal::Inputs<M> in;
  if (const std::string why = statics_internal::Resolve(model, request, &in); !why.empty())
    return tools::UsageError(outputs.tool, why);
  if (prepare) {
    if (const int status = prepare(); status >= 0) return status;
  }
  if (facts != nullptr) {
    facts->first_input = C::QName(model, 0);
    facts->bearings = !statics::GroundBearings<M>(model).empty();
    if (facts->bearings) {
      facts->no_bearings.clear();
    } else if (statics::StaticsFeatures<M>::kHasReactions && C::HasReactions(model) &&
               !(statics::internal::HasJointLinks<M>::value && C::HasJointLinks(model))) {
      facts->no_bearings = "no polar diagram: the model does not name its joints' links (add `scene` to "
                           "the outputs' quantities for the ground bearings' polar diagram)";
    } else {
      facts->no_bearings = "no polar diagram: the model has no revolute joint with the ground whose "
                           "reaction it computes";
    }
  }
  const int steps = static_cast<int>(request.steps), samples = static_cast<int>(request.samples);
  const int table_rows = static_cast<int>(request.table);
  const bool dead_zones = request.dead_zones, equilibria = request.equilibria, design = request.design;
  const std::string& csv_path = outputs.csv_path;
  const std::string& svg_path = outputs.svg_path;
  const typename Types::Params& params = in.params;
  const typename Types::VecQ& q_begin = in.q_begin;
  const typename Types::VecQ& q_end = in.q_end;
  const bool at_speed = in.at_speed, reads_speed = in.reads_speed;
  const typename Types::VecQ* velocities = at_speed ? &in.qd : nullptr;
  const statics::ScanOptions& scan = in.scan;
  const statics::Options& options = in.options;
  std::string error;

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
    std::printf("%s%s %s -> %s", j ? ", " : "", C::QName(model, j), statics_internal::Describe(model, j, q_begin(j)).c_str(),
                statics_internal::Describe(model, j, q_end(j)).c_str());
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
    std::cout << "units: " << statics_internal::TableUnits(columns) << "\n\n";
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
                  statics_internal::Describe(model, 0, r.kinematics.q(0)).c_str(), statics::RowStatus(r),
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
                  statics_internal::Describe(model, j, (q_end(j) - q_begin(j)) / samples).c_str());
      for (const statics::DeadZone& z : zones) {
        std::printf("  %s%s .. %s%s\n", statics_internal::Describe(model, j, z.begin).c_str(),
                    z.begin_located ? "" : " (range end)", statics_internal::Describe(model, j, z.end).c_str(),
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
      std::printf("%s %s", j ? "," : "", statics_internal::Describe(model, j, (q_end(j) - q_begin(j)) / samples).c_str());
    std::printf(": two equilibria closer than one step may be missed\n");
    for (const statics::Equilibrium<M>& e : found) {
      std::printf("  ");
      for (int j = 0; j < nq; ++j)
        std::printf("%s%s = %s", j ? ", " : "", C::QName(model, j), statics_internal::Describe(model, j, e.q(j)).c_str());
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
    svg_options.animate = outputs.animate;
    svg_options.snapshots = static_cast<int>(outputs.snapshots);
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
  if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout.flush()) {
    std::cerr << "error: cannot write the standard output\n";
    return 1;
  }
  return 0;
}

/// The statics of a generated model that may have been generated without them (no `forces`
/// among its outputs' quantities: the per-model tool <model>_statics is then a stub): Run, or
/// one line "error: ..." and exit status 2 (a template, so that Run is not instantiated for a
/// model without statics).
template <class M, class Assembler = position::NewtonAssembler>
int RunIfStatics(const M& model, const StaticsRequest& request, const StaticsOutputs& outputs,
                 const std::function<int()>& prepare = nullptr, StaticsPlotFacts* facts = nullptr) {
  if constexpr (statics::StaticsFeatures<M>::kHasStatics) {
    return Run<M, Assembler>(model, request, outputs, prepare, facts);
  } else {
    (void)model, (void)request, (void)outputs, (void)prepare, (void)facts;
    std::cerr << "error: the model '" << ModelCalls<M>::Name(model)
              << "' was generated without statics; add `forces` to its outputs' quantities\n";
    return mechgen::tools::kExitUsage;
  }
}

}  // namespace mechgen::analysis
