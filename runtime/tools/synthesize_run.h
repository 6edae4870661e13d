// The synthesize command's model-dependent part, RunSynthesize(model, arguments, argv0): one
// source for the per-model tool <model>_synthesize (synthesize_main.cc, M the generated model's
// type, fixed sizes) and for the runtime instantiated once for the model view (M =
// mechgen::ViewModel; mechgen_view synthesize, the synthesis layer's view instantiation in
// runtime/view/synthesis.cc, synthesis/view_synthesis.h). It reads the model only through
// ModelCalls<M> where the synthesis layer does. What each kind does, what it writes and the
// exit statuses: synthesize_main.cc.
//
// Through the view: path generation and motion generation beyond five poses (the local stage's
// and the least squares' Jacobian from the view's design derivatives), motion generation (the
// Burmester pairs; four poses the curves), exact path synthesis (`kind: exact`) and function
// generation (synthesis/function.h: its Levenberg-Marquardt Jacobian from the view's design
// derivatives), with --params/--set on the view's parameter table (common/view_params.h).
#pragma once

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/view_params.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/synthesis/exact.h"
#include "mechgen/synthesis/function.h"
#include "mechgen/synthesis/motion.h"
#include "mechgen/synthesis/projection.h"
#include "mechgen/synthesis/report.h"
#include "mechgen/synthesis/task.h"
#include "synthesize_args.h"

namespace mechgen::synthesize_tool {
namespace run_internal {

namespace fs = std::filesystem;
using namespace mechgen::synthesis;


inline bool WriteWhole(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
  out.close();
  return static_cast<bool>(out);
}

// The model file's text into *text; false, with the error printed, when it cannot be read.
inline bool ReadModelText(const std::string& tool, const std::string& path, std::string* text) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  if (!in) {
    std::cerr << tool << ": error: cannot read the model file " << path << "\n";
    return false;
  }
  *text = bytes.str();
  return true;
}

// A task file's reading or binding: false, with its error (file:line:column) printed, when it failed.
inline bool TaskOk(bool ok, const std::string& error) {
  if (!ok) std::cerr << error << "\n";
  return ok;
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

// Function generation (synthesis/function.h): writes the model file, function.svg, report.txt.
template <class M>
int FunctionMain(const M& model, const std::string& tool, const std::string& task_path, const std::string& model_path,
                 const std::string& out_dir, unsigned long long seed, int threads, long long evaluations,
                 const typename ModelTypes<M>::Params& base) {
  using C = ModelCalls<M>;
  std::string error;
  FunctionTask task;
  if (!TaskOk(ParseFunctionTask(task_path, &task, &error), error)) return 1;
  if (evaluations > 0) task.search.evaluations = evaluations;
  BoundFunction<M> bound;
  if (!TaskOk(BindFunctionTask(model, task, base, &bound, &error), error)) return 1;
  std::string model_text;
  if (!ReadModelText(tool, model_path, &model_text)) return 1;
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
int MotionMain(const M& model, const std::string& tool, const std::string& task_path, const std::string& model_path,
               const std::string& out_dir, const typename ModelTypes<M>::Params& base) {
  using C = ModelCalls<M>;
  std::string error;
  MotionTask task;
  if (!TaskOk(ParseMotionTask(task_path, &task, &error), error)) return 1;
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
    if (!ReadModelText(tool, model_path, &model_text)) return 1;
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

// Nine points, pivots free (synthesis/nine_point.h, exact.h): solutions.csv (every real
// four-bar), report.txt and four_bar_NNNN.svg for each defect-free one (NNNN its solution).
inline int NinePointMain(const std::string& tool, const ExactTask& task, const std::string& model_name,
                         const std::string& task_path, const std::string& out_dir, int threads) {
  std::cerr << tool << ": exact path synthesis, nine points: monodromy (1442 classes for generic points), "
            << threads << " thread(s)\n";
  const NinePointRun run = RunNinePointTask(task, threads);
  const std::string report = NinePointReport(run), csv = NinePointCsv(run, model_name, task_path);
  std::vector<std::pair<fs::path, const std::string*>> files;
  for (const auto& d : run.drawings) files.emplace_back(fs::path(out_dir) / d.first, &d.second);
  files.emplace_back(fs::path(out_dir) / "solutions.csv", &csv);
  files.emplace_back(fs::path(out_dir) / "report.txt", &report);
  if (!WriteAll(files, out_dir)) {
    std::cerr << tool << ": error: cannot write into " << out_dir << "\n";
    return 1;
  }
  std::cout << report << "\nwrote " << run.drawings.size() << " drawing(s), " << (fs::path(out_dir) / "solutions.csv").string()
            << ", " << (fs::path(out_dir) / "report.txt").string() << "\n";
  if (!run.complete) std::cerr << tool << ": warning: the solution set is INCOMPLETE (report.txt)\n";
  return 0;
}

// Exact path synthesis (`synthesis: path`, `kind: exact`; synthesis/exact.h): every isolated
// solution of five points with both pivots given; each real one as a model file
// (<model>_exact_NN.yaml, NN its row in solutions.csv), solutions.csv and report.txt. Nine
// points without pivots: NinePointMain.
template <class M>
int ExactMain(const M& model, const std::string& tool, const std::string& task_path, const std::string& model_path,
              const std::string& out_dir, const typename ModelTypes<M>::Params& base, int threads) {
  std::string error;
  ExactTask task;
  if (!TaskOk(ParseExactTask(task_path, &task, &error), error)) return 1;
  BoundExact<M> bound;
  if (!TaskOk(BindExactTask(model, task, base, &bound, &error), error)) return 1;
  if (task.nine) return NinePointMain(tool, task, ModelCalls<M>::Name(model), task_path, out_dir, threads);
  std::string model_text;
  if (!ReadModelText(tool, model_path, &model_text)) return 1;
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
// report.txt.
template <class M>
int PathMain(const M& model, const std::string& tool, const std::string& task_path, const std::string& model_path,
             const std::string& out_dir, unsigned long long seed, int threads, long long evaluations,
             const typename ModelTypes<M>::Params& base) {
  using C = ModelCalls<M>;
  std::string error;
  PathTask task;
  if (!TaskOk(ParseTask(task_path, &task, &error), error)) return 1;
  if (evaluations > 0) task.search.evaluations = evaluations;
  BoundPath<M> bound;
  if (!TaskOk(BindPathTask(model, task, base, &bound, &error), error)) return 1;
  std::string model_text;
  if (!ReadModelText(tool, model_path, &model_text)) return 1;
  if constexpr (C::kView || mechgen::HasDesignDerivatives<M>::value) {
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
  } else {
    std::cerr << tool << ": error: the model '" << C::Name(model)
              << "' has no `design` section; add `design: [parameters to vary]` (models/README.md)\n";
    return 1;
  }
}

}  // namespace run_internal

/**
 * \brief The synthesize command on `model` with the parsed `arguments` (synthesize_args.h).
 * \tparam M    A generated model (the per-model tool) or mechgen::ViewModel.
 * \param argv0 The program's argv[0]: `mechgen synthesize MODEL` names the model file when
 *              --model does not.
 * \return The exit status (synthesize_main.cc).
 */
template <class M>
int RunSynthesize(const M& model, const Arguments& arguments, const std::string& argv0) {
  using namespace run_internal;
  using C = ModelCalls<M>;
  const char* const name = C::Name(model);
  const std::string& tool = arguments.tool;
  const std::string& task_path = arguments.task_path;
  const std::string& out_dir = arguments.out_dir;
  std::string model_path = arguments.model_path;
  const unsigned long long seed = arguments.seed;
  const int threads = arguments.threads;
  const long long evaluations = arguments.evaluations;
  const mechgen::tools::ParameterOptions& parameter_options = arguments.params;
  const std::string prefix = "mechgen synthesize ";
  if (model_path.empty() && argv0.rfind(prefix, 0) == 0) model_path = argv0.substr(prefix.size());
  if (model_path.empty()) return mechgen::tools::UsageError(tool, "--model: the model file is needed (run as `mechgen synthesize MODEL ...`)");

  using Params = typename ModelTypes<M>::Params;
  Params base = C::DefaultParams(model);
  std::string error;
  if (!mechgen::tools::ApplyModelParameters(parameter_options, model, &base, &error))
    return mechgen::tools::UsageError(tool, error);
  const std::string kind = TaskKind(task_path, &error);
  if (!error.empty()) {
    std::cerr << error << "\n";
    return 1;
  }
  if (kind == "motion") {
    if (C::NumPoints(model) > 0) {
      return MotionMain(model, tool, task_path, model_path, out_dir, base);
    } else {
      std::cerr << task_path << ": error: the model '" << name << "' has no output points (the pose's point)\n";
      return 1;
    }
  }
  const bool exact = kind == "path" && PathTaskKind(task_path, &error) == "exact";
  if (exact) {
    if (C::NumPoints(model) > 0 && C::Nq(model) == 1) {
      return ExactMain(model, tool, task_path, model_path, out_dir, base, threads);
    } else {
      std::cerr << task_path << ": error: kind: exact needs a four-bar model with one input and the coupler point among "
                << "its outputs; '" << name << "' is not one\n";
      return 1;
    }
  }
  if (kind == "function") {
    if constexpr (mechgen::HasDesignDerivatives<M>::value) {
      if (C::HasDesign(model))
        return FunctionMain(model, tool, task_path, model_path, out_dir, seed, threads, evaluations, base);
    }
    std::cerr << task_path << ": error: the model '" << name
              << "' has no `design` section; add `design: [parameters to vary]` (models/README.md)\n";
    return 1;
  }
  return PathMain(model, tool, task_path, model_path, out_dir, seed, threads, evaluations, base);
}

}  // namespace mechgen::synthesize_tool
