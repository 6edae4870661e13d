// The sweep command's model-dependent part, RunSweep(model, arguments): one source for the
// per-model tool <model>_sweep (sweep_main.cc, M the generated model's type, fixed sizes) and
// for the runtime instantiated once for the model view (M = mechgen::ViewModel,
// core/view_runtime.h; the library mechgen_runtime_view, mechgen_view sweep). It checks the
// options against the model, assembles, sweeps (rows streamed to the CSV), prints the table,
// the motion summary and the counts, and writes the outputs whole or not at all. Exit
// statuses as sweep_main.cc says.
//
// --params/--set read the view's parameter table through the view (common/view_params.h), with
// the per-model tool's messages; --svg draws from the view's drawing description (io/svg.h),
// --mode reads its named assembly modes, --design its Design (the design derivatives: the
// generated EvalDesignDerivatives through ModelCalls<M>::Design, position/design.h).
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

#include "common/inputs.h"
#include "common/numbers.h"
#include "common/view_params.h"
#include "sweep_args.h"

#include "mechgen/core/model_calls.h"
#include "mechgen/io/output_file.h"
#include "mechgen/io/svg.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/columns.h"
#include "mechgen/sweep/motion_summary.h"
#include "mechgen/sweep/sweep.h"

namespace mechgen::sweep_tool {

// Exit statuses (models/README.md, "Exit statuses of the sweep"):
constexpr int kExitConverged = 0;    // every row converged; the outputs written
constexpr int kExitError = 1;        // model or output error: nothing written
constexpr int kExitRowsFailed = 3;   // the outputs written, but some rows did not converge
// kExitUsage = 2 (sweep_args.h): bad arguments, nothing written (one line on stderr,
// common/numbers.h).

// The bound on --steps is kMaxSteps (sweep_args.h: `mechgen sweep` checks it before any
// compile): 10^7 steps make a CSV of a few GB; the sweep itself streams (holds one row, plus the
// table's rows and at most kMaxSvgRows for the drawing).
constexpr size_t kMaxSvgRows = 3601;

namespace run_internal {

constexpr double kDegToRad = 0.017453292519943295;
using mechgen::tools::Quote;

// "1.5" -> 1.5 (model units, radians for angles); "90deg" -> pi/2. False if malformed.
inline bool ParseValue(const std::string& text, double* value) {
  return mechgen::tools::ParseNumber(text, value, /*allow_degrees=*/true);
}

// An input's value for the messages: "%g", in degrees for an angle; never "-0".
template <class M>
std::string Describe(const M& model, int j, double value) {
  if (ModelCalls<M>::QIsAngle(model, j)) return mechgen::internal::FormatNumber(value / kDegToRad, "%g") + " deg";
  return mechgen::internal::FormatNumber(value, "%g");
}

// The blocks' modes of the named assembly mode; false with the message when there is none.
template <class M, class Modes>
bool NamedModes(const M& model, const std::string& name, Modes* modes, std::string* error) {
  using C = ModelCalls<M>;
  const int n = C::NumNamedModes(model);
  std::string names;
  for (int i = 0; i < n; ++i) {
    if (name == C::ModeName(model, i)) {
      C::NamedModes(model, i, modes);
      return true;
    }
    names += std::string(i ? ", " : "") + C::ModeName(model, i);
  }
  if (n > 0) {
    *error = "--mode: the model " + std::string(C::Name(model)) + " has no assembly mode '" + name +
             "' (its modes: " + names + ")";
  } else {
    *error = "--mode: the model " + std::string(C::Name(model)) +
             " names no assembly modes (add assembly_modes: to the model; models/README.md)";
  }
  return false;
}

}  // namespace run_internal

/**
 * \brief The sweep command on `model` with the parsed `arguments` (sweep_args.h).
 * \tparam M          A generated model (the per-model tool) or mechgen::ViewModel.
 * \tparam Assembler  The solver's assembler (position/assembler.h): CeresAssembler in the
 *                    per-model tool, NewtonAssembler without Ceres and for the view.
 * \param assembler_name  Its name in the summary line ("Ceres", "Levenberg-Marquardt").
 * \return The exit status (kExitConverged, kExitRowsFailed, kExitError, kExitUsage).
 */
template <class M, class Assembler = position::NewtonAssembler>
int RunSweep(const M& model, const Arguments& arguments, const char* assembler_name = "Levenberg-Marquardt") {
  using C = ModelCalls<M>;
  using Types = ModelTypes<M>;
  using Record = SweepRecord<M>;
  using namespace run_internal;
  const char* const name = C::Name(model);
  const int nq = C::Nq(model);
  auto Usage = [&arguments](const std::string& message) {
    return mechgen::tools::UsageError(arguments.tool, message);
  };
  const std::vector<std::string>& ranges = arguments.ranges;
  const std::vector<std::string>& qd_text = arguments.qd_text;
  const std::vector<std::string>& qdd_text = arguments.qdd_text;
  const std::string& csv_path = arguments.csv_path;
  const std::string& svg_path = arguments.svg_path;
  const bool no_animation = arguments.no_animation;
  std::string error;
  // Counts checked by the parser: --steps in 1..kMaxSteps, --table in 0..kMaxSteps + 1.
  const int steps = static_cast<int>(arguments.steps);
  const int table_rows = static_cast<int>(arguments.table);
  typename position::PositionSolver<M, Assembler>::Modes named_modes = C::DefaultModes(model);
  if (!arguments.mode.empty() && !NamedModes(model, arguments.mode, &named_modes, &error)) return Usage(error);

  // Path of the sweep and the input motion.
  typename Types::VecQ q_begin = Eigen::Map<const typename Types::VecQ>(C::QMin(model), nq);
  typename Types::VecQ q_end = Eigen::Map<const typename Types::VecQ>(C::QMax(model), nq);
  for (const std::string& text : ranges) {
    int j = 0;
    double min = 0, max = 0;
    if (!mechgen::tools::ParseRange(model, text, &j, &min, &max, &error)) return Usage(error);
    q_begin(j) = min;
    q_end(j) = max;
  }
  // One step longer than the solver accepts would make every row invalid_input: a units
  // mistake, refused here (position::CheckInputSteps).
  if (const auto check = position::CheckInputSteps(q_begin, q_end, nq, steps); !check.ok())
    return Usage(mechgen::tools::RangeStepError(model, check));
  auto parse_vector = [&model, nq](const std::vector<std::string>& text, double fallback, double bound,
                                   const char* option, typename Types::VecQ* out, std::string* error) {
    (void)model;
    out->setConstant(nq, fallback);
    if (text.empty()) return true;
    if (text.size() != 1 && text.size() != static_cast<size_t>(nq)) {
      *error = std::string(option) + (nq == 1 ? ": takes one value"
                                              : ": takes 1 or " + std::to_string(nq) + " values (one per input)");
      return false;
    }
    for (int j = 0; j < nq; ++j) {
      const std::string& item = text[text.size() == 1 ? 0 : static_cast<size_t>(j)];
      if (!ParseValue(item, &(*out)(j)) || !(std::abs((*out)(j)) <= bound)) {
        *error = mechgen::tools::BadValue(
            option, item,
            mechgen::tools::Magnitude(bound).Describe() + " (append 'deg' for degrees)");
        return false;
      }
    }
    return true;
  };
  typename Types::VecQ qd, qdd;
  if (!parse_vector(qd_text, 1.0, mechgen::tools::kMaxSpeed, "--qd", &qd, &error) ||
      !parse_vector(qdd_text, 0.0, mechgen::tools::kMaxAcceleration, "--qdd", &qdd, &error)) {
    return Usage(error);
  }

  // The CSV's columns must be unique (the generator ensures it; checked again here).
  std::vector<mechgen::SweepColumn<M>> columns = mechgen::SweepColumns<M>(model);
  if (arguments.design) {
    if (!C::HasDesign(model))
      return Usage(std::string("--design: the model ") + name +
                   " has no design section; add design: [parameter, ...] to it and generate it again");
    mechgen::AppendDesignColumns<M>(model, &columns);
  }
  const std::string duplicate = mechgen::DuplicateColumnName(columns);
  if (!duplicate.empty()) {
    std::cerr << "error: the model " << name << " has two CSV columns named '"
              << duplicate << "'; rename the link, coordinate or point that makes it and "
              << "generate the model again\n";
    return kExitError;
  }

  // The model's parameters: its defaults, then --params and --set.
  typename Types::Params params = C::DefaultParams(model);
  if (!mechgen::tools::ApplyModelParameters(arguments.params, model, &params, &error)) return Usage(error);

  // Assembly at the model's assembly configuration, then the sweep.
  mechgen::position::PositionSolver<M, Assembler> solver(model, mechgen::position::Options(), params);
  mechgen::position::Summary assembly;
  mechgen::position::Status assembled;
  if (arguments.mode.empty()) {
    assembled = solver.AssembleDefault(&assembly);
  } else {
    // The named mode's closed-form roots at the assembly inputs, then the runtime's assembly
    // there on the branch (sign det Phi_phi) those roots give.
    typename Types::VecQ q = Eigen::Map<const typename Types::VecQ>(C::AssemblyQ(model), nq);
    typename Types::VecPhi phi = Eigen::Map<const typename Types::VecPhi>(C::AssemblyPhi(model), C::Nphi(model));
    double det = 0;
    if (C::HasSolve(model)) {
      const auto report = C::Solve(model, params, q, &phi, named_modes, 20, 0.0);
      // Angles as principal values (-pi, pi]: the closed forms keep them near the guess, which
      // is the default mode's.
      for (int i = 0; i < C::Nphi(model); ++i)
        if (C::PhiIsAngle(model, i) && std::isfinite(phi(i)))
          phi(i) = std::remainder(phi(i), 2 * 3.14159265358979323846);
      if (report.status == decltype(report.status)::kConverged) C::DetPhiPhi(model, params, q, phi, &det);
    }
    if (!(det != 0) || !std::isfinite(det)) {
      std::cerr << "error: cannot assemble " << name << " in mode '" << arguments.mode
                << "' at its assembly inputs (det Phi_phi = " << det << ")\n";
      return kExitError;
    }
    assembled = solver.Assemble(q, phi, det > 0 ? 1 : -1, &assembly);
  }
  if (assembled != mechgen::position::Status::kConverged) {
    std::cerr << "error: cannot assemble " << name << " at its assembly configuration"
              << (arguments.mode.empty() ? "" : " in mode '" + arguments.mode + "'") << ": "
              << mechgen::position::FormatSummary(assembly) << "\n";
    return kExitError;
  }
  // The outputs, opened before the sweep (after the assembly, so that a model that does not assemble creates no directory) (an unwritable path fails at once); written to
  // temporary files and renamed only when everything succeeded.
  mechgen::OutputFile csv, svg;
  if ((!csv_path.empty() && !csv.Open(csv_path, &error)) ||
      (!svg_path.empty() && !svg.Open(svg_path, &error))) {
    std::cerr << "error: " << error << "\n";
    return kExitError;
  }

  const bool loop_free = C::LoopFree(model);
  if (loop_free) {
    std::printf("mechgen sweep of '%s': no closed loop (every coordinate is an input, nothing to "
                "assemble); ", name);
  } else {
    std::printf("mechgen sweep of '%s': assembled (branch %+d = sign det Phi_phi, the assembly `mechgen report` names by its blocks' modes; |Phi|_inf = %.1e); ", name,
                assembly.branch, assembly.residual_norm);
  }
  for (int j = 0; j < nq; ++j) {
    std::printf("%s%s %s -> %s", j ? ", " : "", C::QName(model, j),
                Describe(model, j, q_begin(j)).c_str(), Describe(model, j, q_end(j)).c_str());
  }
  std::printf(" in %d steps\n", steps);
  const std::string changed = mechgen::tools::ChangedModelParameters(model, params);
  if (!changed.empty()) std::printf("parameters set: %s\n", changed.c_str());
  std::printf("\n");

  // The sweep, streamed: each row goes to the CSV as it is solved; kept are only the rows of
  // the table, those the drawing uses (all up to kMaxSvgRows, else evenly spaced ones) and
  // the first failures.
  const size_t rows = static_cast<size_t>(steps) + 1;
  const std::vector<size_t> table_indices = mechgen::TableRowIndices(rows, table_rows);
  const size_t svg_stride = rows <= kMaxSvgRows ? 1 : (rows - 2) / (kMaxSvgRows - 1) + 1;
  std::vector<Record> table_records, svg_records, failed;
  table_records.reserve(table_indices.size());
  if (!svg_path.empty()) svg_records.reserve(std::min(rows, kMaxSvgRows + 1));
  size_t next_table = 0;
  double max_residual = 0, max_condition = 0;
  long long iterations = 0, fallbacks = 0;
  int per_status[int(mechgen::position::Status::kNotRun) + 1] = {};
  // Timing: the solver's time (SweepRows between two rows: the continuation step, the
  // velocities and accelerations, the transmission angles) apart from the time this tool
  // spends handing each row out (CSV formatting, keeping the table's and drawing's rows);
  // the first row apart, since it continues from the assembly configuration.
  double output_seconds = 0, first_row_seconds = 0;
  if (!csv_path.empty())
    mechgen::WriteCsvHeader(columns, csv.stream(),
                            mechgen::Described(mechgen::CsvAbout(
                                std::string(name) + "_sweep", name,
                                "kinematic sweep", mechgen::kSweepSigns)));
  // The motion summary (strokes, extremes, time ratios) of a one-input sweep, row by row
  // (nothing for a model of several inputs).
  mechgen::MotionSummaryBuilder<M> motion_summary(q_begin(0), q_end(0), model);
  const auto start = std::chrono::steady_clock::now();
  auto row = [&](int i, const Record& r) {
    const auto t0 = std::chrono::steady_clock::now();
    if (i == 0) first_row_seconds = std::chrono::duration<double>(t0 - start).count();
    const size_t index = static_cast<size_t>(i);
    motion_summary.Add(r);
    if (!csv_path.empty()) mechgen::WriteCsvRow(columns, r, csv.stream());
    if (next_table < table_indices.size() && table_indices[next_table] == index) {
      table_records.push_back(r);
      ++next_table;
    }
    if (!svg_path.empty() && (index % svg_stride == 0 || index + 1 == rows)) {
      svg_records.push_back(r);
    }
    ++per_status[int(r.summary.status)];
    iterations += r.summary.iterations;
    fallbacks += r.summary.used_assembler;
    if (r.summary.status == mechgen::position::Status::kConverged) {
      max_residual = std::max(max_residual, r.summary.residual_norm);
      max_condition = std::max(max_condition, r.summary.condition);
    } else if (failed.size() < 3 && r.summary.status != mechgen::position::Status::kNotRun) {
      failed.push_back(r);
    }
    output_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  mechgen::SweepOptions sweep_options;
  sweep_options.design = arguments.design;
  sweep_options.at_singularity = arguments.at_singular == "follow"    ? mechgen::position::Crossing::kFollowTangent
                                 : arguments.at_singular == "switch"  ? mechgen::position::Crossing::kSwitchBranch
                                 : arguments.at_singular == "reverse" ? mechgen::position::Crossing::kReverseInput
                                                                 : mechgen::position::Crossing::kStop;
  int failures = 0;
  if constexpr (C::kView) {
    // The instantiation in mechgen_runtime_view (core/view_runtime.h: ViewRowFn).
    std::function<void(int, const Record&)> row_fn = row;
    failures = mechgen::SweepRows(&solver, q_begin, q_end, steps, qd, qdd, sweep_options, row_fn);
  } else {
    failures = mechgen::SweepRows(&solver, q_begin, q_end, steps, qd, qdd, sweep_options, row);
  }
  const double total_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double solve_seconds = total_seconds - output_seconds - first_row_seconds;

  if (table_rows > 0) {
    mechgen::PrintTableRows(mechgen::SweepColumns<M>(model), table_records, std::cout);
    std::cout << "\n";
  }
  if (nq == 1) {
    mechgen::PrintMotionSummary(motion_summary.Finish(), std::cout);
    std::cout << "\n";
  }
  if (loop_free) {
    std::printf("%d/%zu configurations (no loop: no equation to solve)\n",
                static_cast<int>(rows) - failures, rows);
  } else {
    std::printf("%d/%zu configurations converged; max |Phi|_inf = %.1e, max cond(Phi_phi) = %.3g, "
                "%.2f Newton iterations/step%s\n",
                static_cast<int>(rows) - failures, rows, max_residual, max_condition,
                double(iterations) / rows,
                fallbacks ? (std::string(" (") + assembler_name + " fallback used)").c_str() : "");
  }
  // Not the README's ~92 ns/step: that benchmark (bench/fourbar_bench.cc) times one
  // continuation step (PositionSolver::MoveTo) alone, without velocities, accelerations or
  // output.
  std::printf("time per row: %.2f us solving (continuation step + velocities, accelerations), "
              "%.2f us output (CSV row, table and drawing rows); the first row, from the "
              "assembly configuration, %.1f us\n",
              rows > 1 ? 1e6 * solve_seconds / double(rows - 1) : 0.0,
              1e6 * output_seconds / double(rows), 1e6 * first_row_seconds);
  for (const auto& r : failed) {
    std::printf("  %s = %s: %s\n", C::QName(model, 0), Describe(model, 0, r.q(0)).c_str(),
                mechgen::position::FormatSummary(r.summary).c_str());
  }

  if (!svg_path.empty()) {
    mechgen::SvgOptions options;
    options.animate = !no_animation;
    options.title = std::string("mechgen: ") + name;
    mechgen::WriteSvg(model, solver.params(), svg_records, options, svg.stream());
  }
  // Each output whole or absent (OutputFile: a temporary file renamed on success); both
  // closed, every write checked, before either is renamed into place.
  if ((!csv_path.empty() && !csv.Close(&error)) || (!svg_path.empty() && !svg.Close(&error)) ||
      (!csv_path.empty() && !csv.Commit(&error)) || (!svg_path.empty() && !svg.Commit(&error))) {
    std::cerr << "error: " << error << "\n";
    return kExitError;
  }
  if (!csv_path.empty()) {
    std::printf("wrote %s (%zu rows x %zu columns)\n", csv_path.c_str(), rows, columns.size());
  }
  if (!svg_path.empty()) {
    const std::string subsampled =
        svg_stride > 1 ? ", every " + std::to_string(svg_stride) + "th row" : "";
    std::printf("wrote %s (%s%s)\n", svg_path.c_str(),
                !no_animation ? "animated; open it in a web browser" : "still",
                subsampled.c_str());
  }
  if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout.flush()) {
    std::cerr << "error: cannot write the standard output\n";
    return kExitError;
  }
  if (failures > 0) {
    std::cerr << "error: " << failures << " of " << rows << " rows did not converge:";
    const char* separator = " ";
    for (int k = 0; k <= int(mechgen::position::Status::kNotRun); ++k) {
      if (k == int(mechgen::position::Status::kConverged) || per_status[k] == 0) continue;
      std::cerr << separator << per_status[k] << " "
                << mechgen::position::ToString(mechgen::position::Status(k));
      separator = ", ";
    }
    std::cerr << " (see the status column)\n";
    return kExitRowsFailed;
  }
  return kExitConverged;
}

}  // namespace mechgen::sweep_tool
