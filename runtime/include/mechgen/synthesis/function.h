/**
 * \file synthesis/function.h
 * Function generation (issue 28) on a generated one-input model with a `design` section: the
 * output angle phi_out (one of the model's dependent variables, e.g. theta_rocker) is to be
 * psi_i when the input is q_i, for the task's pairs (q_i, psi_i), both absolute angles in the
 * model's frame, or for a function y = f(x) over a range (`function:`): its accuracy points
 * (Chebyshev spacing by default) mapped linearly onto the input's and the output's spans, the
 * structural error over the whole range reported. With `free_start`, the input's and the
 * output's start angles are variables too (the spans stay; with pairs, the first pair's
 * angles), and with `free_start.parameters` they are written into the model's offset
 * parameters (FunctionModelParameters). `fit: minimax`: after the stages below, the Remez
 * exchange (MinimaxStage) equalises the structural error's extrema over the range.
 *
 * The stages:
 *  1. Exact where it exists: when the task names the four-bar's links (`freudenstein:
 *     {crank, coupler, rocker, ground}`, the model's ground line along +x as in
 *     models/fourbar.yaml), Freudenstein's equation (synthesis/freudenstein.h) gives the crank,
 *     coupler and rocker for the ground's current length: three pairs exactly, more in the
 *     least-squares sense of the equation (not of the angles); with free start angles also at
 *     a 12 x 12 grid of start angles (the best Search::local_starts of them are seeds).
 *  2. Levenberg–Marquardt (Ceres) on the angle residuals r_i = phi_out(q_i; p) - psi_i
 *     (wrapped into (-pi, pi]) over the variables within their bounds, its Jacobian the
 *     generated dphi/dp (EvalDesignDerivatives) and, for the free input start, dphi/dq (the
 *     coefficient K): no automatic or numerical differentiation. From the exact start(s) and
 *     the model's values.
 *  3. The global stage: Search::restarts runs of differential evolution (synthesis/optimize.h's
 *     DifferentialEvolution, Deb's rule), each its own splitmix64 stream from (seed, run) and an
 *     equal share of Search::evaluations, on `threads` threads (the result depends only on the
 *     seed), each run's best Search::local_starts refined by LM within its budget.
 *  Every candidate checked: the model assembles on its mode at every pair, and from pair to
 *  pair (the input moving directly from q_i to q_i+1, sampled at Search::curve_samples per
 *  turn) it stays on that mode with a nonzero branch measure (no dead point, no branch change);
 *  the path tasks' constraints (synthesis/path.h CheckParameterConstraints; the transmission
 *  angle over that motion, or the full turn when the crank must turn fully). The best by Deb's
 *  rule (feasible first, then the error E = sum r_i^2, rad^2; ties to the earlier start).
 * Counting: one candidate checked = 1 evaluation, one residual evaluation = 1, one Jacobian =
 * 1 + the number of variables.
 */
#pragma once

#include <algorithm>
#include <array>
#include <limits>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SVD>
#include <ceres/cost_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <yaml-cpp/yaml.h>

#include "mechgen/core/model_traits.h"
#include "mechgen/position/design.h"
#include "mechgen/synthesis/expression.h"
#include "mechgen/synthesis/freudenstein.h"
#include "mechgen/synthesis/optimize.h"
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
  std::vector<double> input, psi;        ///< the pairs (q_i, psi_i), rad, at the given start angles
  bool freudenstein = false;             ///< the exact start is asked for
  std::string crank, coupler, rocker, ground;  ///< its links' length parameters
  std::vector<Variable> variables;
  Search search;
  int output_line = 0, output_column = 0, freudenstein_line = 0, freudenstein_column = 0;
  // A function over a range (`function:`): y = f(x) on [x0, x1], the input angle
  // in_start + in_span (x - x0) / (x1 - x0), the output angle out_start + out_span (y - y0) /
  // (y1 - y0), y0 = f(x0), y1 = f(x1); the accuracy points x_i (Chebyshev or uniform) give the
  // pairs above.
  bool range = false;
  std::string expression;
  Expression f;
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  double in_start = 0, in_span = 0, out_start = 0, out_span = 0;
  std::vector<double> x;                 ///< the accuracy points
  bool chebyshev = true;
  int samples = 200;                     ///< the structural error's check: samples + 1 points over the range
  /// `fit: range`: the residuals are the structural error at the samples + 1 points (input and
  /// psi hold those; the accuracy points stay in x, exact_input, exact_psi for Freudenstein's
  /// seeds); `fit: points` (the default): at the accuracy points.
  bool fit_range = false;
  /// `fit: minimax`: fitted at the accuracy points (as `points`), then the Remez exchange
  /// (MinimaxStage) equalises the structural error's extrema over the range.
  bool fit_minimax = false;
  std::vector<double> exact_input, exact_psi;  ///< the accuracy points' pairs (= input, psi unless fit_range)
  // Free start angles: in_start and out_start are variables within these bounds (the spans stay).
  bool free_start = false;
  double in_lo = 0, in_hi = 0, out_lo = 0, out_hi = 0;
  /// `free_start: {..., parameters: [alpha, beta]}`: the model's parameters that turn the
  /// crank's and the output link's points against their frames (the model's input and output
  /// angles read alpha and beta less than the links' lines); the start angles found are
  /// written into them, so that the model file alone meets the task's pairs.
  std::string in_offset, out_offset;
  int offset_line = 0, offset_column = 0;
  // Constraints (as path tasks; `order` excepted) and the input link they name.
  std::string crank_link;
  int crank_line = 0, crank_column = 0;
  Constraints constraints;
};

/// The `synthesis:` kind of a task file ("path", "function", ...), "" and *error if unreadable
/// (task_internal::ReadTaskText: no such file, a directory, not a regular file, too large) or
/// not YAML; "" without an error when the kind is missing (ParseTask says what is).
inline std::string TaskKind(const std::string& path, std::string* error) {
  std::string text;
  if (!task_internal::ReadTaskText(path, &text, error)) return "";
  try {
    const YAML::Node root = YAML::Load(text);
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
    Known(path, root,
          {"synthesis", "model", "output", "pairs", "function", "free_start", "freudenstein", "crank", "variables",
           "constraints", "search"},
          "a function task");
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
    if (root["pairs"] && root["function"])
      throw Error{Where(path, root["function"].Mark()) + "give either pairs: or function:, not both"};
    if (const YAML::Node fn = root["function"]) {
      if (!fn.IsMap())
        throw Error{Where(path, fn.Mark()) + "function: expected {expression: \"log10(x)\", x: [1, 2], input: [a, b], output: [c, d], points: 3}"};
      Known(path, fn, {"expression", "x", "input", "output", "points", "spacing", "samples", "fit"}, "function");
      task->range = true;
      const YAML::Node ex = Required(path, fn, "expression", "y as a function of x, e.g. \"log10(x)\"");
      if (!ex.IsScalar()) throw Error{Where(path, ex.Mark()) + "function.expression: expected an expression in x"};
      task->expression = ex.Scalar();
      int column = 0;
      std::string what;
      if (!task->f.Parse(task->expression, &column, &what)) {
        // The column within the file: the scalar's own column (+1 past an opening quote).
        const bool quoted = ex.Tag() == "!" ;
        YAML::Mark m = ex.Mark();
        m.column += column - 1 + (quoted ? 1 : 0);
        throw Error{Where(path, m) + "function.expression: " + what};
      }
      Pair(path, Required(path, fn, "x", "the range of x, [x0, x1]"), "function.x", false, &task->x0, &task->x1);
      double a = 0, b = 0;
      Pair(path, Required(path, fn, "input", "the input angle at x0 and at x1, e.g. [90deg, 150deg]"), "function.input", true,
           &a, &b, false);
      task->in_start = a, task->in_span = b - a;
      Pair(path, Required(path, fn, "output", "the output angle at f(x0) and at f(x1), e.g. [20deg, 80deg]"), "function.output",
           true, &a, &b, false);
      task->out_start = a, task->out_span = b - a;
      if (task->in_span == 0) throw Error{Where(path, fn["input"].Mark()) + "function.input: the two angles must differ"};
      if (task->out_span == 0) throw Error{Where(path, fn["output"].Mark()) + "function.output: the two angles must differ"};
      const int n = static_cast<int>(Count(path, Required(path, fn, "points", "the number of accuracy points, e.g. 3"),
                                           "function.points", 2, 1000));
      if (const YAML::Node sp = fn["spacing"]) {
        if (!sp.IsScalar() || (sp.Scalar() != "chebyshev" && sp.Scalar() != "uniform"))
          throw Error{Where(path, sp.Mark()) + "function.spacing: expected chebyshev or uniform"};
        task->chebyshev = sp.Scalar() == "chebyshev";
      }
      if (fn["samples"]) task->samples = static_cast<int>(Count(path, fn["samples"], "function.samples", 2, 1000000));
      if (const YAML::Node fit = fn["fit"]) {
        if (!fit.IsScalar() || (fit.Scalar() != "points" && fit.Scalar() != "range" && fit.Scalar() != "minimax"))
          throw Error{Where(path, fit.Mark()) + "function.fit: expected points (the accuracy points), range (the "
                                                "structural error at every sample, least squares) or minimax (its "
                                                "largest over the range)"};
        task->fit_range = fit.Scalar() == "range";
        task->fit_minimax = fit.Scalar() == "minimax";
      }
      task->y0 = task->f(task->x0);
      task->y1 = task->f(task->x1);
      if (!std::isfinite(task->y0) || !std::isfinite(task->y1) || task->y0 == task->y1)
        throw Error{Where(path, ex.Mark()) + "function.expression: f(x0) and f(x1) must be finite and differ (they set the "
                                             "output's scale)"};
      for (int j = 1; j <= n; ++j) {
        const double xj = task->chebyshev
                              ? 0.5 * (task->x0 + task->x1) - 0.5 * (task->x1 - task->x0) * std::cos((2 * j - 1) * M_PI / (2 * n))
                              : task->x0 + (task->x1 - task->x0) * (j - 1) / (n - 1);
        const double yj = task->f(xj);
        if (!std::isfinite(yj))
          throw Error{Where(path, ex.Mark()) + "function.expression: f(" + std::to_string(xj) + ") is not finite"};
        task->x.push_back(xj);
        task->input.push_back(task->in_start + task->in_span * (xj - task->x0) / (task->x1 - task->x0));
        task->psi.push_back(task->out_start + task->out_span * (yj - task->y0) / (task->y1 - task->y0));
      }
      task->exact_input = task->input;
      task->exact_psi = task->psi;
      if (task->fit_range) task->input.clear(), task->psi.clear();
      for (int k = 0; k <= task->samples; ++k) {
        const double xk = task->x0 + (task->x1 - task->x0) * k / task->samples;
        const double yk = task->f(xk);
        if (!std::isfinite(yk))
          throw Error{Where(path, ex.Mark()) + "function.expression: f(" + std::to_string(xk) + ") is not finite on the range"};
        if (task->fit_range) {
          task->input.push_back(task->in_start + task->in_span * (xk - task->x0) / (task->x1 - task->x0));
          task->psi.push_back(task->out_start + task->out_span * (yk - task->y0) / (task->y1 - task->y0));
        }
      }
    } else {
      const YAML::Node pairs = Required(path, root, "pairs", "the (input, output) angle pairs, [[30deg, 95deg], ...] (or function:)");
      if (!pairs.IsSequence() || pairs.size() < 2)
        throw Error{Where(path, pairs.Mark()) + "pairs: expected at least two [input, output] angle pairs"};
      for (const YAML::Node& pr : pairs) {
        if (!pr.IsSequence() || pr.size() != 2) throw Error{Where(path, pr.Mark()) + "a pair: expected [input angle, output angle]"};
        task->input.push_back(Number(path, pr[0], "input angle", true));
        task->psi.push_back(Number(path, pr[1], "output angle", true));
      }
      task->exact_input = task->input;
      task->exact_psi = task->psi;
    }
    if (const YAML::Node fs = root["free_start"]) {
      // With pairs: the start angles are the first pair's; every pair keeps its angles'
      // differences from it (in_start, out_start the first pair's as written).
      if (!task->range) task->in_start = task->input[0], task->out_start = task->psi[0];
      if (!fs.IsMap()) throw Error{Where(path, fs.Mark()) + "free_start: expected {input: [min, max], output: [min, max]}"};
      Known(path, fs, {"input", "output", "parameters"}, "free_start");
      Pair(path, Required(path, fs, "input", "the start angle of the input's bounds, [min, max]"), "free_start.input", true,
           &task->in_lo, &task->in_hi);
      Pair(path, Required(path, fs, "output", "the start angle of the output's bounds, [min, max]"), "free_start.output", true,
           &task->out_lo, &task->out_hi);
      task->free_start = true;
      if (const YAML::Node pm = fs["parameters"]) {
        if (!pm.IsSequence() || pm.size() != 2 || !pm[0].IsScalar() || !pm[1].IsScalar())
          throw Error{Where(path, pm.Mark()) + "free_start.parameters: expected [input offset, output offset], two of "
                                               "the model's parameters (e.g. [alpha, beta])"};
        task->in_offset = pm[0].Scalar();
        task->out_offset = pm[1].Scalar();
        task->offset_line = pm.Mark().line + 1;
        task->offset_column = pm.Mark().column + 1;
      }
    }
    if (const YAML::Node c = root["crank"]) {
      if (!c.IsScalar()) throw Error{Where(path, c.Mark()) + "crank: expected the input link's name"};
      task->crank_link = c.Scalar();
      task->crank_line = c.Mark().line + 1;
      task->crank_column = c.Mark().column + 1;
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
      if (task->exact_input.size() < 3)
        throw Error{Where(path, f.Mark()) + "freudenstein: needs at least three pairs (accuracy points)"};
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
    if (const YAML::Node cons = root["constraints"])
      ReadConstraints(path, cons, !task->crank_link.empty(), /*free_timing=*/false, &task->constraints);
    task->search.restarts = 8;
    if (const YAML::Node s = root["search"]) ReadSearch(path, s, /*function_task=*/true, &task->search);
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
  using Params = typename ModelTypes<M>::Params;
  const M* model = nullptr;   ///< reached through ModelCalls<M> (a generated model, or the model view); outlives this
  FunctionTask task;
  Params base;
  int n = 0;
  int output = -1;            ///< index in the model's dependent variables (ModelCalls<M>::PhiName)
  std::vector<int> column;    ///< each variable's column in its design parameters (ModelCalls<M>::DesignName)
  int nv = 0;                 ///< design variables
  int nx = 0;                 ///< the vector searched: the design variables (+ the two start angles)
  ConstraintIndices checks;
  /// The bounds of the vector searched.
  std::vector<double> lo, hi;
};

template <class M>
bool BindFunctionTask(const M& model, const FunctionTask& task, const typename ModelTypes<M>::Params& base,
                      BoundFunction<M>* out, std::string* error) {
  using C = ModelCalls<M>;
  auto where = [&](int line, int column) { return bind_internal::Where(task.file, line, column); };
  auto parameters = [&]() {
    return bind_internal::List(C::NumFreeParameters(model), [&](int i) { return C::FreeParameterName(model, i); });
  };
  BoundFunction<M> b;
  b.model = &model;
  b.task = task;
  b.base = base;
  b.n = static_cast<int>(task.input.size());
  const std::string no_design = task.file + ": error: the model '" + std::string(C::Name(model)) +
                                "' has no `design` section; add `design: [parameters to vary]` to it (models/README.md)";
  if constexpr (!HasDesignDerivatives<M>::value) {
    *error = no_design;
    return false;
  } else {
    if (!C::HasDesign(model)) {
      *error = no_design;
      return false;
    }
    if (C::Nq(model) != 1) {
      *error = task.file + ": error: function generation needs a one-input model ('" + std::string(C::Name(model)) +
               "' has " + std::to_string(C::Nq(model)) + " inputs)";
      return false;
    }
    for (int i = 0; i < C::Nphi(model); ++i)
      if (task.output == C::PhiName(model, i)) b.output = i;
    if (b.output < 0) {
      *error = where(task.output_line, task.output_column) + "output '" + task.output +
               "' is not one of the model's dependent variables (" +
               bind_internal::List(C::Nphi(model), [&](int i) { return C::PhiName(model, i); }) + ")";
      return false;
    }
    if (!bind_internal::BindVariables(model, task.file, task.variables, &b.column, error)) return false;
    if (task.freudenstein) {
      typename ModelTypes<M>::Params p = base;
      for (const std::string& name : {task.crank, task.coupler, task.rocker, task.ground})
        if (C::FindParameter(model, &p, name.c_str()) == nullptr) {
          *error = where(task.freudenstein_line, task.freudenstein_column) + "freudenstein: no parameter '" + name +
                   "' in the model (parameters: " + parameters() + ")";
          return false;
        }
    }
    if (!BindConstraints(model, task.file, task.constraints, task.crank_link, task.crank_line, task.crank_column,
                         &b.checks, error))
      return false;
    if (!task.in_offset.empty()) {
      typename ModelTypes<M>::Params p = base;
      for (const std::string& name : {task.in_offset, task.out_offset}) {
        if (C::FindParameter(model, &p, name.c_str()) == nullptr) {
          *error = where(task.offset_line, task.offset_column) + "free_start.parameters: no parameter '" + name +
                   "' in the model (parameters: " + parameters() + ")";
          return false;
        }
        for (const Variable& v : task.variables)
          if (v.name == name) {
            *error = where(task.offset_line, task.offset_column) + "free_start.parameters: '" + name +
                     "' is one of the variables; the start angles set it (remove it from variables:)";
            return false;
          }
      }
      if (task.in_offset == task.out_offset) {
        *error = where(task.offset_line, task.offset_column) + "free_start.parameters: the input's and the output's "
                 "offsets must be two different parameters";
        return false;
      }
    }
    b.nv = static_cast<int>(task.variables.size());
    b.nx = b.nv + (task.free_start ? 2 : 0);
    for (const Variable& v : task.variables) b.lo.push_back(v.lo), b.hi.push_back(v.hi);
    if (task.free_start) {
      b.lo.push_back(task.in_lo), b.hi.push_back(task.in_hi);
      b.lo.push_back(task.out_lo), b.hi.push_back(task.out_hi);
    }
    *out = b;
    return true;
  }
}
/// The same on a generated model's type (its one object, GeneratedModel<M>()).
template <class M>
bool BindFunctionTask(const FunctionTask& task, const typename M::template ParamsT<double>& base, BoundFunction<M>* out,
                      std::string* error) {
  return BindFunctionTask(GeneratedModel<M>(), task, base, out, error);
}

/// A function-generation candidate.
struct FunctionCandidate {
  std::vector<double> x;          ///< the variables (+ the input's and the output's start angle)
  std::vector<double> residual;   ///< phi_out(q_i) - psi_i, wrapped (rad); NaN where it does not assemble
  double error = kInf;            ///< sum of squared residuals (rad^2)
  double violation = kInf;        ///< 0: no defect
  std::string defect;
  std::string start;              ///< where it came from (freudenstein, model, run k; + LM)
  double mu_min = kInf, mu_max = -kInf;  ///< transmission angles over the checked motion (rad)
  bool feasible() const { return violation == 0; }
};

/// The structural error over a function task's range: the synthesized output against the
/// function's at samples + 1 evenly spaced x (function: tasks only).
struct StructuralError {
  double max_angle = kInf;   ///< max |phi_out - psi(x)| (rad)
  double max_y = kInf;       ///< the same in the function's units: max |y_mechanism(x) - f(x)|
  double at_x = 0;           ///< where the largest is
  int samples = 0;
  bool assembles = false;    ///< the mechanism assembles on its mode at every sample
  std::vector<double> xs, dy;  ///< every sample's x and y_mechanism - f(x)
};

/// Evaluates and checks function candidates (counts what it did).
template <class M>
class FunctionEvaluator {
 public:
  using C = ModelCalls<M>;
  using Params = typename ModelTypes<M>::Params;
  using VecQ = typename ModelTypes<M>::VecQ;
  using VecPhi = typename ModelTypes<M>::VecPhi;

  explicit FunctionEvaluator(const BoundFunction<M>& b) : b_(b), model_(*b.model) {}
  const BoundFunction<M>& bound() const { return b_; }
  const M& model() const { return model_; }
  long long evaluations = 0;
  long long solves = 0;

  Params ParamsOf(const std::vector<double>& x) const {
    Params p = b_.base;
    for (size_t j = 0; j < b_.task.variables.size(); ++j)
      *C::FindParameter(model_, &p, b_.task.variables[j].name.c_str()) = x[j];
    C::ParametersSet(model_, &p);
    return p;
  }
  /// The start angles of x (the task's when they are not free).
  double InStart(const std::vector<double>& x) const {
    return b_.task.free_start ? x[static_cast<size_t>(b_.nv)] : b_.task.in_start;
  }
  double OutStart(const std::vector<double>& x) const {
    return b_.task.free_start ? x[static_cast<size_t>(b_.nv + 1)] : b_.task.out_start;
  }
  /// The input angle of pair i and its target output angle, for the start angles of x.
  double Q(const std::vector<double>& x, int i) const {
    return b_.task.input[static_cast<size_t>(i)] - b_.task.in_start + InStart(x);
  }
  double Target(const std::vector<double>& x, int i) const {
    return b_.task.psi[static_cast<size_t>(i)] - b_.task.out_start + OutStart(x);
  }

  /// phi at q on the model's mode; false where it does not assemble or is singular (SolveOnMode).
  bool PhiAt(const Params& p, double q, VecPhi* phi) {
    ++solves;
    return SolveOnMode(model_, p, q, phi);
  }

  /// d phi_out / d x at (q, phi) into row[0..nx): the generated dphi/dp of the design
  /// variables and, for free start angles, K (the input's start moves q) and -1 (the output's).
  void JacobianRow(const Params& p, double q, const VecPhi& phi, double* row) const {
    VecQ qv;
    qv.resize(1);
    qv(0) = q;
    position::DesignOf<M> design;
    C::Design(model_, p, qv, phi, &design);
    for (int j = 0; j < b_.nv; ++j) row[j] = design.dphi_dp(b_.output, b_.column[static_cast<size_t>(j)]);
    if (b_.task.free_start) {
      typename ModelTypes<M>::Coefficients co;
      C::Coeffs(model_, p, qv, phi, &co);
      row[b_.nv] = co.K(b_.output, 0);
      row[b_.nv + 1] = -1.0;
    }
  }

  /// The output-angle error at xi of a function task's range, phi_out(in0 + in_span u) -
  /// (out0 + out_span v), u and v xi and f(xi) scaled to [0, 1] (rad); with `row` (nx
  /// entries) also its derivative in x. false where the mechanism does not assemble.
  bool RangeError(const Params& p, const std::vector<double>& x, double xi, double* e, double* row = nullptr) {
    const FunctionTask& t = b_.task;
    const double q = InStart(x) + t.in_span * ((xi - t.x0) / (t.x1 - t.x0));
    VecPhi phi;
    if (!PhiAt(p, q, &phi)) return false;
    *e = WrapPi(phi(b_.output) - (OutStart(x) + t.out_span * (t.f(xi) - t.y0) / (t.y1 - t.y0)));
    if (row != nullptr) JacobianRow(p, q, phi, row);
    return true;
  }

  /// The smallest and the largest of the model's transmission angles at input q (rad); false
  /// where it does not assemble on its mode or has no transmission angle.
  bool MuAt(const Params& p, double q, double* lo, double* hi) {
    VecPhi phi;
    if (C::NumTransmissionAngles(model_) == 0 || !PhiAt(p, q, &phi)) return false;
    VecQ qv;
    qv.resize(1);
    qv(0) = q;
    TransmissionAngleVector mu;
    C::TransmissionAngles(model_, p, qv, phi, &mu);
    *lo = kInf, *hi = -kInf;
    for (int k = 0; k < C::NumTransmissionAngles(model_); ++k) *lo = std::min(*lo, mu(k)), *hi = std::max(*hi, mu(k));
    return true;
  }

  /// The residuals and the checks of x (one evaluation).
  FunctionCandidate Check(const std::vector<double>& x) {
    ++evaluations;
    FunctionCandidate c;
    c.x = x;
    const Params p = ParamsOf(x);
    const FunctionTask& t = b_.task;
    double violation = 0;
    auto flag = [&](double amount, const std::string& what) {
      if (!(amount > 0)) return;
      violation += amount;
      if (c.defect.empty()) c.defect = what;
    };
    c.error = 0;
    c.residual.assign(static_cast<size_t>(b_.n), std::numeric_limits<double>::quiet_NaN());
    VecPhi phi;
    for (int i = 0; i < b_.n; ++i) {
      if (!PhiAt(p, Q(x, i), &phi)) {
        flag(1.0, "pair " + std::to_string(i + 1) + ": the mechanism does not assemble on its mode at its input angle");
        continue;
      }
      const double r = WrapPi(phi(b_.output) - Target(x, i));
      c.residual[static_cast<size_t>(i)] = r;
      c.error += r * r;
    }
    const bool full_turn = CheckParameterConstraints(model_, p, t.constraints, b_.checks, flag);
    // The motion: from pair to pair in the task's order (the input moving directly between
    // them), or the full turn when the crank must turn fully; transmission angles along it.
    const double step = kTwoPi / t.search.curve_samples;
    double mu_min = kInf, mu_max = -kInf;
    auto walk = [&](double q0, double q1, int from) {
      const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(q1 - q0) / step)));
      for (int s = 0; s <= steps; ++s) {
        const double q = q0 + (q1 - q0) * s / steps;
        if (!PhiAt(p, q, &phi)) {
          if (s > 0 && s < steps)
            flag(1.0 / steps, from < 0 ? "the crank does not turn fully on the assembly mode"
                                       : "between pairs " + std::to_string(from + 1) + " and " + std::to_string(from + 2) +
                                             ": the mechanism leaves its assembly mode (a dead point or no closure)");
          continue;
        }
        if (C::NumTransmissionAngles(model_) > 0 && t.constraints.has_mu) {
          VecQ qv;
          qv.resize(1);
          qv(0) = q;
          TransmissionAngleVector mu;
          C::TransmissionAngles(model_, p, qv, phi, &mu);
          for (int k = 0; k < C::NumTransmissionAngles(model_); ++k)
            mu_min = std::min(mu_min, mu(k)), mu_max = std::max(mu_max, mu(k));
        }
      }
    };
    if (full_turn) {
      walk(Q(x, 0), Q(x, 0) + kTwoPi, -1);
    } else {
      for (int i = 0; i + 1 < b_.n; ++i) walk(Q(x, i), Q(x, i + 1), i);
    }
    c.mu_min = mu_min, c.mu_max = mu_max;
    if (t.constraints.has_mu && std::isfinite(mu_min)) {
      flag(t.constraints.mu_lo - mu_min, "the transmission angle falls below its bound");
      flag(mu_max - t.constraints.mu_hi, "the transmission angle rises above its bound");
    }
    if (!std::isfinite(c.error) && violation == 0) flag(1.0, "the error is not finite");
    c.violation = violation;
    return c;
  }

  /// The structural error of x over the task's range (function: tasks; else assembles false).
  StructuralError Structural(const std::vector<double>& x) {
    StructuralError e;
    const FunctionTask& t = b_.task;
    if (!t.range) return e;
    const Params p = ParamsOf(x);
    e.max_angle = e.max_y = 0;
    e.assembles = true;
    e.samples = t.samples + 1;
    for (int k = 0; k <= t.samples; ++k) {
      const double xk = t.x0 + (t.x1 - t.x0) * k / t.samples;
      double da = 0;
      if (!RangeError(p, x, xk, &da)) {
        e.assembles = false;
        e.max_angle = e.max_y = kInf;
        return e;
      }
      const double dy = da * (t.y1 - t.y0) / t.out_span;
      e.xs.push_back(xk);
      e.dy.push_back(dy);
      if (std::abs(da) > e.max_angle) e.max_angle = std::abs(da), e.max_y = std::abs(dy), e.at_x = xk;
    }
    return e;
  }

 private:
  using TransmissionAngleVector =
      Eigen::Matrix<double, ModelFeatures<M>::kNumTransmissionAngles, 1, 0,
                    ModelFeatures<M>::kNumTransmissionAngles == Eigen::Dynamic ? ModelView::kMaxTransmissionAngles
                                                                              : ModelFeatures<M>::kNumTransmissionAngles,
                    1>;
  const BoundFunction<M>& b_;
  const M& model_;
};

/// The angle residuals and their generated Jacobian: dphi_out/dp of the design section and,
/// for free start angles, dphi_out/dq (the coefficient K) for the input's start, -1 for the
/// output's. `limit`: the count it may not pass (an evaluation that would is refused).
template <class M>
class FunctionResiduals : public ceres::CostFunction {
 public:
  explicit FunctionResiduals(FunctionEvaluator<M>* eval, long long limit = std::numeric_limits<long long>::max())
      : eval_(eval), limit_(limit) {
    set_num_residuals(eval->bound().n);
    mutable_parameter_block_sizes()->push_back(static_cast<int32_t>(eval->bound().nx));
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const BoundFunction<M>& b = eval_->bound();
    const int nx = b.nx;
    const long long cost = (jacobians != nullptr && jacobians[0] != nullptr) ? 1 + nx : 1;
    if (eval_->evaluations + cost > limit_) return false;
    eval_->evaluations += cost;
    const std::vector<double> x(parameters[0], parameters[0] + nx);
    const auto p = eval_->ParamsOf(x);
    typename FunctionEvaluator<M>::VecPhi phi;
    for (int i = 0; i < b.n; ++i) {
      const double q = eval_->Q(x, i);
      if (!eval_->PhiAt(p, q, &phi)) return false;
      residuals[i] = WrapPi(phi(b.output) - eval_->Target(x, i));
      if (jacobians != nullptr && jacobians[0] != nullptr) eval_->JacobianRow(p, q, phi, jacobians[0] + i * nx);
    }
    return true;
  }

 private:
  FunctionEvaluator<M>* eval_;
  long long limit_;
};

/// Levenberg–Marquardt from x within the bounds, at most max_evaluations (counted as above);
/// the refined point (unchecked).
template <class M>
std::vector<double> FunctionLocalStage(FunctionEvaluator<M>* eval, std::vector<double> x, int* iterations,
                                       long long max_evaluations = std::numeric_limits<long long>::max() / 4) {
  const BoundFunction<M>& b = eval->bound();
  const int nx = b.nx;
  for (int j = 0; j < nx; ++j)
    x[static_cast<size_t>(j)] = std::clamp(x[static_cast<size_t>(j)], b.lo[static_cast<size_t>(j)], b.hi[static_cast<size_t>(j)]);
  const long long limit = eval->evaluations + max_evaluations;
  ceres::Problem problem;
  problem.AddResidualBlock(new FunctionResiduals<M>(eval, limit), nullptr, x.data());
  for (int j = 0; j < nx; ++j) {
    problem.SetParameterLowerBound(x.data(), j, b.lo[static_cast<size_t>(j)]);
    problem.SetParameterUpperBound(x.data(), j, b.hi[static_cast<size_t>(j)]);
  }
  ceres::Solver::Options options = LocalSolverOptions();
  // Stop (keeping the best point so far) when less than two iterations' worth is left.
  EvaluationBudget<FunctionEvaluator<M>> budget;
  budget.evaluator = eval;
  budget.stop_at = limit - 2 * (2 + nx) - 1;
  options.callbacks.push_back(&budget);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  *iterations = static_cast<int>(summary.iterations.size());
  return x;
}

/// The minimax stage's result (`fit: minimax`): the Remez exchange from the accuracy points'
/// answer. Angles in rad of output; x in the function's variable.
struct MinimaxResult {
  bool asked = false;
  bool converged = false;      ///< the reference's |error| equal to 1e-9 relative
  bool used = false;           ///< its mechanism is the answer (no defect, a smaller largest error)
  std::string why;             ///< when not used or not converged
  int exchanges = 0;           ///< exchange steps (each a levelled solve and a new reference)
  int lawson = 0;              ///< Lawson's steps before the exchange (a seed with too few sign changes)
  int reference = 0;           ///< the reference's extrema: nx + 1, or fewer (a reduced exchange, below)
  int iterations = 0;          ///< LM iterations of the levelled (and Lawson's) solves
  double level = 0;            ///< |E| of the last levelled solve
  double start_max = kInf;     ///< the seed's largest |error| over the range (extrema located)
  double max_angle = kInf;     ///< the answer's largest |error| over the range (extrema located)
  std::vector<double> ref_x, ref_e;  ///< the answer's alternating extrema: x_k and error_k (rad)
  std::vector<double> zeros;   ///< where the answer's error crosses zero (its accuracy points)
  /// The constraints: when the equal-ripple answer breaks a parameter-only constraint (path.h
  /// CheckParameterConstraints: Grashof, the crank, link_ratio, link_lengths), the exchange again
  /// with that constraint active (ConstrainedExchange). `constraint`: its defect message.
  std::string constraint;
  bool constrained_converged = false;
  int active = 0;                   ///< how many constraints the last constrained exchange held (their messages `; `-joined)
  double unconstrained_max = kInf;  ///< the equal-ripple answer's largest |error| (rad), which breaks it
  /// Variables at a bound (issue 44): the exchange (LM within the bounds) ended on a bound with
  /// fewer extrema than the free variables ask for (nx + 1 - k for k bounds), so it was not a
  /// minimax on the bound's surface. Then the minimax within the bounds by sequential linear
  /// programming (BoundMinimax) and the exchange again with the bounds held as constraints
  /// (ConstrainedExchange: the equal ripple to 1e-9).
  bool bound_stage = false;       ///< the linear programs and that exchange ran
  std::string bounds;             ///< the bounds held (`; `-joined), empty when none
  double bound_start_max = kInf;  ///< the largest |error| (rad) where the exchange ended on them
  int bound_steps = 0;            ///< the linear programs' steps kept
  /// The last linear program's multipliers: of the extrema at its x (ref order, summing to 1;
  /// the KKT weights of sum_k w_k sigma_k grad e_k + sum_j mu_j n_j = 0), and of each variable's
  /// bound (mu_j: > 0 its upper bound, < 0 its lower; 0 when off it).
  std::vector<double> kkt_weights, bound_multipliers;
  /// One extremum fewer at the level than the free variables + 1 after the linear programs: the
  /// minimax along the curve where those stay equal (CurveMinimax), its secant steps, and
  /// whether the level's derivative along it reached zero (1e-8 of the level).
  bool curve = false, curve_converged = false;
  int curve_steps = 0;
  int bound_reference = 0;        ///< nx + 1 - k: the extrema of the exchange with them held
  bool bounds_converged = false;  ///< that exchange's extrema equal to 1e-9 relative
  std::string bound_why;          ///< why it did not converge
};

namespace function_internal {

/// The extrema of the range error of x: the samples + 1 even x split into runs of one sign, in
/// each the largest |error|, located by golden section between its neighbours (60 steps); false
/// where the mechanism does not assemble. *zeros: where the error changes sign (bisection).
template <class M>
bool RangeExtrema(FunctionEvaluator<M>* eval, const std::vector<double>& x, std::vector<double>* ex,
                  std::vector<double>* ee, std::vector<double>* zeros = nullptr) {
  const FunctionTask& t = eval->bound().task;
  const auto p = eval->ParamsOf(x);
  const int N = t.samples;
  auto xi = [&](int k) { return t.x0 + (t.x1 - t.x0) * k / N; };
  std::vector<double> e(static_cast<size_t>(N + 1));
  for (int k = 0; k <= N; ++k)
    if (!eval->RangeError(p, x, xi(k), &e[static_cast<size_t>(k)])) return false;
  ex->clear(), ee->clear();
  if (zeros != nullptr) zeros->clear();
  auto error_at = [&](double at, double* v) { return eval->RangeError(p, x, at, v); };
  int k = 0;
  while (k <= N) {
    const bool positive = e[static_cast<size_t>(k)] >= 0;
    int best = k, end = k;
    while (end <= N && (e[static_cast<size_t>(end)] >= 0) == positive) {
      if (std::abs(e[static_cast<size_t>(end)]) > std::abs(e[static_cast<size_t>(best)])) best = end;
      ++end;
    }
    // Golden section on |error| over [x_{best-1}, x_{best+1}] (within the range).
    double lo = xi(std::max(best - 1, 0)), hi = xi(std::min(best + 1, N));
    double at = xi(best), val = e[static_cast<size_t>(best)];
    const double g = 0.5 * (std::sqrt(5.0) - 1);
    double u = hi - g * (hi - lo), w = lo + g * (hi - lo), fu = 0, fw = 0;
    if (!error_at(u, &fu) || !error_at(w, &fw)) return false;
    for (int it = 0; it < 60; ++it) {
      if (std::abs(fu) > std::abs(fw)) {
        hi = w, w = u, fw = fu, u = hi - g * (hi - lo);
        if (!error_at(u, &fu)) return false;
      } else {
        lo = u, u = w, fu = fw, w = lo + g * (hi - lo);
        if (!error_at(w, &fw)) return false;
      }
    }
    for (const auto& [cx, cv] : {std::pair<double, double>{u, fu}, {w, fw}})
      if (std::abs(cv) > std::abs(val) && (cv >= 0) == positive) at = cx, val = cv;
    ex->push_back(at), ee->push_back(val);
    if (zeros != nullptr && end <= N) {  // the sign change between x_{end-1} and x_end
      double a = xi(end - 1), c = xi(end), fa = e[static_cast<size_t>(end - 1)];
      for (int it = 0; it < 60; ++it) {
        const double m = 0.5 * (a + c);
        double fm = 0;
        if (!error_at(m, &fm)) return false;
        if ((fm >= 0) == (fa >= 0)) a = m, fa = fm;
        else c = m;
      }
      zeros->push_back(0.5 * (a + c));
    }
    k = end;
  }
  return true;
}

inline const char* kMuBelow = "the transmission angle falls below its bound";
inline const char* kMuAbove = "the transmission angle rises above its bound";

/// The transmission angle's amount at x over the whole range the answer serves: mu_lo - min mu
/// (`below`) or max mu - mu_hi, the input from in0 to in0 + in_span (wider than Check's walk,
/// which goes from the first accuracy point to the last: meeting the bound here meets it
/// there), or the full turn when the crank must turn fully (crank_rotates, crank_shortest);
/// the extreme is the samples' (t.samples of them; 360 for the full turn) refined by golden
/// section between its neighbours (60 steps), so that the amount is a smooth function of x
/// where the extreme is inside (its derivative that of mu at a fixed input, the envelope) and
/// where it is at an end. NaN where the mechanism does not assemble on the way.
template <class M>
double TransmissionAmount(FunctionEvaluator<M>& eval, const std::vector<double>& x, bool below) {
  const BoundFunction<M>& b = eval.bound();
  const FunctionTask& t = b.task;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto p = eval.ParamsOf(x);
  const bool full_turn = CheckParameterConstraints(eval.model(), p, t.constraints, b.checks, [](double, const std::string&) {});
  const double q0 = eval.InStart(x), span = full_turn ? kTwoPi : t.in_span;
  const int N = full_turn ? 360 : std::max(t.samples, 2);
  // The signed extreme: min mu (below) or -max mu, so that the smallest is wanted either way.
  auto value = [&](double q, double* v) {
    double lo = 0, hi = 0;
    if (!eval.MuAt(p, q, &lo, &hi)) return false;
    *v = below ? lo : -hi;
    return true;
  };
  auto qi = [&](int k) { return q0 + span * k / N; };
  int best = 0;
  double vb = kInf;
  for (int k = 0; k <= N; ++k) {
    double v = 0;
    if (!value(qi(k), &v)) return nan;
    if (v < vb) vb = v, best = k;
  }
  if (full_turn || (best > 0 && best < N)) {
    const double g = 0.5 * (std::sqrt(5.0) - 1);
    double lo = qi(best - 1), hi = qi(best + 1), u = hi - g * (hi - lo), w = lo + g * (hi - lo), fu = 0, fw = 0;
    if (!value(u, &fu) || !value(w, &fw)) return nan;
    for (int it = 0; it < 60; ++it) {
      if (fu < fw) {
        hi = w, w = u, fw = fu, u = hi - g * (hi - lo);
        if (!value(u, &fu)) return nan;
      } else {
        lo = u, u = w, fu = fw, w = lo + g * (hi - lo);
        if (!value(w, &fw)) return nan;
      }
    }
    vb = std::min({vb, fu, fw});
  }
  return below ? t.constraints.mu_lo - vb : -vb - t.constraints.mu_hi;
}

/// The name of variable j of the vector searched: a design variable's, or a start angle's.
template <class M>
std::string VariableName(const BoundFunction<M>& b, int j) {
  if (j < b.nv) return b.task.variables[static_cast<size_t>(j)].name;
  return j == b.nv ? "the input's start angle" : "the output's start angle";
}

/// A variable at its bound as a constraint of the exchange (its message; its amount x_j - hi_j or
/// lo_j - x_j, ConstraintAmount).
template <class M>
std::string BoundMessage(const BoundFunction<M>& b, int j, bool upper) {
  return VariableName(b, j) + " at its " + (upper ? "upper" : "lower") + " bound";
}

/// The signed amount of the constraint `what` at x (the amount its flag gets: > 0 broken, <= 0
/// met): a variable's bound (BoundMessage: exactly linear), a parameter-only one (path.h
/// CheckParameterConstraints) or the transmission angle's bounds over the range
/// (TransmissionAmount); NaN when no constraint by that message is checked.
template <class M>
double ConstraintAmount(FunctionEvaluator<M>& eval, const std::vector<double>& x, const std::string& what) {
  const BoundFunction<M>& b = eval.bound();
  for (int j = 0; j < b.nx; ++j)
    for (bool upper : {false, true})
      if (what == BoundMessage(b, j, upper)) {
        const size_t i = static_cast<size_t>(j);
        return upper ? x[i] - b.hi[i] : b.lo[i] - x[i];
      }
  if (what == kMuBelow || what == kMuAbove)
    return b.task.constraints.has_mu ? TransmissionAmount(eval, x, what == kMuBelow)
                                     : std::numeric_limits<double>::quiet_NaN();
  double amount = std::numeric_limits<double>::quiet_NaN();
  CheckParameterConstraints(eval.model(), eval.ParamsOf(x), b.task.constraints, b.checks, [&](double a, const std::string& w) {
    if (w == what && !(amount > a)) amount = a;  // the largest when flagged twice
  });
  return amount;
}

/// The first constraint the minimax stage sees that x breaks (its message), empty when none:
/// the parameter-only ones, then the transmission angle's bounds over the range.
template <class M>
std::string BrokenConstraint(FunctionEvaluator<M>& eval, const std::vector<double>& x) {
  const BoundFunction<M>& b = eval.bound();
  std::string broken;
  CheckParameterConstraints(eval.model(), eval.ParamsOf(x), b.task.constraints, b.checks, [&](double a, const std::string& w) {
    if (a > 0 && broken.empty()) broken = w;
  });
  if (broken.empty() && b.task.constraints.has_mu && ModelCalls<M>::NumTransmissionAngles(eval.model()) > 0) {
    for (const char* what : {kMuBelow, kMuAbove}) {
      const double a = TransmissionAmount(eval, x, what == kMuBelow);
      if (broken.empty() && !(a <= 0)) broken = what;  // NaN (no assembly on the way) counts as broken
    }
  }
  return broken;
}

/// The range error at points x_k: levelled (sigma given), e(x_k; x) - sigma_k E over the
/// variables and E (the Remez step: nx + 1 points, sigma_k alternating); or weighted (sigma
/// empty), w_k e(x_k; x) over the variables (Lawson's step). The Jacobian the generated one.
template <class M>
class RangeResiduals : public ceres::CostFunction {
 public:
  RangeResiduals(FunctionEvaluator<M>* eval,
                 std::vector<double> at,
                 std::vector<double> weight,
                 std::vector<double> sigma,
                 std::vector<std::string> active = {},
                 double margin = 0)
      : eval_(eval),
        at_(std::move(at)),
        weight_(std::move(weight)),
        sigma_(std::move(sigma)),
        active_(std::move(active)),
        margin_(margin) {
    set_num_residuals(static_cast<int>(at_.size() + active_.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int32_t>(eval->bound().nx + (sigma_.empty() ? 0 : 1)));
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const int nx = eval_->bound().nx, nz = nx + (sigma_.empty() ? 0 : 1);
    const bool jac = jacobians != nullptr && jacobians[0] != nullptr;
    eval_->evaluations += jac ? 1 + nz : 1;
    const std::vector<double> x(parameters[0], parameters[0] + nx);
    const auto p = eval_->ParamsOf(x);
    for (size_t k = 0; k < at_.size(); ++k) {
      double e = 0;
      double* row = jac ? jacobians[0] + k * static_cast<size_t>(nz) : nullptr;
      if (!eval_->RangeError(p, x, at_[k], &e, row)) return false;
      residuals[k] = weight_[k] * e - (sigma_.empty() ? 0.0 : sigma_[k] * parameters[0][nx]);
      if (!jac) continue;
      for (int j = 0; j < nx; ++j) row[j] *= weight_[k];
      if (!sigma_.empty()) row[nx] = -sigma_[k];
    }
    // The active constraints' rows: each amount held at -margin (just inside). A parameter-only
    // amount is piecewise linear in the link lengths (sums, differences, the ratio bound's
    // multiple), so a central difference quotient is its exact gradient within a piece; the
    // transmission angle's is smooth (its extreme over the range located, TransmissionAmount),
    // its quotient within O(h^2). Every variable: the input's start angle moves the range.
    for (size_t c = 0; c < active_.size(); ++c) {
      const size_t last = at_.size() + c;
      residuals[last] = ConstraintAmount(*eval_, x, active_[c]) + margin_;
      if (!std::isfinite(residuals[last])) return false;
      if (!jac) continue;
      double* row = jacobians[0] + last * static_cast<size_t>(nz);
      for (int j = 0; j < nz; ++j) row[j] = 0;
      for (int j = 0; j < nx; ++j) {
        const double h = 1e-6 * std::max(1.0, std::abs(x[static_cast<size_t>(j)]));
        std::vector<double> xp = x, xm = x;
        xp[static_cast<size_t>(j)] += h, xm[static_cast<size_t>(j)] -= h;
        row[j] = (ConstraintAmount(*eval_, xp, active_[c]) - ConstraintAmount(*eval_, xm, active_[c])) / (2 * h);
        if (!std::isfinite(row[j])) return false;
      }
    }
    return true;
  }

 private:
  FunctionEvaluator<M>* eval_;
  std::vector<double> at_, weight_, sigma_;
  std::vector<std::string> active_;
  double margin_ = 0;
};

/// LM within the bounds on RangeResiduals from z (nx variables, + E when levelled); the final
/// cost, the iterations added to *iterations.
template <class M>
double SolveRange(FunctionEvaluator<M>* eval, RangeResiduals<M>* cost, std::vector<double>* z, int* iterations) {
  const BoundFunction<M>& b = eval->bound();
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, z->data());
  for (int j = 0; j < b.nx; ++j) {
    problem.SetParameterLowerBound(z->data(), j, b.lo[static_cast<size_t>(j)]);
    problem.SetParameterUpperBound(z->data(), j, b.hi[static_cast<size_t>(j)]);
  }
  ceres::Solver::Summary summary;
  ceres::Solve(LocalSolverOptions(), &problem, &summary);
  *iterations += static_cast<int>(summary.iterations.size());
  return summary.final_cost;
}

/// Keeps nx + 1 alternating extrema of more: drops the smallest at an end, or the smallest
/// inside with its smaller neighbour (the rest still alternate), until nx + 1 are left.
// The start of one levelled exchange on the extrema's errors ee: their signs (the alternation
// the level keeps) into *sigma, and the variables z (the first nx kept) with the mean |e| as the
// level's first guess appended.
inline void StartLevel(const std::vector<double>& ee, int nx, std::vector<double>* sigma, std::vector<double>* z) {
  sigma->clear();
  double level = 0;
  for (double e : ee) sigma->push_back(e >= 0 ? 1.0 : -1.0), level += std::abs(e) / static_cast<double>(ee.size());
  z->resize(static_cast<size_t>(nx));
  z->push_back(level);
}

inline void Reduce(int keep, std::vector<double>* ex, std::vector<double>* ee) {
  auto drop = [&](size_t i) { ex->erase(ex->begin() + static_cast<long>(i)), ee->erase(ee->begin() + static_cast<long>(i)); };
  while (static_cast<int>(ex->size()) > keep) {
    const size_t n = ex->size();
    if (static_cast<int>(n) == keep + 1) {
      drop(std::abs((*ee)[0]) < std::abs((*ee)[n - 1]) ? 0 : n - 1);
      continue;
    }
    size_t i = 0;
    for (size_t j = 1; j < n; ++j)
      if (std::abs((*ee)[j]) < std::abs((*ee)[i])) i = j;
    if (i == 0 || i == n - 1) {
      drop(i);
    } else {
      const size_t other = std::abs((*ee)[i - 1]) < std::abs((*ee)[i + 1]) ? i - 1 : i + 1;
      drop(std::max(i, other)), drop(std::min(i, other));
    }
  }
}

/// The exchange with constraints active (`active`: their messages, each amount held 1e-10
/// inside its bound): the nx variables less those k conditions leave nx + 1 - k alternating
/// extrema of equal magnitude at the constrained optimum (Chebyshev's criterion on the
/// constraints' surface). The reference (the extrema of the error at `start`, reduced to
/// nx + 1 - k) is levelled with the constraints' rows (a square system in the variables and E),
/// then exchanged for the new error's extrema, until their magnitudes agree to 1e-9 relative
/// (at most 40 steps). *x: the levelled point with the smallest largest error among those that
/// break no constraint the stage sees (BrokenConstraint; unchanged when none does). Returns the
/// last levelled point (`start` when none was levelled).
template <class M>
std::vector<double> ConstrainedExchange(FunctionEvaluator<M>* eval,
                                        const std::vector<std::string>& active,
                                        const std::vector<double>& start,
                                        std::vector<double>* x,
                                        MinimaxResult* m) {
  const int nx = eval->bound().nx, keep = nx + 1 - static_cast<int>(active.size());
  std::string what;
  for (const std::string& a : active) what += (what.empty() ? "" : "; ") + a;
  auto largest = [](const std::vector<double>& v) {
    double w = 0;
    for (double e : v) w = std::max(w, std::abs(e));
    return w;
  };
  m->constrained_converged = false;
  std::vector<double> ex, ee;
  ++eval->evaluations;
  if (!RangeExtrema(eval, start, &ex, &ee) || static_cast<int>(ex.size()) < keep) {
    m->why = "the equal-ripple answer breaks a constraint (" + what + ") and has too few extrema for its exchange";
    return start;
  }
  Reduce(keep, &ex, &ee);
  std::vector<double> z = start, best, last = start;
  double best_max = kInf;
  m->why.clear();
  for (int step = 0; step < 40; ++step) {
    std::vector<double> sigma;
    StartLevel(ee, nx, &sigma, &z);
    const double cost =
        SolveRange(eval, new RangeResiduals<M>(eval, ex, std::vector<double>(ex.size(), 1.0), sigma, active, 1e-10), &z,
                   &m->iterations);
    ++m->exchanges;
    m->level = std::abs(z[static_cast<size_t>(nx)]);
    const std::vector<double> xz(z.begin(), z.begin() + nx);
    last = xz;
    std::vector<double> nex, nee;
    ++eval->evaluations;
    if (!RangeExtrema(eval, xz, &nex, &nee)) {
      m->why = "a levelled solve on the constraint left the range where the mechanism assembles";
      break;
    }
    const double worst = largest(nee);
    if (BrokenConstraint(*eval, xz).empty() && worst < best_max) best_max = worst, best = xz;
    if (cost > 1e-6 * m->level * m->level) {
      m->why = "a levelled solve on the constraint (" + what + ") found no equal-ripple point near the reference";
      break;
    }
    if (static_cast<int>(nex.size()) < keep) {
      m->why = "the levelled error on the constraint has fewer than " + std::to_string(keep) + " alternating extrema";
      break;
    }
    Reduce(keep, &nex, &nee);
    ex = nex, ee = nee;
    double lo = kInf;
    for (double e : ee) lo = std::min(lo, std::abs(e));
    if (worst - lo <= 1e-9 * worst) {
      m->constrained_converged = true;
      break;
    }
  }
  if (!m->constrained_converged && m->why.empty()) m->why = "40 exchange steps on the constraint without equal extrema";
  if (!best.empty()) *x = best, m->max_angle = best_max;
  return last;
}

/// The variables of x at a bound (within 1e-9 of the bound's span): their indices into *held,
/// their messages (BoundMessage) into *what.
template <class M>
void AtBounds(const BoundFunction<M>& b, const std::vector<double>& x, std::vector<int>* held, std::vector<std::string>* what) {
  held->clear(), what->clear();
  for (int j = 0; j < b.nx; ++j) {
    const size_t i = static_cast<size_t>(j);
    const double tol = 1e-9 * std::max(b.hi[i] - b.lo[i], 1e-300);
    const bool upper = x[i] >= b.hi[i] - tol, lower = x[i] <= b.lo[i] + tol;
    if (upper || lower) held->push_back(j), what->push_back(BoundMessage(b, j, upper));
  }
}

/// A small linear program: the largest c . z over z >= 0 with A z <= b, b >= 0 (so that z = 0
/// is a vertex): the dense tableau simplex from the slack basis, Bland's rule (the entering
/// column the first with a positive reduced gain, ties of the ratio test to the smallest basic
/// index: no cycling). *z the optimum, *y the rows' multipliers (y >= 0, A^T y >= c, y . b =
/// c . z: the slacks' reduced costs). false when unbounded or past 50 (m + n) pivots.
inline bool SimplexMax(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& c, Eigen::VectorXd* z,
                       Eigen::VectorXd* y) {
  const Eigen::Index m = A.rows(), n = A.cols();
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(m + 1, n + m + 1);
  T.topLeftCorner(m, n) = A;
  T.block(0, n, m, m).setIdentity();
  T.topRightCorner(m, 1) = b;
  T.bottomLeftCorner(1, n) = -c.transpose();
  std::vector<Eigen::Index> basis(static_cast<size_t>(m));
  for (Eigen::Index i = 0; i < m; ++i) basis[static_cast<size_t>(i)] = n + i;
  const double eps = 1e-12 * std::max(1.0, T.cwiseAbs().maxCoeff());
  for (Eigen::Index pivot = 0;; ++pivot) {
    if (pivot > 50 * (m + n)) return false;
    Eigen::Index enter = -1;
    for (Eigen::Index j = 0; j < n + m && enter < 0; ++j)
      if (T(m, j) < -eps) enter = j;
    if (enter < 0) break;
    Eigen::Index leave = -1;
    double ratio = kInf;
    for (Eigen::Index i = 0; i < m; ++i) {
      if (!(T(i, enter) > eps)) continue;
      const double r = T(i, n + m) / T(i, enter);
      if (r < ratio || (r == ratio && basis[static_cast<size_t>(i)] < basis[static_cast<size_t>(leave)]))
        ratio = r, leave = i;
    }
    if (leave < 0) return false;
    T.row(leave) /= T(leave, enter);
    for (Eigen::Index i = 0; i <= m; ++i)
      if (i != leave && T(i, enter) != 0) T.row(i) -= T(i, enter) * T.row(leave);
    basis[static_cast<size_t>(leave)] = enter;
  }
  *z = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < m; ++i)
    if (basis[static_cast<size_t>(i)] < n) (*z)(basis[static_cast<size_t>(i)]) = std::max(T(i, n + m), 0.0);
  *y = T.block(m, n, 1, m).transpose();
  return true;
}

/// The minimax of the variables within their bounds from x (MinimaxStage, when the exchange
/// ended on fewer extrema than the free variables ask for): sequential linear programming with a
/// trust region (Madsen's method for minimax). Each step: the error's extrema at x (RangeExtrema,
/// one per sign run) e_k at x_k, sigma_k their signs, g_k the generated gradient of the error at
/// x_k (the extremum's own movement of second order there: the envelope); the step d minimises
/// max_k sigma_k (e_k + g_k . d) over lo - x <= d <= hi - x and |d_j| <= Delta max(1, |x_j|) (a
/// linear program, SimplexMax on (d - its lower end, t0 - t)); kept when the largest |error|
/// over the range falls (then Delta doubled when the ratio of the fall to the predicted one
/// passes 0.75 and the step reached the trust region; quartered below 0.25), else Delta
/// quartered. A variable that reaches its bound is set on it (within 1e-12 of the span). Stops
/// when the predicted fall is below 1e-12 of the level (the linear program's optimum at d = 0:
/// x a stationary point of the minimax, the KKT conditions met with the program's multipliers),
/// or Delta below 1e-12, at most 200 steps. At a vertex (as many extrema at the level as the
/// free variables + 1) the step is Newton's on the levelled equations: quadratic at the end.
/// *worst: the largest |error| at the last x; *weights: the last program's multipliers of the
/// extrema (the KKT weights, summing to 1) and *bound_mult: of the variables' bounds (signed: >
/// 0 an upper bound, < 0 a lower), both at the last x; returns the steps kept.
template <class M>
int BoundMinimax(FunctionEvaluator<M>* eval, std::vector<double>* x, double* worst, std::vector<double>* weights,
                 std::vector<double>* bound_mult) {
  const BoundFunction<M>& b = eval->bound();
  const int nx = b.nx;
  const auto N = static_cast<Eigen::Index>(nx);
  auto largest = [](const std::vector<double>& v) {
    double w = 0;
    for (double e : v) w = std::max(w, std::abs(e));
    return w;
  };
  std::vector<double> ex, ee;
  ++eval->evaluations;
  if (!RangeExtrema(eval, *x, &ex, &ee)) return 0;
  double level = largest(ee), delta = 0.05;
  int steps = 0;
  for (int it = 0; it < 200 && level > 0 && delta > 1e-12; ++it) {
    const auto p = eval->ParamsOf(*x);
    const auto K = static_cast<Eigen::Index>(ex.size());
    Eigen::MatrixXd G(K, N);
    std::vector<double> row(static_cast<size_t>(nx));
    bool ok = true;
    for (Eigen::Index k = 0; k < K && ok; ++k) {
      double e = 0;
      eval->evaluations += 1 + nx;
      ok = eval->RangeError(p, *x, ex[static_cast<size_t>(k)], &e, row.data());
      for (int j = 0; j < nx; ++j) G(k, j) = (ee[static_cast<size_t>(k)] >= 0 ? 1.0 : -1.0) * row[static_cast<size_t>(j)];
    }
    if (!ok) break;
    // d = dlo + u, 0 <= u <= dhi - dlo; t = t0 - s, s >= 0 (t0: the largest at u = 0).
    Eigen::VectorXd dlo(N), width(N), c0(K);
    for (int j = 0; j < nx; ++j) {
      const size_t i = static_cast<size_t>(j);
      const double r = delta * std::max(1.0, std::abs((*x)[i]));
      dlo(j) = std::max(b.lo[i] - (*x)[i], -r);
      width(j) = std::max(std::min(b.hi[i] - (*x)[i], r) - dlo(j), 0.0);
    }
    for (Eigen::Index k = 0; k < K; ++k) c0(k) = std::abs(ee[static_cast<size_t>(k)]) + G.row(k).dot(dlo);
    const double t0 = c0.maxCoeff();
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(K + N, N + 1);
    Eigen::VectorXd rhs(K + N), gain = Eigen::VectorXd::Zero(N + 1), z, y;
    A.topLeftCorner(K, N) = G;
    A.topRightCorner(K, 1).setOnes();
    rhs.head(K) = (t0 - c0.array()).matrix();
    A.bottomLeftCorner(N, N).setIdentity();
    rhs.tail(N) = width;
    gain(N) = 1;
    if (!SimplexMax(A, rhs, gain, &z, &y)) break;
    const double predicted = level - (t0 - z(N));
    Eigen::VectorXd d = dlo + z.head(N);
    weights->assign(y.data(), y.data() + K);
    // The bounds' multipliers: the upper end's row (y) less the lower end's reduced cost, where
    // that end is the variable's bound (not the trust region's).
    bound_mult->assign(static_cast<size_t>(nx), 0.0);
    const Eigen::VectorXd reduced = A.transpose() * y - gain;
    for (int j = 0; j < nx; ++j) {
      const size_t i = static_cast<size_t>(j);
      if (dlo(j) + width(j) >= b.hi[i] - (*x)[i]) (*bound_mult)[i] += y(K + j);
      if (dlo(j) <= b.lo[i] - (*x)[i]) (*bound_mult)[i] -= reduced(j);
    }
    if (!(predicted > 1e-12 * level)) break;
    std::vector<double> v = *x;
    bool at_edge = false;
    for (int j = 0; j < nx; ++j) {
      const size_t i = static_cast<size_t>(j);
      const double tol = 1e-12 * std::max(b.hi[i] - b.lo[i], 1e-300);
      v[i] = std::clamp(v[i] + d(j), b.lo[i], b.hi[i]);
      if (v[i] > b.hi[i] - tol) v[i] = b.hi[i];
      if (v[i] < b.lo[i] + tol) v[i] = b.lo[i];
      at_edge = at_edge || std::abs(std::abs(d(j)) - delta * std::max(1.0, std::abs((*x)[i]))) <=
                               1e-9 * delta * std::max(1.0, std::abs((*x)[i]));
    }
    std::vector<double> vx, ve;
    ++eval->evaluations;
    const double actual = RangeExtrema(eval, v, &vx, &ve) ? largest(ve) : kInf;
    const double rho = (level - actual) / predicted;
    if (actual < level) {
      *x = v, ex = vx, ee = ve, level = actual;
      ++steps;
      if (rho > 0.75 && at_edge) delta *= 2;
      if (rho < 0.25) delta /= 4;
    } else {
      delta /= 4;
    }
  }
  *worst = level;
  return steps;
}


/// The levelled point of r extrema (CurveMinimax): Newton on |e(x_k; x)| = E over the variables
/// `move` and E, x_k the r largest alternating extrema of x's error (RangeExtrema, Reduce),
/// relocated at each step (the extremum's own movement of second order: the envelope), the
/// generated gradients; the minimum-norm step when r is below |move| + 1; the variables kept
/// within their bounds. true when the r magnitudes agree to 1e-9 relative (as the exchange's:
/// 1e-10 is below what the position solves give at a level of 5e-4 rad; at most 30 steps);
/// *level their mean, *G the rows sigma_k g_k (r x nx) at the last x.
template <class M>
bool LevelOn(FunctionEvaluator<M>* eval, const std::vector<int>& move, int r, std::vector<double>* x, double* level,
             Eigen::MatrixXd* G) {
  const BoundFunction<M>& b = eval->bound();
  const int nx = b.nx;
  const auto nm = static_cast<Eigen::Index>(move.size());
  std::vector<double> row(static_cast<size_t>(nx));
  for (int it = 0; it < 30; ++it) {
    std::vector<double> ex, ee;
    ++eval->evaluations;
    if (!RangeExtrema(eval, *x, &ex, &ee) || static_cast<int>(ex.size()) < r) return false;
    Reduce(r, &ex, &ee);
    const auto p = eval->ParamsOf(*x);
    G->resize(r, nx);
    double lo = kInf, hi = 0, mean = 0;
    for (int k = 0; k < r; ++k) {
      const size_t i = static_cast<size_t>(k);
      double e = 0;
      eval->evaluations += 1 + nx;
      if (!eval->RangeError(p, *x, ex[i], &e, row.data())) return false;
      for (int j = 0; j < nx; ++j) (*G)(k, j) = (ee[i] >= 0 ? 1.0 : -1.0) * row[static_cast<size_t>(j)];
      lo = std::min(lo, std::abs(ee[i])), hi = std::max(hi, std::abs(ee[i])), mean += std::abs(ee[i]) / r;
    }
    *level = mean;
    if (hi - lo <= 1e-9 * hi) return true;
    // |e_k| + sigma_k g_k . dx = mean + dE for every k.
    Eigen::MatrixXd J(r, nm + 1);
    Eigen::VectorXd rhs(r);
    for (int k = 0; k < r; ++k) {
      for (Eigen::Index c = 0; c < nm; ++c) J(k, c) = (*G)(k, move[static_cast<size_t>(c)]);
      J(k, nm) = -1;
      rhs(k) = mean - std::abs(ee[static_cast<size_t>(k)]);
    }
    const Eigen::VectorXd d = J.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(rhs);
    if (!d.allFinite()) return false;
    for (Eigen::Index c = 0; c < nm; ++c) {
      const size_t i = static_cast<size_t>(move[static_cast<size_t>(c)]);
      (*x)[i] = std::clamp((*x)[i] + d(c), b.lo[i], b.hi[i]);
    }
  }
  return false;
}

/// The minimax on a curve of equal extrema (MinimaxStage, after BoundMinimax): with the
/// variables `held` on their bounds and nf free ones, r = nf extrema at the level leave a curve
/// of points where they are equal (r equations in the nf variables and the level E). Along it
/// (parameter theta, the free variable with the largest component of the curve's tangent t,
/// the null vector of [sigma_k g_k over the free variables, -1]), E'(theta) = t_E / t_theta;
/// the point where E' = 0 is found by the secant method (a bracket kept once E' changes sign,
/// Illinois' rule within it), each theta's point levelled by LevelOn over the other free
/// variables. There the r signed gradients over the free variables are dependent: weights w_k
/// (the left null vector, sum 1) with sum_k w_k sigma_k g_k = 0 over the free variables; with
/// the bounds' multipliers mu_j = -(sum_k w_k sigma_k g_k)_j (> 0 at an upper bound, < 0 at a
/// lower: the KKT conditions when w >= 0 and those signs hold). The secant's extrapolation at
/// most 4 times its last step; a theta where LevelOn fails halved towards the last (6 times).
/// true when |E'| max(1, |theta|) falls below 1e-8 of the level, or the zero of E' is located
/// to 1e-10 of theta's scale (the bracket, or the secant's step; at most 40 steps). *x the
/// point, *level its E.
template <class M>
bool CurveMinimax(FunctionEvaluator<M>* eval, const std::vector<int>& held, int r, std::vector<double>* x, double* level,
                  std::vector<double>* weights, std::vector<double>* bound_mult, int* steps) {
  const BoundFunction<M>& b = eval->bound();
  const int nx = b.nx;
  std::vector<int> free;
  for (int j = 0; j < nx; ++j)
    if (std::find(held.begin(), held.end(), j) == held.end()) free.push_back(j);
  const auto nf = static_cast<Eigen::Index>(free.size());
  if (r != static_cast<int>(nf) || r < 2) return false;
  Eigen::MatrixXd G;
  if (!LevelOn(eval, free, r, x, level, &G)) return false;
  // The tangent at x and E' along theta = x_j.
  auto slope = [&](const Eigen::MatrixXd& g, int* pick) {
    Eigen::MatrixXd J(r, nf + 1);
    for (Eigen::Index c = 0; c < nf; ++c) J.col(c) = g.col(free[static_cast<size_t>(c)]);
    J.col(nf).setConstant(-1);
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeFullV);
    const Eigen::VectorXd t = svd.matrixV().col(nf);
    if (*pick < 0) {
      Eigen::Index c = 0;
      t.head(nf).cwiseAbs().maxCoeff(&c);
      *pick = static_cast<int>(c);
    }
    return t(nf) / t(*pick);
  };
  int pick = -1;
  double s0 = slope(G, &pick);
  const size_t j = static_cast<size_t>(free[static_cast<size_t>(pick)]);
  std::vector<int> others;
  for (int f : free)
    if (f != static_cast<int>(j)) others.push_back(f);
  const double scale = std::max(1.0, std::abs((*x)[j]));
  double a = (*x)[j], fa = s0, bracket_b = 0, fb = 0;
  bool bracketed = false;
  std::vector<double> best = *x;
  double best_level = *level, best_slope = s0;
  bool converged = false;
  double prev = a - (s0 > 0 ? 1e-4 : -1e-4) * scale, fprev = kInf;  // the first step: downhill
  for (int it = 0; it < 40; ++it) {
    if (std::abs(best_slope) * scale <= 1e-8 * best_level) {
      converged = true;
      break;
    }
    double theta = 0;
    if (it == 0) {
      theta = prev;
    } else if (bracketed) {
      theta = (a * fb - bracket_b * fa) / (fb - fa);
      if (std::abs(bracket_b - a) <= 1e-10 * scale) {  // E' = 0 located to 1e-10 of theta's scale
        converged = true;
        break;
      }
    } else {
      // The secant's extrapolation, at most 4 times the last step (E'' is small where E is flat).
      const double last = std::abs(a - prev);
      theta = a + std::clamp(-fa * (a - prev) / (fa - fprev), -4 * last, 4 * last);
      if (std::abs(theta - a) <= 1e-10 * scale) {
        converged = true;
        break;
      }
    }
    theta = std::clamp(theta, b.lo[j], b.hi[j]);
    if (!std::isfinite(theta) || theta == a) break;
    std::vector<double> v;
    double lv = 0;
    bool levelled = false;
    for (int half = 0; half < 6 && !levelled; ++half, theta = 0.5 * (theta + a)) {  // where LevelOn fails: nearer a
      v = best;
      v[j] = theta;
      levelled = LevelOn(eval, others, r, &v, &lv, &G);
    }
    if (!levelled) break;
    int keep_pick = pick;
    const double sv = slope(G, &keep_pick);
    ++*steps;
    if (lv <= best_level * (1 + 1e-9) && std::abs(sv) < std::abs(best_slope)) best = v, best_level = lv, best_slope = sv;
    if (bracketed) {
      if ((sv > 0) == (fb > 0)) {
        bracket_b = theta, fb = sv, fa *= 0.5;  // Illinois
      } else {
        a = bracket_b, fa = fb, bracket_b = theta, fb = sv;
      }
    } else if ((sv > 0) != (fa > 0)) {
      bracketed = true, bracket_b = theta, fb = sv;
    } else {
      prev = a, fprev = fa, a = theta, fa = sv;
    }
  }
  *x = best, *level = best_level;
  // The weights at the answer (G at its last x, levelled or not).
  G.resize(0, 0);
  converged = LevelOn(eval, free, r, x, level, &G) && converged;
  if (G.rows() != r) return false;
  Eigen::MatrixXd A(nf + 1, r);
  for (Eigen::Index c = 0; c < nf; ++c) A.row(c) = G.col(free[static_cast<size_t>(c)]).transpose();
  A.row(nf).setOnes();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nf + 1);
  rhs(nf) = 1;
  const Eigen::VectorXd w = A.colPivHouseholderQr().solve(rhs);
  weights->assign(w.data(), w.data() + w.size());
  bound_mult->assign(static_cast<size_t>(nx), 0.0);
  const Eigen::VectorXd gw = G.transpose() * w;
  for (int h : held) (*bound_mult)[static_cast<size_t>(h)] = -gw(h);
  return converged;
}

}  // namespace function_internal

/// The Remez exchange (`fit: minimax`) from x: the reference, nx + 1 alternating extrema of
/// the error over the range (the seed's own, or after Lawson's iteration when it has fewer
/// sign changes; as many as that leaves, at least 2, when still fewer), is levelled by
/// Levenberg–Marquardt (e(x_k) = sigma_k E, the generated Jacobian, the variables within their
/// bounds), then exchanged for the new error's extrema; until their magnitudes agree to 1e-9 relative (at most 40 steps). *x: the variables with
/// the smallest largest error found (the seed's if none is smaller).
template <class M>
MinimaxResult MinimaxStage(FunctionEvaluator<M>* eval, std::vector<double>* x) {
  using function_internal::RangeExtrema;
  const BoundFunction<M>& b = eval->bound();
  const int nx = b.nx;
  MinimaxResult m;
  m.asked = true;
  std::vector<double> ex, ee;
  ++eval->evaluations;
  if (!RangeExtrema(eval, *x, &ex, &ee)) return m.why = "the seed does not assemble over the range", m;
  auto largest = [](const std::vector<double>& v) {
    double w = 0;
    for (double e : v) w = std::max(w, std::abs(e));
    return w;
  };
  m.start_max = m.max_angle = largest(ee);
  std::vector<double> best = *x;
  auto finish = [&]() {
    // The constraints: an answer that breaks one the stage sees is exchanged again with it
    // active; when that answer breaks another, again with both (from where the last ended), and
    // so on while two extrema at least are left.
    std::vector<double> start = best;
    std::vector<std::string> active;
    // Fewer extrema than the free variables ask for (nx + 1 - k, k of them on a bound): not a
    // minimax of the free variables (the reduced exchange's LM takes the nearest equal-ripple
    // point, not the lowest; or LM within the bounds stopped on one). The minimax within the
    // bounds by linear programs (BoundMinimax); then, with nx - k extrema at the level, the
    // minimum along the curve where they stay equal (CurveMinimax: not a vertex, its gradients
    // dependent there), or with nx + 1 - k the exchange with the bounds met held as constraints
    // (each one extremum fewer, as the transmission angle's bound); kept when it lowers the
    // largest error.
    std::vector<int> held;
    std::vector<std::string> held_what;
    function_internal::AtBounds(b, best, &held, &held_what);
    if (m.reference >= 2 && m.reference < nx + 1 - static_cast<int>(held.size())) {
      m.bound_stage = true;
      m.bound_start_max = m.max_angle;
      std::vector<double> xd = best;
      double wd = m.max_angle;
      m.bound_steps = function_internal::BoundMinimax(eval, &xd, &wd, &m.kkt_weights, &m.bound_multipliers);
      if (wd < m.max_angle) best = xd, m.max_angle = wd;
      function_internal::AtBounds(b, best, &held, &held_what);
      for (const std::string& w : held_what) m.bounds += (m.bounds.empty() ? "" : "; ") + w;
      m.bound_reference = nx + 1 - static_cast<int>(held.size());
      std::vector<double> bx, be;
      ++eval->evaluations;
      const bool assembles = RangeExtrema(eval, best, &bx, &be);
      int at_level = 0;
      for (double e : be) at_level += std::abs(e) >= (1 - 1e-3) * m.max_angle ? 1 : 0;
      if (assembles && at_level == m.bound_reference - 1 && at_level >= 2) {
        // One extremum fewer than the free variables + 1: the minimax along the curve where
        // those at the level stay equal.
        std::vector<double> xc = best, weights, mult;
        double level = 0;
        m.curve = true;
        m.curve_converged = function_internal::CurveMinimax(eval, held, at_level, &xc, &level, &weights, &mult, &m.curve_steps);
        std::vector<double> cx, ce;
        ++eval->evaluations;
        if (RangeExtrema(eval, xc, &cx, &ce)) {
          double worst = 0;
          for (double e : ce) worst = std::max(worst, std::abs(e));
          if (worst <= m.max_angle) best = xc, m.max_angle = worst, m.kkt_weights = weights, m.bound_multipliers = mult;
        }
        m.bound_why = "the minimax on the bounds has " + std::to_string(at_level) + " extrema at the level, not " +
                      std::to_string(m.bound_reference) + " (their gradients over the free variables dependent)";
      } else if (!assembles || static_cast<int>(bx.size()) < m.bound_reference) {
        m.bound_why = "the linear programs left fewer than " + std::to_string(m.bound_reference) +
                      " alternating extrema (a minimax of the free variables on fewer: their gradients dependent)";
      } else {
        const std::string why = m.why;
        const bool constrained = m.constrained_converged;
        const double before = m.max_angle;
        std::vector<double> trial = best;
        function_internal::ConstrainedExchange(eval, held_what, best, &trial, &m);
        m.bounds_converged = m.constrained_converged;
        m.bound_why = m.bounds_converged ? std::string() : m.why;
        m.constrained_converged = constrained, m.why = why;
        if (m.max_angle <= before) {
          best = trial;
        } else {
          m.max_angle = before;
        }
        if (m.bounds_converged) active = held_what;
      }
      start = best;
    }
    for (;;) {
      const std::string broken = function_internal::BrokenConstraint(*eval, start);
      if (broken.empty() || std::find(active.begin(), active.end(), broken) != active.end() ||
          static_cast<int>(active.size()) + 1 > nx - 1)
        break;
      if (m.constraint.empty()) m.unconstrained_max = m.max_angle;
      active.push_back(broken);
      m.constraint += (m.constraint.empty() ? "" : "; ") + broken;
      m.active = static_cast<int>(active.size());
      start = function_internal::ConstrainedExchange(eval, active, start, &best, &m);
      if (!m.constrained_converged) break;
    }
    *x = best;
    std::vector<double> zx, ze;
    if (RangeExtrema(eval, best, &zx, &ze, &m.zeros)) m.ref_x = zx, m.ref_e = ze;
    return m;
  };
  std::vector<double> z = *x;
  int keep = nx + 1;
  if (static_cast<int>(ex.size()) < nx + 1) {
    // Too few sign changes for a reference: Lawson's iteration first, weighted least squares
    // of the error at the samples + 1 points, w_k <- w_k |e_k| / sum w |e| (30 steps, each
    // LM from the last), which tends to the minimax; the smallest largest error it meets.
    const FunctionTask& t = b.task;
    const int N = t.samples;
    std::vector<double> at, w(static_cast<size_t>(N + 1), 1.0 / (N + 1)), e(static_cast<size_t>(N + 1));
    for (int k = 0; k <= N; ++k) at.push_back(t.x0 + (t.x1 - t.x0) * k / N);
    for (int step = 0; step < 30; ++step) {
      std::vector<double> sw;
      for (double wk : w) sw.push_back(std::sqrt(wk));
      function_internal::SolveRange(eval, new function_internal::RangeResiduals<M>(eval, at, sw, {}), &z, &m.iterations);
      ++m.lawson;
      const auto p = eval->ParamsOf(z);
      double sum = 0;
      bool ok = true;
      for (int k = 0; k <= N && ok; ++k) ok = eval->RangeError(p, z, at[static_cast<size_t>(k)], &e[static_cast<size_t>(k)]);
      std::vector<double> lx, le;
      ++eval->evaluations;
      if (!ok || !RangeExtrema(eval, z, &lx, &le)) break;
      const double worst = largest(le);
      if (worst < m.max_angle) m.max_angle = worst, best = z, ex = lx, ee = le;
      for (int k = 0; k <= N; ++k) sum += w[static_cast<size_t>(k)] * std::abs(e[static_cast<size_t>(k)]);
      if (!(sum > 0)) break;
      for (int k = 0; k <= N; ++k) w[static_cast<size_t>(k)] *= std::abs(e[static_cast<size_t>(k)]) / sum;
    }
    if (static_cast<int>(ex.size()) < 2) {
      m.why = "the error has fewer than 2 alternating extrema after Lawson's iteration: no Remez reference";
      return finish();
    }
    // Still fewer than nx + 1: the reduced exchange, on as many extrema as Lawson's answer
    // has (the levelled system then underdetermined, LM taking the step nearest; a family whose
    // extrema's gradients are dependent there: the variables not independent, a bound active).
    keep = std::min(keep, static_cast<int>(ex.size()));
    z = best;
  }
  m.reference = keep;
  function_internal::Reduce(keep, &ex, &ee);
  for (int step = 0; step < 40; ++step) {
    std::vector<double> sigma;
    function_internal::StartLevel(ee, nx, &sigma, &z);
    const double cost = function_internal::SolveRange(
        eval, new function_internal::RangeResiduals<M>(eval, ex, std::vector<double>(ex.size(), 1.0), sigma), &z,
        &m.iterations);
    ++m.exchanges;
    m.level = std::abs(z[static_cast<size_t>(nx)]);
    const std::vector<double> xz(z.begin(), z.begin() + nx);
    std::vector<double> nex, nee;
    ++eval->evaluations;
    if (!RangeExtrema(eval, xz, &nex, &nee)) {
      m.why = "a levelled solve left the range where the mechanism assembles";
      break;
    }
    const double worst = largest(nee);
    if (worst < m.max_angle) m.max_angle = worst, best = xz;
    if (cost > 1e-6 * m.level * m.level) {
      m.why = "a levelled solve found no equal-ripple point near the reference (a bound active?)";
      break;
    }
    if (static_cast<int>(nex.size()) < keep) {
      m.why = "the levelled error has fewer than " + std::to_string(keep) + " alternating extrema";
      break;
    }
    function_internal::Reduce(keep, &nex, &nee);
    ex = nex, ee = nee;
    double lo = kInf;
    for (double e : ee) lo = std::min(lo, std::abs(e));
    if (worst - lo <= 1e-9 * worst) {
      m.converged = true;
      break;
    }
  }
  if (!m.converged && m.why.empty()) m.why = "40 exchange steps without equal extrema";
  return finish();
}

/// What function synthesis did.
struct FunctionResult {
  FunctionCandidate best;
  std::vector<FunctionCandidate> starts;   ///< the seeds' and the runs' results, in order
  FreudensteinResult exact;                ///< the exact stage (ok false when not asked or refused)
  bool exact_asked = false;
  int exact_grid = 0;                      ///< free start angles: start-angle pairs Freudenstein was run at
  long long evaluations = 0, solves = 0;
  long long global_evaluations = 0;        ///< of the global stage's runs (in `evaluations`)
  int runs = 0;
  int iterations = 0;
  StructuralError structural;              ///< of the best (function: tasks)
  MinimaxResult minimax;                   ///< `fit: minimax`: the Remez exchange from the best
};

namespace function_internal {
/// LM from `start` when it assembles at every pair; the better of the two by Deb's rule.
template <class M>
FunctionCandidate Refine(FunctionEvaluator<M>* eval, const FunctionCandidate& at, long long max_evaluations,
                         int* iterations) {
  bool assembles = true;
  for (double e : at.residual) assembles = assembles && std::isfinite(e);
  if (!assembles || max_evaluations <= 0) return at;
  int it = 0;
  FunctionCandidate refined = eval->Check(FunctionLocalStage(eval, at.x, &it, max_evaluations));
  *iterations += it;
  refined.start = at.start + " + LM";
  return Better(refined, at) ? refined : at;
}
}  // namespace function_internal

/// The stages (file comment): the exact start(s) and the model's values, then
/// Search::restarts runs of differential evolution (each its own splitmix64 stream from
/// (seed, run) and an equal share of Search::evaluations; on `threads` threads, the result
/// independent of their number), each run's best Search::local_starts refined by LM.
template <class M>
FunctionResult SynthesizeFunction(const BoundFunction<M>& b, uint64_t seed, int threads = 1) {
  using function_internal::Refine;
  FunctionEvaluator<M> eval(b);
  FunctionResult r;
  const FunctionTask& t = b.task;
  const int nv = b.nv, nx = b.nx;
  std::vector<double> x0(static_cast<size_t>(nx));
  {
    auto p = b.base;
    for (int j = 0; j < nv; ++j)
      x0[static_cast<size_t>(j)] =
          *ModelCalls<M>::FindParameter(*b.model, &p, t.variables[static_cast<size_t>(j)].name.c_str());
    if (t.free_start) x0[static_cast<size_t>(nv)] = t.in_start, x0[static_cast<size_t>(nv + 1)] = t.out_start;
  }
  auto clamp = [&](std::vector<double> x) {
    for (int j = 0; j < nx; ++j)
      x[static_cast<size_t>(j)] = std::clamp(x[static_cast<size_t>(j)], b.lo[static_cast<size_t>(j)], b.hi[static_cast<size_t>(j)]);
    return x;
  };
  // The exact method at start angles (in0, out0): its four-bar as a candidate.
  auto exact_at = [&](double in0, double out0, FreudensteinResult* fr) {
    // The links' absolute angles: the model's input and output angles plus the offsets the
    // model turns the crank's and the output link's points by (free_start.parameters).
    auto p = b.base;
    const double alpha = t.in_offset.empty() ? 0.0 : *ModelCalls<M>::FindParameter(*b.model, &p, t.in_offset.c_str());
    const double beta = t.out_offset.empty() ? 0.0 : *ModelCalls<M>::FindParameter(*b.model, &p, t.out_offset.c_str());
    std::vector<double> t2, t4;
    for (size_t i = 0; i < t.exact_input.size(); ++i) {
      t2.push_back(t.exact_input[i] - t.in_start + in0 + alpha);
      t4.push_back(t.exact_psi[i] - t.out_start + out0 + beta);
    }
    *fr = Freudenstein(t2, t4, *ModelCalls<M>::FindParameter(*b.model, &p, t.ground.c_str()));
    std::vector<double> x = x0;
    for (int j = 0; j < nv; ++j) {
      const std::string& name = t.variables[static_cast<size_t>(j)].name;
      if (name == t.crank) x[static_cast<size_t>(j)] = fr->a;
      if (name == t.coupler) x[static_cast<size_t>(j)] = fr->b;
      if (name == t.rocker) x[static_cast<size_t>(j)] = fr->c;
    }
    if (t.free_start) x[static_cast<size_t>(nv)] = in0, x[static_cast<size_t>(nv + 1)] = out0;
    return x;
  };
  // Seeds: the exact start (free start angles: Freudenstein's least squares on a 12 x 12 grid
  // of start angles, its best few by Deb's rule), the model's values.
  std::vector<FunctionCandidate> seeds;
  if (t.freudenstein) {
    r.exact_asked = true;
    std::vector<double> xe = exact_at(t.in_start, t.out_start, &r.exact);
    if (r.exact.ok) {
      seeds.push_back(eval.Check(clamp(xe)));
      seeds.back().start = "freudenstein";
    }
    if (t.free_start) {
      std::vector<FunctionCandidate> grid;
      const int G = 12;
      for (int u = 0; u < G; ++u) {
        for (int v = 0; v < G; ++v) {
          const double in0 = t.in_lo + (t.in_hi - t.in_lo) * (u + 0.5) / G;
          const double out0 = t.out_lo + (t.out_hi - t.out_lo) * (v + 0.5) / G;
          FreudensteinResult fr;
          const std::vector<double> x = exact_at(in0, out0, &fr);
          ++r.exact_grid;
          if (!fr.ok) continue;
          grid.push_back(eval.Check(clamp(x)));
          grid.back().start = "freudenstein at start angles " + Short(ToDegrees(in0), 5) + "deg, " +
                              Short(ToDegrees(out0), 5) + "deg";
        }
      }
      std::stable_sort(grid.begin(), grid.end(), [](const FunctionCandidate& u, const FunctionCandidate& v) { return Better(u, v); });
      for (int k = 0; k < std::min<int>(t.search.local_starts, static_cast<int>(grid.size())); ++k)
        seeds.push_back(grid[static_cast<size_t>(k)]);
    }
  }
  seeds.push_back(eval.Check(clamp(x0)));
  seeds.back().start = "model";
  for (const FunctionCandidate& s : seeds) {
    const FunctionCandidate kept = Refine(&eval, s, std::numeric_limits<long long>::max() / 4, &r.iterations);
    r.starts.push_back(kept);
    if (r.starts.size() == 1 || Better(kept, r.best)) r.best = kept;
  }
  // The global stage: DE runs, each refined by LM from its best few.
  const int runs = t.search.restarts;
  r.runs = runs;
  if (runs > 0) {
    struct RunOut {
      FunctionCandidate best;
      long long evaluations = 0, solves = 0;
      int iterations = 0;
    };
    std::vector<RunOut> out(static_cast<size_t>(runs));
    const long long budget = std::max<long long>(1, t.search.evaluations / runs);
    RunParallel(runs, threads, [&](int run) {
      FunctionEvaluator<M> ev(b);
      SplitMix64 rng(seed, static_cast<uint64_t>(run));
      int np = t.search.population > 0 ? t.search.population : std::max(20, 10 * nx);
      np = static_cast<int>(std::max<long long>(4, std::min<long long>(np, budget)));
      const long long global_budget = budget - static_cast<long long>(t.search.local_share * static_cast<double>(budget));
      std::vector<FunctionCandidate> pop = DifferentialEvolution<FunctionCandidate>(
          b.lo, b.hi, np, &rng, [&](const std::vector<double>& x) { return ev.Check(x); },
          [&]() { return ev.evaluations + np <= global_budget; });
      std::vector<size_t> order(pop.size());
      for (size_t k = 0; k < order.size(); ++k) order[k] = k;
      std::stable_sort(order.begin(), order.end(), [&](size_t u, size_t v) { return Better(pop[u], pop[v]); });
      RunOut& o = out[static_cast<size_t>(run)];
      o.best = pop[order[0]];
      o.best.start = "run " + std::to_string(run + 1);
      const int starts = std::max(1, std::min<int>(t.search.local_starts, np));
      for (int k = 0; k < starts; ++k) {
        const long long left = budget - ev.evaluations;
        if (left <= 0) break;
        FunctionCandidate c = pop[order[static_cast<size_t>(k)]];
        c.start = "run " + std::to_string(run + 1);
        const FunctionCandidate refined = Refine(&ev, c, left / (starts - k), &o.iterations);
        if (Better(refined, o.best)) o.best = refined;
      }
      o.evaluations = ev.evaluations;
      o.solves = ev.solves;
    });
    for (const RunOut& o : out) {
      r.starts.push_back(o.best);
      if (Better(o.best, r.best)) r.best = o.best;
      r.global_evaluations += o.evaluations;
      eval.solves += o.solves;
      r.iterations += o.iterations;
    }
  }
  // fit: minimax: the Remez exchange from the best; its mechanism is the answer when it has no
  // defect (or the best has one) and a smaller largest error over the range.
  if (t.fit_minimax) {
    std::vector<double> xm = r.best.x;
    r.minimax = MinimaxStage(&eval, &xm);
    if (xm != r.best.x) {
      FunctionCandidate c = eval.Check(xm);
      c.start = r.best.start + " + minimax";
      if (c.feasible() || !r.best.feasible()) {
        r.best = c;
        r.minimax.used = true;
      } else {
        r.minimax.why = "its mechanism has a defect (" + c.defect + "); the accuracy points' answer is kept";
      }
    } else if (r.minimax.why.empty()) {
      r.minimax.why = "no smaller largest error than the accuracy points' answer";
    }
  }
  r.evaluations = eval.evaluations + r.global_evaluations;
  r.structural = eval.Structural(r.best.x);
  r.solves = eval.solves;
  return r;
}

/// The parameters the model file gets: the variables' values and, with free_start.parameters,
/// the offsets alpha + (in0 - in_start) and beta + (out0 - out_start) (alpha, beta the model's
/// values): the model's input angle is the crank line's less alpha, its output angle the output
/// link's line less beta, so that with these the model's own angles meet the task's pairs as
/// written (the start angles the task file gives) while its links stand where the search put them.
template <class M>
void FunctionModelParameters(const BoundFunction<M>& b, const FunctionCandidate& c, std::vector<std::string>* names,
                             std::vector<double>* values) {
  const FunctionTask& t = b.task;
  names->clear(), values->clear();
  for (size_t j = 0; j < t.variables.size(); ++j) names->push_back(t.variables[j].name), values->push_back(c.x[j]);
  if (t.free_start && !t.in_offset.empty()) {
    auto p = b.base;
    names->push_back(t.in_offset);
    values->push_back(*ModelCalls<M>::FindParameter(*b.model, &p, t.in_offset.c_str()) +
                      c.x[static_cast<size_t>(b.nv)] - t.in_start);
    names->push_back(t.out_offset);
    values->push_back(*ModelCalls<M>::FindParameter(*b.model, &p, t.out_offset.c_str()) +
                      c.x[static_cast<size_t>(b.nv + 1)] - t.out_start);
  }
}

/// The written model's input at each pair, in the pairs' order (the motion from pair to pair
/// that Check walks): the search's input angle, less the change FunctionModelParameters makes
/// to the input's offset parameter (the model's input is the crank line's angle less it), so
/// that with the offsets written these are the task's own input angles.
template <class M>
std::vector<double> FunctionWrittenInputs(const BoundFunction<M>& b, const FunctionCandidate& c) {
  std::vector<std::string> names;
  std::vector<double> values;
  FunctionModelParameters(b, c, &names, &values);
  double shift = 0;
  for (size_t k = 0; k < names.size(); ++k) {
    if (b.task.in_offset.empty() || names[k] != b.task.in_offset) continue;
    auto p = b.base;
    shift = values[k] - *ModelCalls<M>::FindParameter(*b.model, &p, names[k].c_str());
  }
  FunctionEvaluator<M> eval(b);
  std::vector<double> motion;
  for (int i = 0; i < b.n; ++i) motion.push_back(eval.Q(c.x, i) - shift);
  return motion;
}

/// The report: the stages, the residual per pair, the structural error, the checks, the parameters.
template <class M>
std::string FunctionReport(const BoundFunction<M>& b, const FunctionResult& r, uint64_t seed, int threads = 1) {
  const FunctionTask& t = b.task;
  std::string s = "# function generation: " + std::string(ModelCalls<M>::Name(*b.model)) + ", output " + t.output + ", " +
                  std::to_string(b.n) + (t.range ? " accuracy points" : " pairs") + " (task " + t.file + ")\n";
  if (t.range)
    s += "function: y = " + t.expression + " on x in [" + Short(t.x0, 9) + ", " + Short(t.x1, 9) + "], " +
         (t.chebyshev ? "Chebyshev" : "uniform") + " spacing; input " + Short(ToDegrees(t.in_span), 9) +
         " deg and output " + Short(ToDegrees(t.out_span), 9) + " deg over the range" +
         (t.free_start ? ", start angles free" : "") + "\n";
  s += "seed " + std::to_string(seed) + ", threads " + std::to_string(threads) + ", global runs " + std::to_string(r.runs) +
       ", evaluations " + std::to_string(r.evaluations) + " (global stage and its LM " + std::to_string(r.global_evaluations) +
       "), position solves " + std::to_string(r.solves) + ", LM iterations " + std::to_string(r.iterations) + "\n";
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
    if (r.exact_grid > 0)
      s += "Freudenstein's least squares at " + std::to_string(r.exact_grid) + " start-angle pairs (the seeds of the free start angles)\n";
  }
  const FunctionCandidate& c = r.best;
  s += "best: from " + c.start + ", error (sum of squared angle residuals at the " +
       std::string(t.fit_range ? "samples" : "points") + ") " + Short(c.error, 9) + " rad^2\n";
  s += "defect checks: " + (c.feasible() ? std::string("none (every pair on the model's assembly mode, no dead point between pairs, "
                                                       "the constraints met)")
                                         : c.defect) + "\n";
  if (std::isfinite(c.mu_min))
    s += "transmission angle over the motion: " + Short(ToDegrees(c.mu_min), 5) + " to " + Short(ToDegrees(c.mu_max), 5) + " deg\n";
  if (t.free_start) {
    s += "start angles: input " + Num(ToDegrees(c.x[static_cast<size_t>(b.nv)])) + " deg, output " +
         Num(ToDegrees(c.x[static_cast<size_t>(b.nv + 1)])) + " deg\n";
    if (!t.in_offset.empty()) {
      std::vector<std::string> names;
      std::vector<double> values;
      FunctionModelParameters(b, c, &names, &values);
      s += "in the model file: " + t.in_offset + " = " + Num(values[values.size() - 2]) + ", " + t.out_offset + " = " +
           Num(values.back()) + " (rad; the model's input and output angles then meet the task's pairs as written)\n";
    }
  }
  const double in_shift = t.free_start ? c.x[static_cast<size_t>(b.nv)] - t.in_start : 0;
  const double out_shift = t.free_start ? c.x[static_cast<size_t>(b.nv + 1)] - t.out_start : 0;
  if (t.fit_range) {
    double worst = 0;
    for (double e : c.residual) worst = std::max(worst, std::abs(e));
    s += "fitted: the structural error at " + std::to_string(b.n) + " samples over the range (largest residual " +
         Short(worst, 6) + " rad)\n";
  } else {
    s += std::string(t.range ? "point  x  " : "pair  ") + "input(deg)  target(deg)  residual(rad)\n";
  }
  for (int i = 0; i < (t.fit_range ? 0 : b.n); ++i)
    s += std::to_string(i + 1) + "  " + (t.range ? Short(t.x[static_cast<size_t>(i)], 10) + "  " : std::string()) +
         Short(ToDegrees(t.input[static_cast<size_t>(i)] + in_shift), 10) + "  " +
         Short(ToDegrees(t.psi[static_cast<size_t>(i)] + out_shift), 10) + "  " +
         Short(c.residual[static_cast<size_t>(i)], 6) + "\n";
  if (t.range) {
    const StructuralError& e = r.structural;
    if (e.assembles)
      s += "structural error over the range (" + std::to_string(e.samples) + " samples): largest " + Short(e.max_y, 6) +
           " in y (" + Short(ToDegrees(e.max_angle), 6) + " deg of output) at x = " + Short(e.at_x, 9) + "\n";
    else
      s += "structural error over the range: the mechanism does not assemble on its mode over the whole range\n";
  }
  if (r.minimax.asked) {
    const MinimaxResult& m = r.minimax;
    const double to_y = (t.y1 - t.y0) / t.out_span;
    s += "minimax (Remez exchange of the accuracy points): " +
         (m.lawson > 0 ? std::to_string(m.lawson) + " Lawson steps (the seed has too few sign changes), "
                       : std::string()) +
         (m.reference > 0 && m.reference < static_cast<int>(r.best.x.size()) + 1
              ? "a reduced exchange on " + std::to_string(m.reference) + " extrema (Lawson's answer has no more), "
              : std::string()) +
         std::to_string(m.exchanges) + " exchange steps, " + std::to_string(m.iterations) + " LM iterations, " +
         (m.converged ? "converged" : "not converged: " + m.why) +
         (m.used ? "" : "; not used" + (m.converged ? ": " + m.why : std::string())) + "\n";
    if (!m.constraint.empty())
      s += "the equal-ripple answer breaks a constraint (" + m.constraint + "; its largest |error| " +
           Short(m.unconstrained_max * std::abs(to_y), 6) + " in y): exchanged again with " +
           (m.active > 1 ? "them active (" + std::to_string(m.active) + " extrema fewer), "
                         : std::string("it active (one extremum fewer), ")) +
           (m.constrained_converged ? "converged" : "not converged: " + m.why) + "\n";
    if (m.bound_stage) {
      s += "the exchange ended on " + std::to_string(m.reference) + " extrema (largest |error| " +
           Short(m.bound_start_max * std::abs(to_y), 6) + " in y), fewer than the " + std::to_string(m.bound_reference) +
           " the free variables ask for: " + std::to_string(m.bound_steps) +
           " linear-programming steps (the minimax within the bounds), then " +
           (m.curve ? std::to_string(m.curve_steps) + " steps along the curve of " + std::to_string(m.bound_reference - 1) +
                          " equal extrema" + (m.bounds.empty() ? std::string() : " with " + m.bounds + " held") +
                          (m.curve_converged ? ", its minimum reached" : ", its minimum not reached (the level's slope above 1e-8)") + " (" +
                          m.bound_why + ")"
                    : "the exchange on " + std::to_string(m.bound_reference) + " extrema" +
                          (m.bounds.empty() ? std::string() : " with " + m.bounds + " held (one extremum fewer per bound)") +
                          ", " + (m.bounds_converged ? "converged" : "not converged: " + m.bound_why));
      if (m.curve && !m.kkt_weights.empty()) {  // at the answer (the curve's minimum)
        s += "; KKT weights of the extrema";
        for (double w : m.kkt_weights) s += " " + Short(w, 4);
        for (size_t j = 0; j < m.bound_multipliers.size(); ++j)
          if (m.bound_multipliers[j] != 0)
            s += ", of the bound of " + function_internal::VariableName(b, static_cast<int>(j)) + " " +
                 Short(m.bound_multipliers[j], 4);
      }
      s += "\n";
    }
    if (std::isfinite(m.max_angle)) {
      s += "largest |structural error| over the range (extrema located): " + Short(m.max_angle * std::abs(to_y), 6) +
           " in y (" + Short(ToDegrees(m.max_angle), 6) + " deg of output); the accuracy points' answer: " +
           Short(m.start_max * std::abs(to_y), 6) + " in y (" + Short(ToDegrees(m.start_max), 6) + " deg)\n";
      s += "equioscillation: the error's extrema (x, error in y, error in deg)\n";
      for (size_t k = 0; k < m.ref_x.size(); ++k)
        s += "  " + Short(m.ref_x[k], 10) + "  " + Short(m.ref_e[k] * to_y, 6) + "  " + Short(ToDegrees(m.ref_e[k]), 6) + "\n";
      s += "accuracy points (the error's zeros): x =";
      for (double zx : m.zeros) s += " " + Short(zx, 10);
      s += "\n";
    }
  }
  s += "parameters:";
  for (size_t j = 0; j < t.variables.size(); ++j) s += " " + t.variables[j].name + " = " + Num(c.x[j]);
  s += "\n";
  return s;
}

/// The output angle against the input (a margin each side of the points) and the targets:
/// the pairs (circles) and, for a function over a range, the function's own angle (dashed).
template <class M>
std::string FunctionSvg(FunctionEvaluator<M>* eval, const FunctionCandidate& c, int samples = 400) {
  const BoundFunction<M>& b = eval->bound();
  const FunctionTask& t = b.task;
  const auto p = eval->ParamsOf(c.x);
  // The circles: the pairs or accuracy points (not the samples of `fit: range`).
  std::vector<double> qs, ts;
  for (size_t i = 0; i < t.exact_input.size(); ++i)
    qs.push_back(t.exact_input[i] - t.in_start + eval->InStart(c.x)), ts.push_back(t.exact_psi[i] - t.out_start + eval->OutStart(c.x));
  double q0 = *std::min_element(qs.begin(), qs.end()), q1 = *std::max_element(qs.begin(), qs.end());
  std::vector<std::array<double, 2>> wanted;
  if (t.range) {
    const double in0 = eval->InStart(c.x), out0 = eval->OutStart(c.x);
    q0 = std::min(in0, in0 + t.in_span), q1 = std::max(in0, in0 + t.in_span);
    for (int k = 0; k <= samples; ++k) {
      const double xk = t.x0 + (t.x1 - t.x0) * k / samples;
      wanted.push_back({in0 + t.in_span * (xk - t.x0) / (t.x1 - t.x0), out0 + t.out_span * (t.f(xk) - t.y0) / (t.y1 - t.y0)});
    }
  }
  const double pad = 0.1 * std::max(q1 - q0, 1e-3);
  q0 -= pad, q1 += pad;
  std::vector<std::vector<std::array<double, 2>>> pieces(1);
  double ymin = kInf, ymax = -kInf;
  typename FunctionEvaluator<M>::VecPhi phi;
  const double ref = ts[0];
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
  for (double y : ts) ymin = std::min(ymin, y), ymax = std::max(ymax, y);
  for (const auto& w : wanted) ymin = std::min(ymin, w[1]), ymax = std::max(ymax, w[1]);
  const double w = 600, h = 400, m = 20;
  const double yspan = std::max(ymax - ymin, 1e-9);
  auto X = [&](double q) { return Short(m + (q - q0) / (q1 - q0) * w, 7); };
  auto Y = [&](double y) { return Short(m + (ymax - y) / yspan * h, 7); };
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Short(w + 2 * m) + "\" height=\"" +
                    Short(h + 2 * m) + "\">\n<title>" + std::string(ModelCalls<M>::Name(eval->model())) + ": " + t.output +
                    " against the input (curve), the task's " + (t.range ? "function (dashed) and accuracy points" : "pairs") +
                    " (circles)</title>\n";
  svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  if (!wanted.empty()) {
    svg += "<polyline fill=\"none\" stroke=\"#c0392b\" stroke-width=\"1\" stroke-dasharray=\"6 4\" points=\"";
    for (const auto& pt : wanted) svg += X(pt[0]) + "," + Y(pt[1]) + " ";
    svg += "\"/>\n";
  }
  for (const auto& piece : pieces) {
    if (piece.size() < 2) continue;
    svg += "<polyline fill=\"none\" stroke=\"#1f5fa8\" stroke-width=\"1.5\" points=\"";
    for (const auto& pt : piece) svg += X(pt[0]) + "," + Y(pt[1]) + " ";
    svg += "\"/>\n";
  }
  for (size_t i = 0; i < qs.size(); ++i)
    svg += "<circle cx=\"" + X(qs[i]) + "\" cy=\"" + Y(ts[i]) +
           "\" r=\"5\" fill=\"none\" stroke=\"#c0392b\" stroke-width=\"1.5\"/>\n";
  svg += "</svg>\n";
  return svg;
}

}  // namespace mechgen::synthesis
