/**
 * \file synthesis/function.h
 * Function generation (issue 28) on a generated one-input model with a `design` section: the
 * output angle phi_out (one of the model's dependent variables, e.g. theta_rocker) is to be
 * psi_i when the input is q_i, for the task's pairs (q_i, psi_i), both absolute angles in the
 * model's frame.
 *
 * The stages:
 *  1. Exact where it exists: when the task names the four-bar's links (`freudenstein:
 *     {crank, coupler, rocker, ground}`, the model's ground line along +x as in
 *     models/fourbar.yaml), Freudenstein's equation (synthesis/freudenstein.h) gives the crank,
 *     coupler and rocker for the ground's current length: three pairs exactly, more in the
 *     least-squares sense of the equation (not of the angles).
 *  2. Levenberg–Marquardt (Ceres) on the angle residuals r_i = phi_out(q_i; p) - psi_i
 *     (wrapped into (-pi, pi]) over the task's variables within their bounds, its Jacobian the
 *     generated dphi/dp (EvalDesignDerivatives: no automatic or numerical differentiation),
 *     from the exact start (if any), from the model's values and from Search::restarts
 *     uniform starts in the bounds (one splitmix64 stream per start: the result depends only on
 *     the seed; a start where the model does not assemble at every pair is only checked). This
 *     is the general case (any model; more pairs than the exact method fits).
 *  3. Every candidate checked: the model assembles on its mode at every pair, and from pair to
 *     pair (in the task's order, the input moving directly from q_i to q_i+1, sampled at
 *     Search::curve_samples per turn) it stays on that mode with a nonzero branch measure: no
 *     dead point, no branch change between the pairs. The best is chosen by Deb's rule
 *     (feasible first, then the error E = sum r_i^2, rad^2; ties to the earlier start).
 * Counting: one residual evaluation = 1 evaluation, one Jacobian = 1 + the number of variables.
 */
#pragma once

#include <algorithm>
#include <array>
#include <limits>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <yaml-cpp/yaml.h>

#include "mechgen/core/model_traits.h"
#include "mechgen/position/design.h"
#include "mechgen/synthesis/freudenstein.h"
#include "mechgen/synthesis/output.h"
#include "mechgen/synthesis/path.h"
#include "mechgen/synthesis/random.h"
#include "mechgen/synthesis/task.h"

namespace mechgen::synthesis {

/// A function-generation task as written in its file (docs/synthesis.md).
struct FunctionTask {
  std::string file;
  std::string model;                     ///< `model:` relative to the task file, "" if not given
  std::string output;                    ///< the output angle: one of the model's phi names
  std::vector<double> input, psi;        ///< the pairs (q_i, psi_i), rad
  bool freudenstein = false;             ///< the exact start is asked for
  std::string crank, coupler, rocker, ground;  ///< its links' length parameters
  std::vector<Variable> variables;
  Search search;
  int output_line = 0, output_column = 0, freudenstein_line = 0, freudenstein_column = 0;
};

/// The `synthesis:` kind of a task file ("path", "function", ...), "" and *error if unreadable.
inline std::string TaskKind(const std::string& path, std::string* error) {
  std::ifstream in(path);
  if (!in) return *error = path + ": cannot read the task file", "";
  try {
    const YAML::Node root = YAML::Load(in);
    if (root.IsMap() && root["synthesis"] && root["synthesis"].IsScalar()) return root["synthesis"].Scalar();
    return "";  // ParseTask says what is missing
  } catch (const YAML::Exception& e) {
    *error = task_internal::Where(path, e.mark) + "not valid YAML: " + e.msg;
    return "";
  }
}

/// Reads a `synthesis: function` task; false and *error (FILE:LINE:COLUMN: what to change).
inline bool ParseFunctionTask(const std::string& path, FunctionTask* task, std::string* error) {
  using namespace task_internal;
  *task = FunctionTask();
  task->file = path;
  YAML::Node root;
  if (!LoadTaskRoot(path, "`synthesis: function`, `output`, `pairs`, `variables`", &root, error)) return false;
  try {
    Known(path, root, {"synthesis", "model", "output", "pairs", "freudenstein", "variables", "search"}, "a function task");
    const YAML::Node kind = Required(path, root, "synthesis", "the kind of task");
    if (!kind.IsScalar() || kind.Scalar() != "function") throw Error{Where(path, kind.Mark()) + "expected synthesis: function"};
    if (const YAML::Node m = root["model"]) {
      if (!m.IsScalar()) throw Error{Where(path, m.Mark()) + "model: expected a file name"};
      task->model = m.Scalar();
    }
    const YAML::Node out = Required(path, root, "output", "the output angle, one of the model's dependent variables (e.g. theta_rocker)");
    if (!out.IsScalar()) throw Error{Where(path, out.Mark()) + "output: expected a dependent variable's name such as theta_rocker"};
    task->output = out.Scalar();
    task->output_line = out.Mark().line + 1;
    task->output_column = out.Mark().column + 1;
    const YAML::Node pairs = Required(path, root, "pairs", "the (input, output) angle pairs, [[30deg, 95deg], ...]");
    if (!pairs.IsSequence() || pairs.size() < 2)
      throw Error{Where(path, pairs.Mark()) + "pairs: expected at least two [input, output] angle pairs"};
    for (const YAML::Node& pr : pairs) {
      if (!pr.IsSequence() || pr.size() != 2) throw Error{Where(path, pr.Mark()) + "a pair: expected [input angle, output angle]"};
      task->input.push_back(Number(path, pr[0], "input angle", true));
      task->psi.push_back(Number(path, pr[1], "output angle", true));
    }
    if (const YAML::Node f = root["freudenstein"]) {
      if (!f.IsMap()) throw Error{Where(path, f.Mark()) + "freudenstein: expected {crank: a, coupler: b, rocker: c, ground: d}"};
      Known(path, f, {"crank", "coupler", "rocker", "ground"}, "freudenstein");
      task->freudenstein = true;
      task->freudenstein_line = f.Mark().line + 1;
      task->freudenstein_column = f.Mark().column + 1;
      std::string* slots[4] = {&task->crank, &task->coupler, &task->rocker, &task->ground};
      const char* keys[4] = {"crank", "coupler", "rocker", "ground"};
      for (int k = 0; k < 4; ++k) {
        const YAML::Node v = Required(path, f, keys[k], "the parameter that is this link's length");
        if (!v.IsScalar()) throw Error{Where(path, v.Mark()) + "freudenstein." + keys[k] + ": expected a parameter name"};
        *slots[k] = v.Scalar();
      }
      if (task->input.size() < 3)
        throw Error{Where(path, f.Mark()) + "freudenstein: needs at least three pairs"};
    }
    ReadVariables(path, root, "{a: [0.1, 10], ...}", &task->variables);
    if (task->freudenstein) {
      for (const std::string* link : {&task->crank, &task->coupler, &task->rocker}) {
        bool found = false;
        for (const Variable& v : task->variables) found = found || v.name == *link;
        if (!found)
          throw Error{Where(path, root["freudenstein"].Mark()) + "freudenstein: '" + *link +
                      "' must be one of the variables (the exact method sets it)"};
      }
    }
    task->search.restarts = 8;
    if (const YAML::Node s = root["search"]) {
      if (!s.IsMap()) throw Error{Where(path, s.Mark()) + "search: expected a mapping"};
      Known(path, s, {"restarts", "curve_samples", "evaluations"}, "search (function task)");
      if (s["restarts"]) task->search.restarts = static_cast<int>(Count(path, s["restarts"], "restarts", 0, 10000));
      if (s["curve_samples"])
        task->search.curve_samples = static_cast<int>(Count(path, s["curve_samples"], "curve_samples", 8, 100000));
      if (s["evaluations"]) task->search.evaluations = Count(path, s["evaluations"], "evaluations", 100, 1000000000LL);
    }
  } catch (const Error& e) {
    *error = e.message;
    return false;
  } catch (const YAML::Exception& e) {
    *error = Where(path, e.mark) + e.msg;
    return false;
  }
  return true;
}

/// The angle in (-pi, pi].
inline double WrapPi(double a) {
  const double w = Wrap(a + M_PI) - M_PI;
  return w == -M_PI ? M_PI : w;
}

/// A function task bound to M.
template <class M>
struct BoundFunction {
  using Params = typename M::template ParamsT<double>;
  FunctionTask task;
  Params base;
  int n = 0;
  int output = -1;            ///< index in M::kPhiNames
  std::vector<int> column;    ///< each variable's column in M::kDesignNames
};

template <class M>
bool BindFunctionTask(const FunctionTask& task, const typename M::template ParamsT<double>& base, BoundFunction<M>* out,
                      std::string* error) {
  auto where = [&](int line, int column) { return bind_internal::Where(task.file, line, column); };
  auto list = [](const auto& names) { return bind_internal::List(names); };
  BoundFunction<M> b;
  b.task = task;
  b.base = base;
  b.n = static_cast<int>(task.input.size());
  if constexpr (!HasDesignDerivatives<M>::value) {
    *error = task.file + ": the model '" + std::string(M::kName) +
             "' has no `design` section; add `design: [parameters to vary]` to it (models/README.md)";
    return false;
  } else {
    if constexpr (M::kNq != 1) {
      *error = task.file + ": function generation needs a one-input model ('" + std::string(M::kName) + "' has " +
               std::to_string(M::kNq) + " inputs)";
      return false;
    }
    for (int i = 0; i < M::kNphi; ++i)
      if (task.output == M::kPhiNames[static_cast<size_t>(i)]) b.output = i;
    if (b.output < 0) {
      *error = where(task.output_line, task.output_column) + "output '" + task.output +
               "' is not one of the model's dependent variables (" + list(M::kPhiNames) + ")";
      return false;
    }
    if (!bind_internal::BindVariables<M>(task.file, task.variables, &b.column, error)) return false;
    if (task.freudenstein) {
      typename M::template ParamsT<double> p = base;
      for (const std::string& name : {task.crank, task.coupler, task.rocker, task.ground})
        if (p.Find(name.c_str()) == nullptr) {
          *error = where(task.freudenstein_line, task.freudenstein_column) + "freudenstein: no parameter '" + name +
                   "' in the model (parameters: " + list(M::template ParamsT<double>::kNames) + ")";
          return false;
        }
    }
    *out = b;
    return true;
  }
}

/// A function-generation candidate.
struct FunctionCandidate {
  std::vector<double> x;          ///< the variables
  std::vector<double> residual;   ///< phi_out(q_i) - psi_i, wrapped (rad); NaN where it does not assemble
  double error = kInf;            ///< sum of squared residuals (rad^2)
  double violation = kInf;        ///< 0: no defect
  std::string defect;
  std::string start;              ///< where the local stage started (freudenstein, model, random k)
  bool feasible() const { return violation == 0; }
};

/// Evaluates and checks function candidates (counts what it did).
template <class M>
class FunctionEvaluator {
 public:
  using Params = typename M::template ParamsT<double>;
  using VecQ = Eigen::Matrix<double, M::kNq, 1>;
  using VecPhi = Eigen::Matrix<double, M::kNphi, 1>;

  explicit FunctionEvaluator(const BoundFunction<M>& b) : b_(b) {}
  const BoundFunction<M>& bound() const { return b_; }
  long long evaluations = 0;
  long long solves = 0;

  Params ParamsOf(const std::vector<double>& x) const {
    Params p = b_.base;
    for (size_t j = 0; j < b_.task.variables.size(); ++j) *p.Find(b_.task.variables[j].name.c_str()) = x[j];
    return p;
  }

  /// phi at q on the model's mode; false where it does not assemble (or at a branch point).
  bool PhiAt(const Params& p, double q, VecPhi* phi) {
    ++solves;
    VecQ qv;
    qv(0) = q;
    VecPhi ph;
    for (int i = 0; i < M::kNphi; ++i) ph(i) = M::kAssemblyPhi[static_cast<size_t>(i)];
    const auto report = M::Solve(p, qv, &ph, M::kDefaultModes);
    using Status = decltype(report.status);
    if (report.status != Status::kConverged || !(report.branch_measure > 1e-12) || !ph.allFinite()) return false;
    *phi = ph;
    return true;
  }

  /// The residuals and the checks of x.
  FunctionCandidate Check(const std::vector<double>& x) {
    FunctionCandidate c;
    c.x = x;
    const Params p = ParamsOf(x);
    const FunctionTask& t = b_.task;
    double violation = 0;
    auto flag = [&](double amount, const std::string& what) {
      violation += amount;
      if (c.defect.empty()) c.defect = what;
    };
    c.error = 0;
    c.residual.assign(static_cast<size_t>(b_.n), std::numeric_limits<double>::quiet_NaN());
    VecPhi phi;
    for (int i = 0; i < b_.n; ++i) {
      if (!PhiAt(p, t.input[static_cast<size_t>(i)], &phi)) {
        flag(1.0, "pair " + std::to_string(i + 1) + ": the mechanism does not assemble on its mode at its input angle");
        continue;
      }
      const double r = WrapPi(phi(b_.output) - t.psi[static_cast<size_t>(i)]);
      c.residual[static_cast<size_t>(i)] = r;
      c.error += r * r;
    }
    const double step = kTwoPi / t.search.curve_samples;
    for (int i = 0; i + 1 < b_.n; ++i) {
      const double q0 = t.input[static_cast<size_t>(i)], q1 = t.input[static_cast<size_t>(i + 1)];
      const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(q1 - q0) / step)));
      for (int s = 1; s < steps; ++s) {
        if (!PhiAt(p, q0 + (q1 - q0) * s / steps, &phi)) {
          flag(1.0 / steps, "between pairs " + std::to_string(i + 1) + " and " + std::to_string(i + 2) +
                                ": the mechanism leaves its assembly mode (a dead point or no closure)");
        }
      }
    }
    c.violation = violation;
    return c;
  }

 private:
  const BoundFunction<M>& b_;
};

/// The angle residuals and their generated Jacobian (dphi_out/dp of the design section).
template <class M>
class FunctionResiduals : public ceres::CostFunction {
 public:
  explicit FunctionResiduals(FunctionEvaluator<M>* eval) : eval_(eval) {
    set_num_residuals(eval->bound().n);
    mutable_parameter_block_sizes()->push_back(static_cast<int32_t>(eval->bound().task.variables.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const BoundFunction<M>& b = eval_->bound();
    const int nv = static_cast<int>(b.task.variables.size());
    eval_->evaluations += (jacobians != nullptr && jacobians[0] != nullptr) ? 1 + nv : 1;
    const std::vector<double> x(parameters[0], parameters[0] + nv);
    const auto p = eval_->ParamsOf(x);
    typename FunctionEvaluator<M>::VecPhi phi;
    position::DesignOf<M> design;
    for (int i = 0; i < b.n; ++i) {
      const double q = b.task.input[static_cast<size_t>(i)];
      if (!eval_->PhiAt(p, q, &phi)) return false;
      residuals[i] = WrapPi(phi(b.output) - b.task.psi[static_cast<size_t>(i)]);
      if (jacobians == nullptr || jacobians[0] == nullptr) continue;
      Eigen::Matrix<double, M::kNq, 1> qv;
      qv(0) = q;
      M::Design(p, qv, phi, &design);
      for (int j = 0; j < nv; ++j) jacobians[0][i * nv + j] = design.dphi_dp(b.output, b.column[static_cast<size_t>(j)]);
    }
    return true;
  }

 private:
  FunctionEvaluator<M>* eval_;
};

/// Levenberg–Marquardt from x within the variables' bounds; the refined point (unchecked).
template <class M>
std::vector<double> FunctionLocalStage(FunctionEvaluator<M>* eval, std::vector<double> x, int* iterations) {
  const BoundFunction<M>& b = eval->bound();
  const int nv = static_cast<int>(x.size());
  for (int j = 0; j < nv; ++j)
    x[static_cast<size_t>(j)] = std::clamp(x[static_cast<size_t>(j)], b.task.variables[static_cast<size_t>(j)].lo,
                                           b.task.variables[static_cast<size_t>(j)].hi);
  ceres::Problem problem;
  problem.AddResidualBlock(new FunctionResiduals<M>(eval), nullptr, x.data());
  for (int j = 0; j < nv; ++j) {
    problem.SetParameterLowerBound(x.data(), j, b.task.variables[static_cast<size_t>(j)].lo);
    problem.SetParameterUpperBound(x.data(), j, b.task.variables[static_cast<size_t>(j)].hi);
  }
  ceres::Solver::Options options;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 200;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-20;
  options.parameter_tolerance = 1e-16;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  *iterations = static_cast<int>(summary.iterations.size());
  return x;
}

/// What function synthesis did.
struct FunctionResult {
  FunctionCandidate best;
  std::vector<FunctionCandidate> starts;   ///< every local stage's result, in start order
  FreudensteinResult exact;                ///< the exact stage (ok false when not asked or refused)
  bool exact_asked = false;
  long long evaluations = 0, solves = 0;
  int iterations = 0;
};

/// The stages above; `seed` sets the random starts.
template <class M>
FunctionResult SynthesizeFunction(const BoundFunction<M>& b, uint64_t seed) {
  FunctionEvaluator<M> eval(b);
  FunctionResult r;
  const FunctionTask& t = b.task;
  const int nv = static_cast<int>(t.variables.size());
  std::vector<std::pair<std::string, std::vector<double>>> starts;
  std::vector<double> x0(static_cast<size_t>(nv));
  {
    auto p = b.base;
    for (int j = 0; j < nv; ++j) x0[static_cast<size_t>(j)] = *p.Find(t.variables[static_cast<size_t>(j)].name.c_str());
  }
  if (t.freudenstein) {
    r.exact_asked = true;
    auto p = b.base;
    r.exact = Freudenstein(t.input, t.psi, *p.Find(t.ground.c_str()));
    if (r.exact.ok) {
      std::vector<double> x = x0;
      for (int j = 0; j < nv; ++j) {
        const std::string& name = t.variables[static_cast<size_t>(j)].name;
        if (name == t.crank) x[static_cast<size_t>(j)] = r.exact.a;
        if (name == t.coupler) x[static_cast<size_t>(j)] = r.exact.b;
        if (name == t.rocker) x[static_cast<size_t>(j)] = r.exact.c;
      }
      starts.push_back({"freudenstein", x});
    }
  }
  starts.push_back({"model", x0});
  for (int k = 0; k < t.search.restarts; ++k) {
    SplitMix64 rng(seed, static_cast<uint64_t>(k));
    std::vector<double> x(static_cast<size_t>(nv));
    for (int j = 0; j < nv; ++j) {
      const Variable& v = t.variables[static_cast<size_t>(j)];
      x[static_cast<size_t>(j)] = v.lo + rng.Uniform() * (v.hi - v.lo);
    }
    starts.push_back({"random " + std::to_string(k + 1), x});
  }
  for (auto& s : starts) {  // every start inside the bounds (the answer must be)
    for (int j = 0; j < nv; ++j)
      s.second[static_cast<size_t>(j)] = std::clamp(s.second[static_cast<size_t>(j)], t.variables[static_cast<size_t>(j)].lo,
                                                    t.variables[static_cast<size_t>(j)].hi);
  }
  for (const auto& s : starts) {
    // The start itself (the exact method's answer is kept as it is when it is best), then LM.
    FunctionCandidate at = eval.Check(s.second);
    at.start = s.first;
    // LM only from a start that assembles at every pair (its first evaluation needs them all).
    bool assembles = true;
    for (double e : at.residual) assembles = assembles && std::isfinite(e);
    FunctionCandidate refined;
    if (assembles) {
      int iterations = 0;
      refined = eval.Check(FunctionLocalStage(&eval, s.second, &iterations));
      refined.start = s.first + " + LM";
      r.iterations += iterations;
    }
    const FunctionCandidate& kept = assembles && Better(refined, at) ? refined : at;
    r.starts.push_back(kept);
    if (r.starts.size() == 1 || Better(kept, r.best)) r.best = kept;
  }
  r.evaluations = eval.evaluations;
  r.solves = eval.solves;
  return r;
}

/// The report: the stages, the residual per pair, the checks, the parameters.
template <class M>
std::string FunctionReport(const BoundFunction<M>& b, const FunctionResult& r, uint64_t seed) {
  const FunctionTask& t = b.task;
  std::string s = "# function generation: " + std::string(M::kName) + ", output " + t.output + ", " +
                  std::to_string(b.n) + " pairs (task " + t.file + ")\n";
  s += "seed " + std::to_string(seed) + ", local starts " + std::to_string(r.starts.size()) + ", evaluations " +
       std::to_string(r.evaluations) + ", position solves " + std::to_string(r.solves) + ", LM iterations " +
       std::to_string(r.iterations) + "\n";
  if (r.exact_asked) {
    if (r.exact.ok) {
      double worst = 0;
      for (double e : r.exact.residual) worst = std::max(worst, std::abs(e));
      s += "Freudenstein (" + std::string(b.n == 3 ? "exact, three pairs" : "least squares of the equation") + "): " +
           t.crank + " = " + Num(r.exact.a) + ", " + t.coupler + " = " + Num(r.exact.b) + ", " + t.rocker + " = " +
           Num(r.exact.c) + " (" + t.ground + " = " + Num(r.exact.d) + "); largest equation residual " + Short(worst) +
           "\n";
    } else {
      s += "Freudenstein: refused: " + r.exact.why + "\n";
    }
  }
  const FunctionCandidate& c = r.best;
  s += "best: from " + c.start + ", error (sum of squared angle residuals) " + Short(c.error, 9) + " rad^2\n";
  s += "defect checks: " + (c.feasible() ? std::string("none (every pair on the model's assembly mode, no dead point between pairs)")
                                         : c.defect) + "\n";
  s += "pair  input(deg)  target(deg)  residual(rad)\n";
  for (int i = 0; i < b.n; ++i)
    s += std::to_string(i + 1) + "  " + Short(t.input[static_cast<size_t>(i)] * 180 / M_PI, 10) + "  " +
         Short(t.psi[static_cast<size_t>(i)] * 180 / M_PI, 10) + "  " + Short(c.residual[static_cast<size_t>(i)], 6) + "\n";
  s += "parameters:";
  for (size_t j = 0; j < t.variables.size(); ++j) s += " " + t.variables[j].name + " = " + Num(c.x[j]);
  s += "\n";
  return s;
}

/// The output angle over the pairs' input range (a margin each side) against the pairs.
template <class M>
std::string FunctionSvg(FunctionEvaluator<M>* eval, const FunctionCandidate& c, int samples = 400) {
  const BoundFunction<M>& b = eval->bound();
  const FunctionTask& t = b.task;
  const auto p = eval->ParamsOf(c.x);
  double q0 = *std::min_element(t.input.begin(), t.input.end()), q1 = *std::max_element(t.input.begin(), t.input.end());
  const double pad = 0.1 * std::max(q1 - q0, 1e-3);
  q0 -= pad, q1 += pad;
  std::vector<std::vector<std::array<double, 2>>> pieces(1);
  double ymin = kInf, ymax = -kInf;
  typename FunctionEvaluator<M>::VecPhi phi;
  const double ref = t.psi[0];
  for (int k = 0; k <= samples; ++k) {
    const double q = q0 + (q1 - q0) * k / samples;
    if (!eval->PhiAt(p, q, &phi)) {
      if (!pieces.back().empty()) pieces.emplace_back();
      continue;
    }
    const double y = ref + WrapPi(phi(b.output) - ref);
    pieces.back().push_back({q, y});
    ymin = std::min(ymin, y), ymax = std::max(ymax, y);
  }
  for (double y : t.psi) ymin = std::min(ymin, y), ymax = std::max(ymax, y);
  const double w = 600, h = 400, m = 20;
  const double yspan = std::max(ymax - ymin, 1e-9);
  auto X = [&](double q) { return Short(m + (q - q0) / (q1 - q0) * w, 7); };
  auto Y = [&](double y) { return Short(m + (ymax - y) / yspan * h, 7); };
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Short(w + 2 * m) + "\" height=\"" +
                    Short(h + 2 * m) + "\">\n<title>" + std::string(M::kName) + ": " + t.output +
                    " against the input (curve), the task's pairs (circles)</title>\n";
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (const auto& piece : pieces) {
    if (piece.size() < 2) continue;
    svg += "<polyline fill=\"none\" stroke=\"#1f5fa8\" stroke-width=\"1.5\" points=\"";
    for (const auto& pt : piece) svg += X(pt[0]) + "," + Y(pt[1]) + " ";
    svg += "\"/>\n";
  }
  for (int i = 0; i < b.n; ++i)
    svg += "<circle cx=\"" + X(t.input[static_cast<size_t>(i)]) + "\" cy=\"" + Y(t.psi[static_cast<size_t>(i)]) +
           "\" r=\"5\" fill=\"none\" stroke=\"#c0392b\" stroke-width=\"1.5\"/>\n";
  svg += "</svg>\n";
  return svg;
}

}  // namespace mechgen::synthesis
