/**
 * \file analysis/sweep.h
 * The sweep as an analysis (issue 43: one analysis layer for every tool): Check(model,
 * request) says what is wrong with a SweepRequest (analysis/sweep_request.h) on this model,
 * Run(model, request, outputs) assembles, sweeps and streams the rows of the sweep's column
 * table (sweep/columns.h) to the CSV, prints the table, the motion summary and the counts,
 * draws the SVG, and writes the outputs whole or not at all; it returns the exit status
 * (kSweepConverged, kSweepRowsFailed, kSweepError, kSweepUsage). EvaluateSweep is the sweep
 * alone (no I/O: the assembly and the rows handed over), which Run writes and the study keeps
 * (study/run.h, analysis: sweep and statics). One source for the fixed-size
 * path (a generated model's type: the per-model tool <model>_sweep, tools/sweep_main.cc) and for
 * the model view (M = ViewModel: explicitly instantiated in runtime/view/analysis_sweep.cc,
 * declared in core/view_runtime.h; mechgen_view sweep, tools/view/sweep.cc).
 *
 * --params/--set read the model's parameter table (analysis/view_params.h); --svg draws
 * from the model's drawing description (io/svg.h), --mode reads its named assembly modes,
 * --design its Design (the design derivatives: the generated EvalDesignDerivatives through
 * ModelCalls<M>::Design, position/design.h).
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
#include "mechgen/analysis/sweep_request.h"
#include "mechgen/analysis/view_params.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/io/format.h"
#include "mechgen/io/output_file.h"
#include "mechgen/io/svg.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/columns.h"
#include "mechgen/sweep/motion_summary.h"
#include "mechgen/sweep/sweep.h"

namespace mechgen::analysis {

// The sweep streams: it holds one row, plus the table's rows and at most kSweepMaxSvgRows for
// the drawing.
constexpr size_t kSweepMaxSvgRows = 3601;

namespace sweep_internal {

// "1.5" -> 1.5 (model units, radians for angles); "90deg" -> pi/2. False if malformed.
inline bool ParseValue(const std::string& text, double* value) {
  return mechgen::tools::ParseNumber(text, value, /*allow_degrees=*/true);
}

// An input's value for the messages: "%g", in degrees for an angle; never "-0".
template <class M>
std::string Describe(const M& model, int j, double value) {
  if (ModelCalls<M>::QIsAngle(model, j)) return mechgen::internal::FormatNumber(internal::ToDegrees(value), "%g") + " deg";
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

/// A SweepRequest read against the model: the path, the input motion, the blocks' modes and
/// the parameters.
template <class M>
struct Inputs {
  using Types = ModelTypes<M>;
  typename Types::VecQ q_begin, q_end, qd, qdd;
  typename ModelCalls<M>::Modes modes;
  typename Types::Params params;
};

/// Reads the request against the model into *in; the usage error's text, empty when it fits.
template <class M>
std::string Resolve(const M& model, const SweepRequest& request, Inputs<M>* in) {
  using C = ModelCalls<M>;
  using Types = ModelTypes<M>;
  const char* const name = C::Name(model);
  const int nq = C::Nq(model);
  std::string error;
  // Counts checked by whoever filled the request: steps in 1..kSweepMaxSteps.
  const int steps = static_cast<int>(request.steps);
  in->modes = C::DefaultModes(model);
  if (!request.mode.empty() && !NamedModes(model, request.mode, &in->modes, &error)) return error;

  // Path of the sweep and the input motion.
  in->q_begin = Eigen::Map<const typename Types::VecQ>(C::QMin(model), nq);
  in->q_end = Eigen::Map<const typename Types::VecQ>(C::QMax(model), nq);
  for (const std::string& text : request.ranges) {
    int j = 0;
    double min = 0, max = 0;
    if (!mechgen::tools::ParseRange(model, text, &j, &min, &max, &error)) return error;
    in->q_begin(j) = min;
    in->q_end(j) = max;
  }
  // One step longer than the solver accepts would make every row invalid_input: a units
  // mistake, refused here (position::CheckInputSteps).
  if (const auto check = position::CheckInputSteps(in->q_begin, in->q_end, nq, steps); !check.ok())
    return mechgen::tools::RangeStepError(model, check);
  auto parse_vector = [nq](const std::vector<std::string>& text, double fallback, double bound,
                           const char* option, typename Types::VecQ* out, std::string* error) {
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
  if (!parse_vector(request.qd_text, 1.0, mechgen::tools::kMaxSpeed, "--qd", &in->qd, &error) ||
      !parse_vector(request.qdd_text, 0.0, mechgen::tools::kMaxAcceleration, "--qdd", &in->qdd, &error)) {
    return error;
  }
  if (request.design && !C::HasDesign(model))
    return std::string("--design: the model ") + name +
           " has no design section; add design: [parameter, ...] to it and generate it again";

  // The model's parameters: its defaults, then --params and --set.
  in->params = C::DefaultParams(model);
  if (!mechgen::tools::ApplyModelParameters(request.params, model, &in->params, &error)) return error;
  return "";
}

}  // namespace sweep_internal

/// What became of EvaluateSweep.
enum class SweepEvaluated {
  kRan,               ///< swept (the rows' statuses say which converged)
  kNotAssembled,      ///< no assembly at the model's assembly configuration (*assembly says why)
  kModeNotAssembled,  ///< the named mode's closed-form roots give no branch (*det)
  kStopped,           ///< begin returned false: nothing swept
};

/// The sweep's options from the request: the design columns, what to do at a singularity.
inline SweepOptions SweepOptionsOf(const SweepRequest& request) {
  SweepOptions o;
  o.design = request.design;
  o.at_singularity = request.at_singular == "follow"    ? position::Crossing::kFollowTangent
                     : request.at_singular == "switch"  ? position::Crossing::kSwitchBranch
                     : request.at_singular == "reverse" ? position::Crossing::kReverseInput
                                                        : position::Crossing::kStop;
  return o;
}

/**
 * \brief The rows of the sweep asked for by `request` as read against the model (`in`:
 * Resolve's, or the caller's: the study's sample), with no I/O: the position solver assembled
 * at the model's assembly configuration (request.mode: on the named mode's branch, from its
 * closed-form roots there), begin() once it did (false: nothing swept, kStopped), then
 * row(i, record) for each of the request.steps + 1 rows (SweepRecord<M>: the rows of the
 * sweep's column table, SweepColumns), in order. *assembly the assembly's summary, *det the
 * named mode's det Phi_phi, *failures the rows that failed (SweepRows).
 */
template <class M, class Assembler = position::NewtonAssembler, class Begin, class RowFn>
SweepEvaluated EvaluateSweep(const M& model, const SweepRequest& request, const sweep_internal::Inputs<M>& in,
                             Begin&& begin, RowFn&& row, position::Summary* assembly, double* det, int* failures) {
  using C = ModelCalls<M>;
  using Types = ModelTypes<M>;
  const int nq = C::Nq(model);
  *failures = 0;
  position::PositionSolver<M, Assembler> solver(model, position::Options(), in.params);
  position::Status assembled;
  if (request.mode.empty()) {
    assembled = solver.AssembleDefault(assembly);
  } else {
    // The named mode's closed-form roots at the assembly inputs, then the runtime's assembly
    // there on the branch (sign det Phi_phi) those roots give.
    typename Types::VecQ q = Eigen::Map<const typename Types::VecQ>(C::AssemblyQ(model), nq);
    typename Types::VecPhi phi = Eigen::Map<const typename Types::VecPhi>(C::AssemblyPhi(model), C::Nphi(model));
    *det = 0;
    if (C::HasSolve(model)) {
      const auto report = C::Solve(model, in.params, q, &phi, in.modes, 20, 0.0);
      // Angles as principal values (-pi, pi]: the closed forms keep them near the guess, which
      // is the default mode's.
      for (int i = 0; i < C::Nphi(model); ++i)
        if (C::PhiIsAngle(model, i) && std::isfinite(phi(i)))
          phi(i) = std::remainder(phi(i), 2 * 3.14159265358979323846);
      if (report.status == decltype(report.status)::kConverged) C::DetPhiPhi(model, in.params, q, phi, det);
    }
    if (!(*det != 0) || !std::isfinite(*det)) return SweepEvaluated::kModeNotAssembled;
    assembled = solver.Assemble(q, phi, *det > 0 ? 1 : -1, assembly);
  }
  if (assembled != position::Status::kConverged) return SweepEvaluated::kNotAssembled;
  if (!begin()) return SweepEvaluated::kStopped;
  const int steps = static_cast<int>(request.steps);
  if constexpr (C::kView) {
    // The instantiation in mechgen_runtime_view (core/view_runtime.h: ViewRowFn).
    std::function<void(int, const SweepRecord<M>&)> row_fn = row;
    *failures = mechgen::SweepRows(&solver, in.q_begin, in.q_end, steps, in.qd, in.qdd, SweepOptionsOf(request), row_fn);
  } else {
    *failures = mechgen::SweepRows(&solver, in.q_begin, in.q_end, steps, in.qd, in.qdd, SweepOptionsOf(request), row);
  }
  return SweepEvaluated::kRan;
}

/// What is wrong with `request` on `model` (the usage error's text, one line), empty when
/// Run can go on: the ranges' inputs and their steps (position::CheckInputSteps), --qd and
/// --qdd, the named mode, --design on a model without a design section, the parameters.
template <class M>
std::string Check(const M& model, const SweepRequest& request) {
  sweep_internal::Inputs<M> in;
  return sweep_internal::Resolve(model, request, &in);
}

/// The sweep of a view whose shape the runtime has an instantiation sized to
/// (core/view_sized.h: SizedViewModel), run there, its exit status in *status; false (nothing
/// done) for any other view, or one whose `sized` is false. In mechgen_runtime_view
/// (runtime/view/analysis_sized.cc).
bool RunSized(const ViewModel& model, const SweepRequest& request, const SweepOutputs& outputs, int* status);

/**
 * \brief The sweep of `model` asked for by `request`, written to `outputs`.
 * \tparam M          A generated model (the per-model tool) or mechgen::ViewModel.
 * \tparam Assembler  The solver's assembler (position/assembler.h): CeresAssembler in the
 *                    per-model tool, NewtonAssembler without Ceres and for the view.
 * \return The exit status (kSweepConverged, kSweepRowsFailed, kSweepError, kSweepUsage after
 *         "<tool>: error: <Check's text>" on stderr).
 */
template <class M, class Assembler = position::NewtonAssembler>
int Run(const M& model, const SweepRequest& request, const SweepOutputs& outputs) {
  if constexpr (std::is_same_v<M, ViewModel>) {
    if (int status = 0; RunSized(model, request, outputs, &status)) return status;
  }
  using C = ModelCalls<M>;
  using Types = ModelTypes<M>;
  using Record = SweepRecord<M>;
  const char* const name = C::Name(model);
  const int nq = C::Nq(model);
  const std::string& csv_path = outputs.csv_path;
  const std::string& svg_path = outputs.svg_path;
  std::string error;
  sweep_internal::Inputs<M> in;
  error = sweep_internal::Resolve(model, request, &in);
  if (!error.empty()) return mechgen::tools::UsageError(outputs.tool, error);
  const int steps = static_cast<int>(request.steps);
  const int table_rows = static_cast<int>(request.table);
  const typename Types::VecQ& q_begin = in.q_begin;
  const typename Types::VecQ& q_end = in.q_end;
  const typename Types::Params& params = in.params;

  // The CSV's columns must be unique (the generator ensures it; checked again here).
  std::vector<mechgen::SweepColumn<M>> columns = mechgen::SweepColumns<M>(model);
  if (request.design) mechgen::AppendDesignColumns<M>(model, &columns);
  const std::string duplicate = mechgen::DuplicateColumnName(columns);
  if (!duplicate.empty()) {
    std::cerr << "error: the model " << name << " has two CSV columns named '"
              << duplicate << "'; rename the link, coordinate or point that makes it and "
              << "generate the model again\n";
    return kSweepError;
  }

  // Assembly at the model's assembly configuration, then the sweep (EvaluateSweep); the
  // outputs are opened and the heading printed once it assembled (begin).
  mechgen::position::Summary assembly;
  double det = 0;
  mechgen::OutputFile csv, svg;
  bool opened = true;
  // The sweep, streamed: each row goes to the CSV as it is solved; kept are only the rows of
  // the table, those the drawing uses (all up to kMaxSvgRows, else evenly spaced ones) and
  // the first failures.
  const size_t rows = static_cast<size_t>(steps) + 1;
  const std::vector<size_t> table_indices = mechgen::TableRowIndices(rows, table_rows);
  const size_t svg_stride = rows <= kSweepMaxSvgRows ? 1 : (rows - 2) / (kSweepMaxSvgRows - 1) + 1;
  std::vector<Record> table_records, svg_records, failed;
  table_records.reserve(table_indices.size());
  if (!svg_path.empty()) svg_records.reserve(std::min(rows, kSweepMaxSvgRows + 1));
  size_t next_table = 0;
  double max_residual = 0, max_condition = 0;
  long long iterations = 0, fallbacks = 0;
  int per_status[int(mechgen::position::Status::kNotRun) + 1] = {};
  // Timing: the solver's time (SweepRows between two rows: the continuation step, the
  // velocities and accelerations, the transmission angles) apart from the time this tool
  // spends handing each row out (CSV formatting, keeping the table's and drawing's rows);
  // the first row apart, since it continues from the assembly configuration.
  double output_seconds = 0, first_row_seconds = 0;
  // The motion summary (strokes, extremes, time ratios) of a one-input sweep, row by row
  // (nothing for a model of several inputs).
  mechgen::MotionSummaryBuilder<M> motion_summary(q_begin(0), q_end(0), model);
  auto start = std::chrono::steady_clock::now();
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
  const bool loop_free = C::LoopFree(model);
  auto begin = [&]() {
    // The outputs, opened before the sweep (after the assembly, so that a model that does not assemble creates no directory) (an unwritable path fails at once); written to
    // temporary files and renamed only when everything succeeded.
    if ((!csv_path.empty() && !csv.Open(csv_path, &error)) ||
        (!svg_path.empty() && !svg.Open(svg_path, &error))) {
      std::cerr << "error: " << error << "\n";
      opened = false;
      return false;
    }

    if (loop_free) {
      std::printf("mechgen sweep of '%s': no closed loop (every coordinate is an input, nothing to "
                  "assemble); ", name);
    } else {
      std::printf("mechgen sweep of '%s': assembled (branch %+d = sign det Phi_phi, the assembly `mechgen report` names by its blocks' modes; |Phi|_inf = %.1e); ", name,
                  assembly.branch, assembly.residual_norm);
    }
    for (int j = 0; j < nq; ++j) {
      std::printf("%s%s %s -> %s", j ? ", " : "", C::QName(model, j),
                  sweep_internal::Describe(model, j, q_begin(j)).c_str(), sweep_internal::Describe(model, j, q_end(j)).c_str());
    }
    std::printf(" in %d steps\n", steps);
    const std::string changed = mechgen::tools::ChangedModelParameters(model, params);
    if (!changed.empty()) std::printf("parameters set: %s\n", changed.c_str());
    std::printf("\n");

    if (!csv_path.empty())
      mechgen::WriteCsvHeader(columns, csv.stream(),
                              mechgen::Described(mechgen::CsvAbout(
                                  std::string(name) + "_sweep", name,
                                  "kinematic sweep", mechgen::kSweepSigns)));
    start = std::chrono::steady_clock::now();
    return true;
  };
  int failures = 0;
  const SweepEvaluated evaluated =
      EvaluateSweep<M, Assembler>(model, request, in, begin, row, &assembly, &det, &failures);
  if (evaluated == SweepEvaluated::kModeNotAssembled) {
    std::cerr << "error: cannot assemble " << name << " in mode '" << request.mode
              << "' at its assembly inputs (det Phi_phi = " << det << ")\n";
    return kSweepError;
  }
  if (evaluated == SweepEvaluated::kNotAssembled) {
    std::cerr << "error: cannot assemble " << name << " at its assembly configuration"
              << (request.mode.empty() ? "" : " in mode '" + request.mode + "'") << ": "
              << mechgen::position::FormatSummary(assembly) << "\n";
    return kSweepError;
  }
  if (!opened) return kSweepError;
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
                fallbacks ? (std::string(" (") + outputs.assembler_name + " fallback used)").c_str() : "");
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
    std::printf("  %s = %s: %s\n", C::QName(model, 0), sweep_internal::Describe(model, 0, r.q(0)).c_str(),
                mechgen::position::FormatSummary(r.summary).c_str());
  }

  if (!svg_path.empty()) {
    mechgen::SvgOptions options;
    options.animate = outputs.animate;
    options.title = std::string("mechgen: ") + name;
    mechgen::WriteSvg(model, params, svg_records, options, svg.stream());
  }
  // Each output whole or absent (OutputFile: a temporary file renamed on success); both
  // closed, every write checked, before either is renamed into place.
  if ((!csv_path.empty() && !csv.Close(&error)) || (!svg_path.empty() && !svg.Close(&error)) ||
      (!csv_path.empty() && !csv.Commit(&error)) || (!svg_path.empty() && !svg.Commit(&error))) {
    std::cerr << "error: " << error << "\n";
    return kSweepError;
  }
  if (!csv_path.empty()) {
    std::printf("wrote %s (%zu rows x %zu columns)\n", csv_path.c_str(), rows, columns.size());
  }
  if (!svg_path.empty()) {
    const std::string subsampled =
        svg_stride > 1 ? ", every " + std::to_string(svg_stride) + "th row" : "";
    std::printf("wrote %s (%s%s)\n", svg_path.c_str(),
                outputs.animate ? "animated; open it in a web browser" : "still",
                subsampled.c_str());
  }
  if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout.flush()) {
    std::cerr << "error: cannot write the standard output\n";
    return kSweepError;
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
    return kSweepRowsFailed;
  }
  return kSweepConverged;
}

}  // namespace mechgen::analysis
