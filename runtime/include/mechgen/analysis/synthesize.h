/**
 * \file analysis/synthesize.h
 * Dimensional synthesis as an analysis (issue 43: one analysis layer for every tool), asked for
 * by a SynthesizeRequest (analysis/synthesize_request.h): the task file's kind chooses path
 * generation (synthesis/path.h, optimize.h, projection.h), function generation
 * (synthesis/function.h), motion generation (synthesis/motion.h) or exact path synthesis
 * (`kind: exact`: synthesis/exact.h, nine points: nine_point.h). Check(model, request) says
 * what is wrong with the request on this model (the parameters, the task file read and bound to
 * the model, the model file); Run(model, request, outputs) reads the request through the same
 * Prepare, synthesizes, prints the report and writes the outputs into request.out_dir whole
 * (each to a temporary name, then renamed) or not at all. One source for the per-model tool
 * <model>_synthesize (tools/synthesize_main.cc, M the generated model's type, fixed sizes) and
 * for the model view (M = ViewModel: runtime/view/synthesis.cc, declared in
 * synthesis/view_synthesis.h, the library mechgen_runtime_view_synthesis; `mechgen_view
 * synthesize`). It reads the model only through ModelCalls<M> where the synthesis layer does.
 * What each kind does, what it writes and the exit statuses: tools/synthesize_main.cc.
 *
 * Through the view: path generation and motion generation beyond five poses (the local stage's
 * and the least squares' Jacobian from the view's design derivatives), motion generation (the
 * Burmester pairs; four poses the curves), exact path synthesis (`kind: exact`) and function
 * generation (synthesis/function.h: its Levenberg-Marquardt Jacobian from the view's design
 * derivatives), with --params/--set on the view's parameter table (analysis/view_params.h).
 */
#pragma once

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "mechgen/analysis/numbers.h"
#include "mechgen/analysis/params.h"
#include "mechgen/analysis/synthesize_request.h"
#include "mechgen/analysis/view_params.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/synthesis/exact.h"
#include "mechgen/synthesis/function.h"
#include "mechgen/synthesis/motion.h"
#include "mechgen/synthesis/projection.h"
#include "mechgen/synthesis/report.h"
#include "mechgen/synthesis/task.h"

namespace mechgen::analysis {
namespace synthesize_internal {

namespace fs = std::filesystem;
namespace tools = mechgen::tools;
using namespace mechgen::synthesis;

inline bool WriteWhole(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
  out.close();
  return static_cast<bool>(out);
}

// The model file's text into *text; false, with what went wrong in *error, when it cannot be read.
inline bool ReadModelText(const std::string& path, std::string* text, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  if (!in) {
    *error = "cannot read the model file " + path;
    return false;
  }
  *text = bytes.str();
  return true;
}

// Writes (path, bytes) whole: each to a temporary name, then renamed; nothing left on failure.
inline bool WriteAll(const std::vector<std::pair<fs::path, const std::string*>>& files, const std::string& out_dir) {
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  bool ok = !ec;
  for (const auto& f : files) ok = ok && WriteWhole(f.first.string() + ".part", *f.second);
  for (const auto& f : files) {
    if (ok) {
      fs::rename(f.first.string() + ".part", f.first, ec);
      ok = !ec;
    }
  }
  if (!ok)
    for (const auto& f : files) fs::remove(f.first.string() + ".part", ec);
  return ok;
}

// The report's line on the parameters set by --set or --params ("" when none is).
template <class M>
std::string SetLine(const M& model, const typename ModelTypes<M>::Params& base, const std::vector<std::string>& variables) {
  const std::string set = SetParametersText(model, base, variables);
  return set.empty() ? std::string() : "\nparameters set by --set/--params (the search used them; the model file is written with them): " + set + "\n";
}

/// The task file's kind (its `synthesis:`, and `kind: exact` for a path task).
enum class Kind { kPath, kFunction, kMotion, kExact };

/// What Prepare reads from a request and a model, for Check and Run alike: the parameters, the
/// task file read and bound to the model (its kind's members), the model file's text.
template <class M>
struct Prepared {
  std::string model_path;               ///< the model file (the request's)
  typename ModelTypes<M>::Params base;  ///< the model's parameters, with --set/--params
  Kind kind = Kind::kPath;
  MotionTask motion;
  FunctionTask function;
  BoundFunction<M> bound_function;
  ExactTask exact;
  BoundExact<M> bound_exact;
  PathTask path;
  BoundPath<M> bound_path;
  /// The model file's text (path and function tasks, exact ones of five points; a motion task
  /// reads it after the search, when it writes a model file).
  std::string model_text;
  int status = 0;          ///< 0 read whole, else the exit status its error ends with (2: a usage error)
  bool tool_line = false;  ///< the error printed as "<tool>: error: <text>" (else as it is: FILE:LINE:COLUMN: error: ...)
};

// Prepare's end when the request fits: status 0, no error.
template <class M>
std::string Fits(Prepared<M>* r) {
  r->status = 0;
  return "";
}

// A task file's error (its reading or its binding; file:line:column) as Prepare's: exit 1.
template <class M>
std::string TaskError(Prepared<M>* r, const std::string& error) {
  r->status = 1;
  r->tool_line = false;
  return error;
}

// The model file's text into r->model_text; the error (exit 1, "<tool>: error: ") when it cannot be read.
template <class M>
std::string ReadModel(Prepared<M>* r) {
  std::string error;
  if (ReadModelText(r->model_path, &r->model_text, &error)) return Fits(r);
  r->status = 1;
  r->tool_line = true;
  return error;
}

// Function generation: the task read, its evaluations (--evaluations), bound, the model file.
template <class M>
std::string PrepareFunction(const M& model, const SynthesizeRequest& a, Prepared<M>* r) {
  std::string error;
  FunctionTask& task = r->function;
  if (!ParseFunctionTask(a.task_path, &task, &error)) return TaskError(r, error);
  if (a.evaluations > 0) task.search.evaluations = a.evaluations;
  if (!BindFunctionTask(model, task, r->base, &r->bound_function, &error)) return TaskError(r, error);
  return ReadModel(r);
}

// Motion generation: the task read (bound by SynthesizeMotion itself).
template <class M>
std::string PrepareMotion(const SynthesizeRequest& a, Prepared<M>* r) {
  std::string error;
  if (!ParseMotionTask(a.task_path, &r->motion, &error)) return TaskError(r, error);
  return Fits(r);
}

// Exact path synthesis: the task read and bound, and the model file (each real solution is
// written as a model, five points or nine).
template <class M>
std::string PrepareExact(const M& model, const SynthesizeRequest& a, Prepared<M>* r) {
  std::string error;
  ExactTask& task = r->exact;
  if (!ParseExactTask(a.task_path, &task, &error)) return TaskError(r, error);
  if (!BindExactTask(model, task, r->base, &r->bound_exact, &error)) return TaskError(r, error);
  return ReadModel(r);
}

// Path generation: the task read, its evaluations (--evaluations), bound, the model file, and
// the design section (the local stage's Jacobian).
template <class M>
std::string PreparePath(const M& model, const SynthesizeRequest& a, Prepared<M>* r) {
  using C = ModelCalls<M>;
  std::string error;
  PathTask& task = r->path;
  if (!ParseTask(a.task_path, &task, &error)) return TaskError(r, error);
  if (a.evaluations > 0) task.search.evaluations = a.evaluations;
  if (!BindPathTask(model, task, r->base, &r->bound_path, &error)) return TaskError(r, error);
  if (const std::string read = ReadModel(r); r->status != 0) return read;
  if constexpr (C::kView || mechgen::HasDesignDerivatives<M>::value) {
    return Fits(r);
  } else {
    r->status = 1;
    r->tool_line = true;
    return std::string("the model '") + C::Name(model) +
           "' has no `design` section; add `design: [parameters to vary]` (models/README.md)";
  }
}

/// Reads the request against the model into *r: the model file's path, the parameters, the
/// task's kind and what the model needs for it, the task read and bound, the model file's text.
/// The error's text, empty when it fits; r->status 0 when it fits, else the exit status it ends
/// with (2 a usage error: the model file's path, the parameters; 1 the task file or the model
/// cannot take it) and r->tool_line how it is printed.
template <class M>
std::string Prepare(const M& model, const SynthesizeRequest& a, Prepared<M>* r) {
  using C = ModelCalls<M>;
  const char* const name = C::Name(model);
  const std::string& task_path = a.task_path;
  r->status = tools::kExitUsage;
  r->tool_line = true;
  if (a.model_path.empty()) return "--model: the model file is needed (run as `mechgen synthesize MODEL ...`)";
  r->model_path = a.model_path;
  r->base = C::DefaultParams(model);
  std::string error;
  if (!tools::ApplyModelParameters(a.params, model, &r->base, &error)) return error;
  r->status = 1;
  r->tool_line = false;
  const std::string kind = TaskKind(task_path, &error);
  if (!error.empty()) return error;
  if (kind == "motion") {
    r->kind = Kind::kMotion;
    if (C::NumPoints(model) > 0) {
      return PrepareMotion(a, r);
    } else {
      return task_path + ": error: the model '" + name + "' has no output points (the pose's point)";
    }
  }
  const bool exact = kind == "path" && PathTaskKind(task_path, &error) == "exact";
  if (exact) {
    r->kind = Kind::kExact;
    if (C::NumPoints(model) > 0 && C::Nq(model) == 1) {
      return PrepareExact(model, a, r);
    } else {
      return task_path + ": error: kind: exact needs a four-bar model with one input and the coupler point among " +
             "its outputs; '" + name + "' is not one";
    }
  }
  if (kind == "function") {
    r->kind = Kind::kFunction;
    if constexpr (mechgen::HasDesignDerivatives<M>::value) {
      if (C::HasDesign(model)) return PrepareFunction(model, a, r);
    }
    return task_path + ": error: the model '" + name +
           "' has no `design` section; add `design: [parameters to vary]` (models/README.md)";
  }
  r->kind = Kind::kPath;
  return PreparePath(model, a, r);
}

// Function generation (synthesis/function.h): writes the model file, function.svg, report.txt.
template <class M>
int FunctionMain(const M& model, const std::string& tool, const SynthesizeRequest& request, const Prepared<M>& prepared) {
  using C = ModelCalls<M>;
  const std::string &model_path = prepared.model_path, &out_dir = request.out_dir, &model_text = prepared.model_text;
  const unsigned long long seed = request.seed;
  const int threads = request.threads;
  const typename ModelTypes<M>::Params& base = prepared.base;
  const FunctionTask& task = prepared.function;
  const BoundFunction<M>& bound = prepared.bound_function;
  std::string error;
  std::cerr << tool << ": function task: " << task.search.restarts << " global runs, " << task.search.evaluations
            << " evaluations, " << threads << " thread(s)\n";
  const FunctionResult r = SynthesizeFunction(bound, seed, threads);
  std::vector<std::string> variables;
  for (const Variable& v : task.variables) variables.push_back(v.name);
  std::string report = FunctionReport(bound, r, seed, threads) + SetLine(model, base, variables);
  if (!r.best.feasible()) {
    std::cerr << report << "\n" << tool << ": no mechanism meets the pairs on its assembly mode; nothing written\n";
    return 3;
  }
  std::vector<std::string> names;
  std::vector<double> values;
  FunctionModelParameters(bound, r.best, &names, &values);  // the variables (and the start angles' offsets)
  // The written model's parameters and its input at the pairs (FunctionWrittenInputs).
  auto written_params = base;
  for (size_t k = 0; k < names.size(); ++k) *C::FindParameter(model, &written_params, names[k].c_str()) = values[k];
  C::ParametersSet(model, &written_params);
  const std::vector<double> motion = FunctionWrittenInputs(bound, r.best);
  std::string synthesized;
  WrittenAssembly written;
  if (!WriteSynthesizedModel(model, model_text, written_params, names, motion, &synthesized, &written, &error)) {
    std::cerr << tool << ": error: cannot write the synthesized model: " << error << "\n";
    return 1;
  }
  report += WrittenModelText(model, written, written_params);
  FunctionEvaluator<M> eval(bound);
  const std::string svg = FunctionSvg(&eval, r.best);
  const std::vector<std::pair<fs::path, const std::string*>> files = {
      {fs::path(out_dir) / fs::path(model_path).filename(), &synthesized},
      {fs::path(out_dir) / "function.svg", &svg},
      {fs::path(out_dir) / "report.txt", &report}};
  if (!WriteAll(files, out_dir)) {
    std::cerr << tool << ": error: cannot write into " << out_dir << "\n";
    return 1;
  }
  std::cout << report << "\nwrote " << files[0].first.string() << ", " << files[1].first.string() << ", "
            << files[2].first.string() << "\n";
  return 0;
}

// Motion generation (synthesis/motion.h): five or more poses, the model file of the chosen
// Burmester pair (more than five: after least squares) and report.txt; four poses, curves.csv
// and curves.svg.
template <class M>
int MotionMain(const M& model, const std::string& tool, const SynthesizeRequest& request, const Prepared<M>& prepared) {
  using C = ModelCalls<M>;
  const std::string &model_path = prepared.model_path, &out_dir = request.out_dir;
  const typename ModelTypes<M>::Params& base = prepared.base;
  const MotionTask& task = prepared.motion;
  std::string error;
  MotionResult r;
  if (!SynthesizeMotion(model, task, base, &r, &error)) {
    std::cerr << error << "\n";
    return 1;
  }
  std::string report = MotionReport(task, r);
  std::vector<std::pair<fs::path, const std::string*>> files;
  std::string second, third;
  if (task.poses.size() == 4) {
    second = "# the four-pose Burmester curves: circle point k in the body frame of pose 1 (origin its point, x "
             "at its angle), centre point M in the frame of the poses; one row per point found on a ray\n"
             "ray,k_x,k_y,M_x,M_y,radius\n";
    for (const CurvePoint& cp : r.curve)
      second += std::to_string(cp.ray) + "," + Num(cp.dyad.k.x()) + "," + Num(cp.dyad.k.y()) + "," + Num(cp.dyad.M.x()) +
                "," + Num(cp.dyad.M.y()) + "," + Num(cp.dyad.radius) + "\n";
    third = CurvesSvg(task, r);
    files = {{fs::path(out_dir) / "curves.csv", &second}, {fs::path(out_dir) / "curves.svg", &third},
             {fs::path(out_dir) / "report.txt", &report}};
  } else {
    if (r.chosen < 0) {
      std::cerr << report << "\n" << tool << ": no pair of Burmester points guides the model's coupler through the poses; nothing written\n";
      return 3;
    }
    std::string model_text;
    if (!ReadModelText(model_path, &model_text, &error)) {
      std::cerr << tool << ": error: " << error << "\n";
      return 1;
    }
    const FourBarFromDyads& f = r.candidates[static_cast<size_t>(r.chosen)].fourbar;
    const double values[9] = {f.a, f.b, f.c, f.d, f.xi, f.eta, f.x0, f.y0, f.theta0};
    auto written_params = base;
    for (size_t k = 0; k < 9; ++k) *C::FindParameter(model, &written_params, task.parameters[k].c_str()) = values[k];
    C::ParametersSet(model, &written_params);
    WrittenAssembly written;
    typename C::Modes modes = C::DefaultModes(model);  // the model's, or its mirror (the pair's mode)
    modes[0] = r.candidates[static_cast<size_t>(r.chosen)].mode;
    if (!WriteSynthesizedModel(model, model_text, written_params, task.parameters, MotionInputs(f), &second, &written,
                               &error, &modes)) {
      std::cerr << tool << ": error: cannot write the synthesized model: " << error << "\n";
      return 1;
    }
    report += SetLine(model, base, task.parameters) + WrittenModelText(model, written, written_params);
    files = {{fs::path(out_dir) / fs::path(model_path).filename(), &second}, {fs::path(out_dir) / "report.txt", &report}};
  }
  if (!WriteAll(files, out_dir)) {
    std::cerr << tool << ": error: cannot write into " << out_dir << "\n";
    return 1;
  }
  std::cout << report << "\nwrote";
  for (size_t k = 0; k < files.size(); ++k) std::cout << (k ? ", " : " ") << files[k].first.string();
  std::cout << "\n";
  return 0;
}

// Nine points, pivots free (synthesis/nine_point.h, exact.h): every real four-bar checked by
// the generated kinematics and the defect checks and written as a model file
// (<model>_nine_NNNN.yaml, NNNN its solution), solutions.csv (every real four-bar, with its
// verdicts and model file), report.txt and four_bar_NNNN.svg for each defect-free one.
template <class M>
int NinePointMain(const M& model, const std::string& tool, const SynthesizeRequest& request, const Prepared<M>& prepared) {
  const std::string &task_path = request.task_path, &out_dir = request.out_dir;
  const int threads = request.threads;
  std::cerr << tool << ": exact path synthesis, nine points: monodromy (1442 classes for generic points), "
            << threads << " thread(s)\n";
  std::vector<std::pair<std::string, std::string>> models;
  const NinePointRun run = RunNinePointTask(prepared.bound_exact, prepared.model_text,
                                            fs::path(prepared.model_path).stem().string(), &models, threads);
  const std::string report = NinePointReport(run), csv = NinePointCsv(run, ModelCalls<M>::Name(model), task_path);
  std::vector<std::pair<fs::path, const std::string*>> files;
  for (const auto& m : models) files.emplace_back(fs::path(out_dir) / m.first, &m.second);
  for (const auto& d : run.drawings) files.emplace_back(fs::path(out_dir) / d.first, &d.second);
  files.emplace_back(fs::path(out_dir) / "solutions.csv", &csv);
  files.emplace_back(fs::path(out_dir) / "report.txt", &report);
  if (!WriteAll(files, out_dir)) {
    std::cerr << tool << ": error: cannot write into " << out_dir << "\n";
    return 1;
  }
  std::cout << report << "\nwrote " << models.size() << " model file(s), " << run.drawings.size() << " drawing(s), "
            << (fs::path(out_dir) / "solutions.csv").string() << ", " << (fs::path(out_dir) / "report.txt").string()
            << "\n";
  if (!run.complete) std::cerr << tool << ": warning: the solution set is INCOMPLETE (report.txt)\n";
  return 0;
}

// Exact path synthesis (`synthesis: path`, `kind: exact`; synthesis/exact.h): every isolated
// solution of five points with both pivots given; each real one as a model file
// (<model>_exact_NN.yaml, NN its row in solutions.csv), solutions.csv and report.txt. Nine
// points without pivots: NinePointMain.
template <class M>
int ExactMain(const M& model, const std::string& tool, const SynthesizeRequest& request, const Prepared<M>& prepared) {
  const std::string &task_path = request.task_path, &model_path = prepared.model_path, &out_dir = request.out_dir;
  const std::string& model_text = prepared.model_text;
  const typename ModelTypes<M>::Params& base = prepared.base;
  const ExactTask& task = prepared.exact;
  const BoundExact<M>& bound = prepared.bound_exact;
  if (task.nine) return NinePointMain(model, tool, request, prepared);
  std::cerr << tool << ": exact path synthesis: every path of the homotopy (256)\n";
  std::vector<std::pair<std::string, std::string>> models;
  const ExactRun run = RunExactTask(bound, model_text, fs::path(model_path).stem().string(), &models);
  std::vector<std::string> names;
  for (const std::string& n : task.parameters)
    if (!n.empty()) names.push_back(n);
  const std::string report = ExactReport(run, task) + SetLine(model, base, names);
  const std::string csv = ExactCsv(run, ModelCalls<M>::Name(model), task_path);
  std::vector<std::pair<fs::path, const std::string*>> files;
  for (const auto& m : models) files.emplace_back(fs::path(out_dir) / m.first, &m.second);
  files.emplace_back(fs::path(out_dir) / "solutions.csv", &csv);
  files.emplace_back(fs::path(out_dir) / "report.txt", &report);
  if (!WriteAll(files, out_dir)) {
    std::cerr << tool << ": error: cannot write into " << out_dir << "\n";
    return 1;
  }
  std::cout << report << "\nwrote " << models.size() << " model file(s), " << (fs::path(out_dir) / "solutions.csv").string()
            << ", " << (fs::path(out_dir) / "report.txt").string() << "\n";
  if (!run.complete)
    std::cerr << tool << ": warning: the solution set is INCOMPLETE (failed, singular or coinciding paths: "
              << "rows of solutions.csv with their figures)\n";
  return 0;
}

// Path generation (synthesis/path.h, optimize.h, projection.h): writes the model file, path.svg,
// report.txt. (Prepare refuses a model without design derivatives.)
template <class M>
int PathMain(const M& model, const std::string& tool, const SynthesizeRequest& request, const Prepared<M>& prepared) {
  const std::string &model_path = prepared.model_path, &out_dir = request.out_dir, &model_text = prepared.model_text;
  const unsigned long long seed = request.seed;
  const int threads = request.threads;
  const typename ModelTypes<M>::Params& base = prepared.base;
  const PathTask& task = prepared.path;
  const BoundPath<M>& bound = prepared.bound_path;
  std::string error;
  const auto wall0 = std::chrono::steady_clock::now();
  const std::clock_t cpu0 = std::clock();
  std::cerr << tool << ": " << task.search.restarts << " runs, " << task.search.evaluations << " evaluations, "
            << threads << " thread(s)\n";
  SearchResult s;
  if (!SynthesizePath(bound, seed, threads, &s, &error, [&](int done, int total) {
        std::fprintf(stderr, "%s: run %d of %d done\n", tool.c_str(), done, total);
      })) {
    std::cerr << error << "\n";
    return 1;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const double cpu = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  PathEvaluator<M> eval(bound);
  const Candidate& c = s.best.best;
  const std::string continuation = c.feasible() ? ContinuationCheck(&eval, c) : std::string("not run");
  std::vector<std::string> names;
  for (const Variable& v : task.variables) names.push_back(v.name);
  std::string report = Report(&eval, s, continuation, seed, threads, wall, cpu, model_path) + SetLine(model, base, names);
  if (!c.feasible() || !continuation.empty()) {
    std::cerr << report << "\n" << tool << ": no mechanism satisfies the task's constraints; nothing written\n";
    return 3;
  }
  // The outputs: built whole in memory, written to temporary names, then renamed.
  std::string synthesized;
  WrittenAssembly written;
  if (!WriteSynthesizedModel(model, model_text, eval.ParamsOf(c.x), names, MotionInputs(bound, c), &synthesized,
                             &written, &error)) {
    std::cerr << tool << ": error: cannot write the synthesized model: " << error << "\n";
    return 1;
  }
  report += WrittenModelText(model, written, eval.ParamsOf(c.x));
  const std::string svg = CurveSvg(&eval, c);
  const std::vector<std::pair<fs::path, const std::string*>> files = {
      {fs::path(out_dir) / fs::path(model_path).filename(), &synthesized},
      {fs::path(out_dir) / "path.svg", &svg},
      {fs::path(out_dir) / "report.txt", &report}};
  if (!WriteAll(files, out_dir)) {
    std::cerr << tool << ": error: cannot write into " << out_dir << "\n";
    return 1;
  }
  std::cout << report;
  std::cout << "\nwrote " << files[0].first.string() << ", " << files[1].first.string() << ", "
            << files[2].first.string() << "\n";
  return 0;
}

}  // namespace synthesize_internal

/// What is wrong with `request` on `model` (one line, or a task file's FILE:LINE:COLUMN: error:
/// ...), empty when Run can go on: the model file's path, the parameters, the task file (its
/// kind, read, bound to the model: its point, parameters, variables), what its kind needs of the
/// model (output points, one input, the design section), the model file readable.
template <class M>
std::string Check(const M& model, const SynthesizeRequest& request) {
  synthesize_internal::Prepared<M> r;
  return synthesize_internal::Prepare(model, request, &r);
}

/**
 * \brief The synthesis `request` asks for (its task file's kind) on `model`: the report on the
 * standard output, the outputs written into request.out_dir whole or not at all.
 * \tparam M  A generated model (the per-model tool) or mechgen::ViewModel.
 * \return The exit status (0 done, 1 a bad task file, a model that cannot take it or an output
 *         not written, 2 a usage error, 3 no feasible mechanism: tools/synthesize_main.cc).
 */
template <class M>
int Run(const M& model, const SynthesizeRequest& request, const SynthesizeOutputs& outputs) {
  using namespace synthesize_internal;
  using C = ModelCalls<M>;
  const std::string& tool = outputs.tool;
  Prepared<M> r;
  if (const std::string error = Prepare(model, request, &r); r.status != 0) {
    if (r.status == tools::kExitUsage) return tools::UsageError(tool, error);
    std::cerr << (r.tool_line ? tool + ": error: " : std::string()) << error << "\n";
    return r.status;
  }
  switch (r.kind) {
    case Kind::kMotion:
      return MotionMain(model, tool, request, r);
    case Kind::kExact:
      return ExactMain(model, tool, request, r);
    case Kind::kFunction:
      if constexpr (mechgen::HasDesignDerivatives<M>::value) return FunctionMain(model, tool, request, r);
      break;
    case Kind::kPath:
      if constexpr (C::kView || mechgen::HasDesignDerivatives<M>::value) return PathMain(model, tool, request, r);
      break;
  }
  return 1;  // (not reached: Prepare refuses a function or path task on a model without design derivatives)
}

}  // namespace mechgen::analysis
