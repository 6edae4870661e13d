/**
 * \file synthesis/path.h
 * Path generation (issue 28) on a generated model with a `design` section: the task
 * (synthesis/task.h) bound to the model, the evaluation of a candidate with its defect
 * checks, and the evaluator the global and local stages (synthesis/optimize.h) share.
 *
 * A candidate is the task's variables (model design parameters) and the input angle q_i at
 * each target: prescribed (q_i = offset + angle_i [+ p[relative_to]]) or, with free timing,
 * each q_i found by projecting the target onto the coupler curve (the curve sampled at
 * Search::curve_samples input angles, then Gauss–Newton on |r_P(q) - T|^2 with K_P).
 * Error: E = sum_i |r_P(q_i) - T_i|^2 (the published benchmarks' measure).
 *
 * Defects (each adds to the candidate's violation; 0: none): every target reached on the
 * model's assembly mode (kDefaultModes, M::Solve's closed forms / Newton blocks) and, along
 * the motion from target to target (sampled at the curve's step), the mechanism assembles on
 * that mode, regular by the project's singular-configuration threshold (SolveOnMode): it does
 * not have to pass a dead point (branch change) between targets; targets in increasing input angle within one turn (`order`);
 * Grashof class and the crank's full rotation (the link lengths from the generated
 * EvalDesignChecks); link-length bounds and the longest over the shortest link (`link_ratio`);
 * transmission angle bounds over the motion (the full
 * turn when the crank must turn fully, else from the first target to the last).
 */
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "mechgen/core/constants.h"
#include "mechgen/core/linear_algebra.h"
#include "mechgen/core/model_calls.h"
#include "mechgen/core/model_traits.h"
#include "mechgen/core/model_view.h"
#include "mechgen/synthesis/task.h"

namespace mechgen::synthesis {

constexpr double kTwoPi = 6.283185307179586;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// The generated Solve's own defaults (its max_iterations; tolerance 0: its own), which every
/// solve here takes.
constexpr int kSolveIterations = 20;

/// A generated model's object (its functions are static): what the functions taking the model
/// are called with for a generated model's type.
template <class M>
const M& GeneratedModel() {
  static const M model{};
  return model;
}

/// The scene (every named point of every link, ModelCalls<M>::Scene) at q = 0 with phi at the
/// assembly guess: where the ground points are, which do not move (the constraints' regions,
/// the exact task's pivots). Only for a model with scene points.
template <class M>
void GroundScene(const M& model, const typename ModelTypes<M>::Params& p, typename ModelTypes<M>::MatScene* r) {
  using C = ModelCalls<M>;
  typename ModelTypes<M>::VecQ q = ModelTypes<M>::VecQ::Zero(C::Nq(model));
  typename ModelTypes<M>::VecPhi phi;
  phi.resize(C::Nphi(model));
  for (int i = 0; i < C::Nphi(model); ++i) phi(i) = C::AssemblyPhi(model)[i];
  C::Scene(model, p, q, phi, r);
}

/// The angle in [0, 2 pi).
inline double Wrap(double a) {
  double w = std::fmod(a, kTwoPi);
  if (w < 0) w += kTwoPi;
  return w >= kTwoPi ? 0.0 : w;
}

/// What the constraints (Constraints, path and function tasks) read from the generated model:
/// the four-bar loop's link lengths among the design checks (EvalDesignChecks; -1 if absent)
/// and the ground points of `ground_region` among the scene points (EvalScene).
struct ConstraintIndices {
  int check_crank = -1, check_ground = -1;
  std::vector<int> check_lengths;
  std::vector<int> region_points;
};

/// A task bound to the model M: indices instead of names.
template <class M>
struct BoundPath {
  using Params = typename ModelTypes<M>::Params;
  const M* model = nullptr;    ///< reached through ModelCalls<M> (a generated model, or the model view); outlives this
  PathTask task;
  Params base;                 ///< the model's parameters (with --set applied); the fixed ones stay
  int n = 0;                   ///< targets
  int point = -1;              ///< index in M::kPointNames
  std::vector<int> column;     ///< each variable's column in M::kDesignNames
  int relative_to = -1;        ///< timing.relative_to: its variable index, -1 if fixed or none
  double relative_fixed = 0;   ///< its value when it is not a variable
  int offset_var = -1;         ///< index of the free offset in the global vector, -1 if none
  int num_global = 0;          ///< variables of the global stage (design + free offset)
  ConstraintIndices checks;    ///< what the constraints read from the generated model
  int place_x = -1, place_y = -1, place_angle = -1;  ///< the placement's variables, -1: none
};

namespace bind_internal {
/// "FILE:LINE:COLUMN: error: " of a place in a task file (task_internal::Where's form).
inline std::string Where(const std::string& file, int line, int column) {
  return file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": error: ";
}
/// The names of a model's list (M::kDesignNames, ...) for a message: "a, b, c" or "(none)".
template <class Names>
std::string List(const Names& names) {
  std::string text;
  for (const char* n : names) text += (text.empty() ? "" : ", ") + std::string(n);
  return text.empty() ? std::string("(none)") : text;
}
/// The same of n names name(0), ..., name(n - 1) (a list read through ModelCalls).
template <class Name>
std::string List(int n, const Name& name) {
  std::string text;
  for (int i = 0; i < n; ++i) text += (text.empty() ? "" : ", ") + std::string(name(i));
  return text.empty() ? std::string("(none)") : text;
}
/// Each variable's column in M::kDesignNames into *column; false and *error (its place) for a
/// variable that is not a design parameter of M. Every kind of task binds its variables here.
template <class M>
bool BindVariables(const M& model, const std::string& file, const std::vector<Variable>& variables,
                   std::vector<int>* column, std::string* error) {
  using C = ModelCalls<M>;
  for (const Variable& v : variables) {
    int col = -1;
    for (int d = 0; d < C::NumDesign(model); ++d)
      if (v.name == C::DesignName(model, d)) col = d;
    if (col < 0) {
      *error = Where(file, v.line, v.column) + "variable '" + v.name + "' is not one of the model's design parameters (" +
               List(C::NumDesign(model), [&](int d) { return C::DesignName(model, d); }) +
               "); add it to the model's `design:` list";
      return false;
    }
    column->push_back(col);
  }
  return true;
}
template <class M>
bool BindVariables(const std::string& file, const std::vector<Variable>& variables, std::vector<int>* column,
                   std::string* error) {
  return BindVariables(M(), file, variables, column, error);
}
}  // namespace bind_internal

/// The constraints' places in M (ConstraintIndices); false and *error (FILE:LINE:COLUMN) when
/// the model cannot take them. `crank_link`: the task's input link ("" none).
template <class M>
bool BindConstraints(const M& model, const std::string& file, const Constraints& c, const std::string& crank_link,
                     int crank_line, int crank_column, ConstraintIndices* out, std::string* error) {
  using C = ModelCalls<M>;
  ConstraintIndices ix;
  const bool need_lengths = c.grashof || c.crank_rotates || c.crank_shortest || c.has_lengths || c.has_ratio;
  if (need_lengths) {
    for (int k = 0; k < C::NumDesignChecks(model); ++k) {
      const std::string name = C::DesignCheckName(model, k);
      if (name.rfind("length_", 0) == 0 && name.size() > 13 && name.compare(name.size() - 6, 6, "_loop0") == 0) {
        ix.check_lengths.push_back(k);
        const std::string link = name.substr(7, name.size() - 13);
        if (link == crank_link) ix.check_crank = k;
        if (link == C::LinkName(model, C::GroundLink(model))) ix.check_ground = k;
      }
    }
    if (ix.check_lengths.size() != 4) {
      *error = file + ": error: the constraints grashof/crank_*/link_lengths need a four-bar loop with a ground link "
               "(the model's design checks have no link lengths of one)";
      return false;
    }
    if ((c.crank_rotates || c.crank_shortest) && ix.check_crank < 0) {
      *error = bind_internal::Where(file, crank_line, crank_column) + "crank: '" + crank_link +
               "' is not a moving link of the model's four-bar loop (links: " +
               bind_internal::List(C::NumLinks(model), [&](int l) { return C::LinkName(model, l); }) + ")";
      return false;
    }
  }
  if (c.has_region) {
    if (C::NumScenePoints(model) == 0) {
      *error = bind_internal::Where(file, c.region_line, c.region_column) + "ground_region: the model has no scene points";
      return false;
    } else {
    std::string ground_points;
    for (int k = 0; k < C::NumScenePoints(model); ++k) {
      if (C::ScenePointLink(model, k) != C::GroundLink(model)) continue;
      ground_points += (ground_points.empty() ? "" : ", ") + std::string(C::ScenePointName(model, k));
      if (c.region_pivots.empty()) ix.region_points.push_back(k);
    }
    for (const std::string& name : c.region_pivots) {
      int found = -1;
      for (int k = 0; k < C::NumScenePoints(model); ++k)
        if (C::ScenePointLink(model, k) == C::GroundLink(model) && name == C::ScenePointName(model, k)) found = k;
      if (found < 0) {
        *error = bind_internal::Where(file, c.region_line, c.region_column) + "ground_region: '" + name +
                 "' is not a point of the model's ground link (" + (ground_points.empty() ? "none" : ground_points) + ")";
        return false;
      }
      ix.region_points.push_back(found);
    }
    if (ix.region_points.empty()) {
      *error = bind_internal::Where(file, c.region_line, c.region_column) +
               "ground_region: the model's ground link has no named points";
      return false;
    }
    }
  }
  *out = ix;
  return true;
}

template <class M>
bool BindConstraints(const std::string& file, const Constraints& c, const std::string& crank_link, int crank_line,
                     int crank_column, ConstraintIndices* out, std::string* error) {
  return BindConstraints(M(), file, c, crank_link, crank_line, crank_column, out, error);
}

/// The parameter-only constraints of p (link lengths, Grashof, the crank, link_ratio, the
/// ground region): each violation through flag(amount, what). True when the crank must turn
/// fully (its motion is then checked over the whole turn).
template <class M, class Flag>
bool CheckParameterConstraints(const M& model, const typename ModelTypes<M>::Params& p, const Constraints& c,
                               const ConstraintIndices& ix, Flag&& flag) {
  using C = ModelCalls<M>;
  bool full_turn = false;
  // The link lengths among the design checks (Grashof, the crank, the lengths, link_ratio).
  auto lengths = [&](const auto& margin) {
    std::array<double, 4> len;
    for (int k = 0; k < 4; ++k) len[static_cast<size_t>(k)] = margin(ix.check_lengths[static_cast<size_t>(k)]);
    std::array<double, 4> sorted = len;
    std::sort(sorted.begin(), sorted.end());
    const double grashof = sorted[1] + sorted[2] - sorted[0] - sorted[3];  // p + q - s - l
    if (c.grashof) flag(-grashof, "not Grashof (s + l > p + q)");
    if (c.has_ratio) flag(sorted[3] - c.ratio_max * sorted[0], "the longest link over the shortest above link_ratio");
    if (c.has_lengths) {
      for (double l : len) flag(std::max(c.length_lo - l, l - c.length_hi), "a link length outside link_lengths");
    }
    if (c.crank_rotates || c.crank_shortest) {
      const double crank = margin(ix.check_crank);
      const double ground = ix.check_ground >= 0 ? margin(ix.check_ground) : kInf;
      double shortest_gap = crank - sorted[0];  // 0 when the crank is the shortest
      if (c.crank_rotates) shortest_gap = std::min(shortest_gap, ground - sorted[0]);
      flag(-grashof, "the crank cannot turn fully: not Grashof");
      flag(shortest_gap, c.crank_shortest ? "the crank is not the shortest link"
                                          : "the crank cannot turn fully: neither it nor the ground is the shortest link");
      full_turn = true;
    }
  };
  if constexpr (C::kView) {
    if (!ix.check_lengths.empty() && C::NumDesignChecks(model) > 0) {
      typename C::DesignMargins margin;
      C::DesignChecks(model, p, &margin);
      lengths(margin);
    }
  } else if constexpr (HasDesignDerivatives<M>::value) {
    if constexpr (M::kNumDesignChecks > 0) {
      if (!ix.check_lengths.empty()) {
        typename C::DesignMargins margin;
        C::DesignChecks(model, p, &margin);
        lengths(margin);
      }
    }
  }
  {
    if (!ix.region_points.empty() && C::NumScenePoints(model) > 0) {
      typename ModelTypes<M>::MatScene r;
      GroundScene(model, p, &r);
      for (int k : ix.region_points) {
        const double x = r(0, k), y = r(1, k);
        const std::string what = std::string("ground point ") + C::ScenePointName(model, k) +
                                 " outside ground_region";
        if (c.region_rectangle) {
          flag(std::max(0.0, c.region_lo[0] - x) + std::max(0.0, x - c.region_hi[0]) + std::max(0.0, c.region_lo[1] - y) +
                   std::max(0.0, y - c.region_hi[1]),
               what);
        } else {
          flag(std::hypot(x - c.region_lo[0], y - c.region_lo[1]) - c.region_radius, what);
        }
      }
    }
  }
  return full_turn;
}

template <class M, class Flag>
bool CheckParameterConstraints(const typename M::template ParamsT<double>& p, const Constraints& c,
                               const ConstraintIndices& ix, Flag&& flag) {
  return CheckParameterConstraints(M(), p, c, ix, std::forward<Flag>(flag));
}

/// Binds `task` to M: the point, the variables (the model's design parameters), the crank
/// link and what the constraints need must exist. false and *error (FILE:LINE:COLUMN) if not.
template <class M>
bool BindPathTask(const M& model, const PathTask& task, const typename ModelTypes<M>::Params& base, BoundPath<M>* out,
                  std::string* error) {
  using C = ModelCalls<M>;
  auto where = [&](int line, int column) { return bind_internal::Where(task.file, line, column); };
  using Params = typename ModelTypes<M>::Params;
  using VecQ = typename ModelTypes<M>::VecQ;
  using VecPhi = typename ModelTypes<M>::VecPhi;
  BoundPath<M> b;
  b.model = &model;
  b.task = task;
  b.base = base;
  b.n = static_cast<int>(task.tx.size());
  if (!C::HasDesign(model)) {
    *error = task.file + ": error: the model '" + std::string(C::Name(model)) +
             "' has no `design` section; add `design: [parameters to vary]` to it (models/README.md)";
    return false;
  } else {
    if (C::Nq(model) != 1) {
      *error = task.file + ": error: path generation needs a one-input model ('" + std::string(C::Name(model)) + "' has " +
               std::to_string(C::Nq(model)) + " inputs)";
      return false;
    }
    for (int m = 0; m < C::NumPoints(model); ++m)
      if (task.point == C::PointName(model, m)) b.point = m;
    if (b.point < 0) {
      *error = where(task.point_line, task.point_column) + "point '" + task.point + "' is not among the model's output points (" +
               bind_internal::List(C::NumPoints(model), [&](int m) { return C::PointName(model, m); }) +
               "); add it to the model's outputs.points or name one of those";
      return false;
    }
    if (!bind_internal::BindVariables(model, task.file, task.variables, &b.column, error)) return false;
    if (!task.timing.free && !task.timing.relative_to.empty()) {
      const std::string& r = task.timing.relative_to;
      for (size_t j = 0; j < task.variables.size(); ++j)
        if (task.variables[j].name == r) b.relative_to = static_cast<int>(j);
      if (b.relative_to < 0) {
        Params p = base;
        const double* value = C::FindParameter(model, &p, r.c_str());
        if (value == nullptr) {
          *error = where(task.timing.line, task.timing.column) + "timing.relative_to: no parameter '" + r +
                   "' in the model (parameters: " +
                   bind_internal::List(C::NumFreeParameters(model), [&](int i) { return C::FreeParameterName(model, i); }) +
                   ")";
          return false;
        }
        b.relative_fixed = *value;
      }
    }
    b.num_global = static_cast<int>(task.variables.size());
    if (!task.timing.free && task.timing.offset_free) b.offset_var = b.num_global++;
    if (!BindConstraints(model, task.file, task.constraints, task.crank_link, task.crank_line, task.crank_column,
                         &b.checks, error))
      return false;
    if (!task.placement.x.empty()) {
      for (size_t j = 0; j < task.variables.size(); ++j) {
        if (task.variables[j].name == task.placement.x) b.place_x = static_cast<int>(j);
        if (task.variables[j].name == task.placement.y) b.place_y = static_cast<int>(j);
        if (task.variables[j].name == task.placement.angle) b.place_angle = static_cast<int>(j);
      }
      // The placement must move the model rigidly: the point at the model's values placed at
      // (0, 0, 0) and at (0.3, -0.2, 0.4) (the input measured from the angle), at the first
      // of a few input angles where it assembles, to 1e-9 of the point's size.
      Params p0 = base, p1 = base;
      auto set = [&](Params* p, const std::string& name, double value) {
        *C::FindParameter(model, p, name.c_str()) = value;
      };
      set(&p0, task.placement.x, 0), set(&p0, task.placement.y, 0), set(&p0, task.placement.angle, 0);
      set(&p1, task.placement.x, 0.3), set(&p1, task.placement.y, -0.2);
      set(&p1, task.placement.angle, 0.4);
      C::ParametersSet(model, &p0), C::ParametersSet(model, &p1);
      bool rigid = false;
      for (int k = 0; k < 12 && !rigid; ++k) {
        const double q = kTwoPi * k / 12;
        VecQ q0, q1;
        q0.resize(1), q1.resize(1);
        q0(0) = q, q1(0) = q + 0.4;
        VecPhi f0, f1;
        f0.resize(C::Nphi(model)), f1.resize(C::Nphi(model));
        for (int i = 0; i < C::Nphi(model); ++i) f0(i) = f1(i) = C::AssemblyPhi(model)[i];
        const auto s0 = C::Solve(model, p0, q0, &f0, C::DefaultModes(model), kSolveIterations, 0.0);
        const auto s1 = C::Solve(model, p1, q1, &f1, C::DefaultModes(model), kSolveIterations, 0.0);
        using Status = decltype(s0.status);
        if (s0.status != Status::kConverged || s1.status != Status::kConverged) continue;
        typename ModelTypes<M>::Coefficients c0, c1;
        C::Coeffs(model, p0, q0, f0, &c0);
        C::Coeffs(model, p1, q1, f1, &c1);
        const double x0 = c0.r_P(0, b.point), y0 = c0.r_P(1, b.point);
        const double xr = 0.3 + std::cos(0.4) * x0 - std::sin(0.4) * y0, yr = -0.2 + std::sin(0.4) * x0 + std::cos(0.4) * y0;
        const double size = 1 + std::hypot(x0, y0);
        if (!(std::hypot(c1.r_P(0, b.point) - xr, c1.r_P(1, b.point) - yr) <= 1e-9 * size)) {
          *error = where(task.placement.line, task.placement.column) +
                   "placement: these parameters do not place the model rigidly (the point moves otherwise when they change); "
                   "remove `placement:` or name the frame's x, y and angle";
          return false;
        }
        rigid = true;
      }
      if (!rigid) {
        *error = where(task.placement.line, task.placement.column) +
                 "placement: the model does not assemble at the model's values to check it";
        return false;
      }
    }
    *out = b;
    return true;
  }
}

/// The same on a generated model's type (its one object, GeneratedModel<M>()).
template <class M>
bool BindPathTask(const PathTask& task, const typename M::template ParamsT<double>& base, BoundPath<M>* out,
                  std::string* error) {
  return BindPathTask(GeneratedModel<M>(), task, base, out, error);
}

/// Whether Phi_phi is regular by the project's one singular-configuration threshold
/// (core/constants.h: 1/cond_1(Phi_phi) >= kMinRcond, the position solver's
/// Options::min_rcond, the same test as its Classify): false at a dead point or a change
/// point, or so near one that K has lost six digits, where the runtime's continuation and the
/// sweep refuse the configuration.
template <class Matrix>
bool Regular(const Matrix& Phi_phi) {
  double cond = kInf, det = 0;
  ConditionAndDeterminant(Phi_phi, &cond, &det);
  return det != 0 && std::isfinite(det) && cond * kMinRcond <= 1.0;
}

/// The configuration at input q on the model's assembly mode (M::Solve from the assembly values
/// on M::kDefaultModes) into *phi; false where it does not assemble. With `judge`, also false
/// where it is not Regular(). Every solve of a candidate (path, function and motion tasks: the
/// path evaluator judges the Phi_phi its coefficients carry) and the written model's assembly
/// (WriteSynthesizedModel) go through here. `modes`: another assembly mode than the model's
/// (exact synthesis: a solution on the mirror mode; nullptr: kDefaultModes).

template <class M>
bool SolveOnMode(const M& model, const typename ModelTypes<M>::Params& p, double q, typename ModelTypes<M>::VecPhi* phi,
                 bool judge = true, const typename ModelCalls<M>::Modes* modes = nullptr) {
  using C = ModelCalls<M>;
  using T = ModelTypes<M>;
  typename T::VecQ qv;
  qv.resize(C::Nq(model));
  qv(0) = q;
  typename T::VecPhi ph;
  ph.resize(C::Nphi(model));
  for (int i = 0; i < C::Nphi(model); ++i) ph(i) = C::AssemblyPhi(model)[i];
  const auto report =
      C::Solve(model, p, qv, &ph, modes != nullptr ? *modes : C::DefaultModes(model), kSolveIterations, 0.0);
  using Status = decltype(report.status);
  if (report.status != Status::kConverged || !ph.allFinite()) return false;
  if (judge) {
    typename T::MatCPhi Phi_phi;
    C::Phi(model, p, qv, ph, nullptr, &Phi_phi, nullptr);
    if (!Regular(Phi_phi)) return false;
  }
  *phi = ph;
  return true;
}
/// The same on a generated model's type (default-constructed: its functions are static).
template <class M>
bool SolveOnMode(const typename M::template ParamsT<double>& p, double q, Eigen::Matrix<double, M::kNphi, 1>* phi,
                 bool judge = true, const std::array<int, M::kNumBlocks>* modes = nullptr) {
  return SolveOnMode(M(), p, q, phi, judge, modes);
}

/// A candidate and what its checks found.
struct Candidate {
  std::vector<double> x;       ///< the global vector: design variables (+ the free offset)
  std::vector<double> q;       ///< the input angle at each target
  double error = kInf;         ///< sum of squared distances to the targets
  double violation = kInf;     ///< 0: no defect
  std::string defect;          ///< the first defect found, "" if none
  double mu_min = kInf, mu_max = -kInf;  ///< transmission angles over the checked motion (rad)
  std::vector<double> distance;  ///< |r_P(q_i) - T_i| per target
  bool feasible() const { return violation == 0; }
};

/// Deb's rule: a feasible candidate beats an infeasible one, two feasible ones compare their
/// error, two infeasible ones their violation. For every kind of candidate (path, function:
/// feasible(), error, violation).
template <class C>
bool Better(const C& a, const C& b) {
  if (a.feasible() != b.feasible()) return a.feasible();
  if (a.feasible()) return a.error < b.error;
  return a.violation < b.violation;
}

/// Evaluates candidates of a bound task. One per thread (it counts what it did).
template <class M>
class PathEvaluator {
 public:
  using C = ModelCalls<M>;
  using Params = typename ModelTypes<M>::Params;
  using VecQ = typename ModelTypes<M>::VecQ;
  using VecPhi = typename ModelTypes<M>::VecPhi;
  using Coeffs = typename ModelTypes<M>::Coefficients;

  explicit PathEvaluator(const BoundPath<M>& b) : b_(b), model_(*b.model) {}

  const BoundPath<M>& bound() const { return b_; }
  const M& model() const { return model_; }
  long long evaluations = 0;  ///< candidate evaluations (global stage) and residual evaluations
  long long solves = 0;       ///< position solves

  /// The model's parameters with the design variables x (the first task.variables.size()).
  Params ParamsOf(const std::vector<double>& x) const {
    Params p = b_.base;
    for (size_t j = 0; j < b_.task.variables.size(); ++j)
      *C::FindParameter(model_, &p, b_.task.variables[j].name.c_str()) = x[j];
    C::ParametersSet(model_, &p);
    return p;
  }

  /// The prescribed timing's q_i (for free timing: not used).
  double PrescribedQ(const std::vector<double>& x, int i) const {
    const Timing& t = b_.task.timing;
    const double offset = b_.offset_var >= 0 ? x[static_cast<size_t>(b_.offset_var)] : t.offset;
    const double rel = b_.relative_to >= 0 ? x[static_cast<size_t>(b_.relative_to)] : b_.relative_fixed;
    return offset + t.angles[static_cast<size_t>(i)] + rel;
  }

  /// The point at q on the model's assembly mode; false if it does not assemble there or is
  /// singular by the project's threshold (SolveOnMode). Fills the coefficients (r_P, K_P) and
  /// phi.
  bool PointAt(const Params& p, double q, VecPhi* phi, Coeffs* c) {
    ++solves;
    VecPhi ph;
    const bool judge_coefficients = C::CoeffsHavePhi(model_);
    if (!SolveOnMode(model_, p, q, &ph, /*judge=*/!judge_coefficients)) return false;
    VecQ qv;
    qv.resize(1);
    qv(0) = q;
    C::Coeffs(model_, p, qv, ph, c);
    if constexpr (ModelFeatures<M>::kCoeffsHavePhi) {
      if (judge_coefficients && !Regular(c->Phi_phi)) return false;
    }
    if (!c->r_P.allFinite()) return false;
    *phi = ph;
    return true;
  }

  /// The violation of the constraints that need no position solve (CheckParameterConstraints:
  /// link lengths, Grashof, the crank, link_ratio, the ground region) at x; 0: met. Not an
  /// evaluation (the design checks' closed form and the ground points only).
  double ParameterViolation(const std::vector<double>& x) const {
    double violation = 0;
    CheckParameterConstraints(model_, ParamsOf(x), b_.task.constraints, b_.checks, [&](double amount, const std::string&) {
      if (amount > 0) violation += amount;
    });
    return violation;
  }

  /// The placement fitted to the targets (task.placement, prescribed timing): the points of x
  /// with the frame at (0, 0, 0), then the rigid motion that brings them nearest the targets
  /// in least squares (Procrustes in the plane: the angle atan2(sum p x t, sum p . t) of the
  /// centred points, the translation between the centroids), each clamped into its bounds
  /// (the angle wrapped first). *x changed in place; false (x unchanged) if a target's point
  /// does not assemble.
  bool Place(std::vector<double>* x) {
    std::vector<double> local = *x;
    local[static_cast<size_t>(b_.place_x)] = 0, local[static_cast<size_t>(b_.place_y)] = 0;
    local[static_cast<size_t>(b_.place_angle)] = 0;
    const Params p = ParamsOf(local);
    const int n = b_.n;
    std::vector<double> px(static_cast<size_t>(n)), py(static_cast<size_t>(n));
    VecPhi phi;
    Coeffs co;
    double pcx = 0, pcy = 0, tcx = 0, tcy = 0;
    for (int i = 0; i < n; ++i) {
      if (!PointAt(p, PrescribedQ(local, i), &phi, &co)) return false;
      px[static_cast<size_t>(i)] = co.r_P(0, b_.point), py[static_cast<size_t>(i)] = co.r_P(1, b_.point);
      pcx += px[static_cast<size_t>(i)] / n, pcy += py[static_cast<size_t>(i)] / n;
      tcx += b_.task.tx[static_cast<size_t>(i)] / n, tcy += b_.task.ty[static_cast<size_t>(i)] / n;
    }
    double s_dot = 0, s_cross = 0;
    for (int i = 0; i < n; ++i) {
      const double ax = px[static_cast<size_t>(i)] - pcx, ay = py[static_cast<size_t>(i)] - pcy;
      const double bx = b_.task.tx[static_cast<size_t>(i)] - tcx, by = b_.task.ty[static_cast<size_t>(i)] - tcy;
      s_dot += ax * bx + ay * by;
      s_cross += ax * by - ay * bx;
    }
    const std::vector<Variable>& v = b_.task.variables;
    auto clamp = [&](int j, double value) {
      return std::min(v[static_cast<size_t>(j)].hi, std::max(v[static_cast<size_t>(j)].lo, value));
    };
    double angle = std::atan2(s_cross, s_dot);
    const Variable& va = v[static_cast<size_t>(b_.place_angle)];
    while (angle < va.lo && angle + kTwoPi <= va.hi) angle += kTwoPi;
    while (angle > va.hi && angle - kTwoPi >= va.lo) angle -= kTwoPi;
    angle = clamp(b_.place_angle, angle);
    const double c = std::cos(angle), s = std::sin(angle);
    (*x)[static_cast<size_t>(b_.place_angle)] = angle;
    (*x)[static_cast<size_t>(b_.place_x)] = clamp(b_.place_x, tcx - (c * pcx - s * pcy));
    (*x)[static_cast<size_t>(b_.place_y)] = clamp(b_.place_y, tcy - (s * pcx + c * pcy));
    return true;
  }

  /// The global stage's evaluation of x: the placement fitted (task.placement), the timing
  /// prescribed or projected, then Check().
  Candidate Evaluate(const std::vector<double>& x_in) {
    ++evaluations;
    Candidate cand;
    std::vector<double> x = x_in;
    if (b_.place_x >= 0) Place(&x);
    cand.x = x;
    const Params p = ParamsOf(x);
    const int n = b_.n;
    cand.q.assign(static_cast<size_t>(n), 0.0);
    if (!b_.task.timing.free) {
      for (int i = 0; i < n; ++i) cand.q[static_cast<size_t>(i)] = PrescribedQ(x, i);
    } else if (!Project(p, &cand.q)) {
      cand.violation = 1e6;
      cand.defect = "the mechanism does not assemble at any sampled input angle";
      return cand;
    }
    Check(p, &cand);
    return cand;
  }

  /// The checks and the error of cand (x and q given).
  void Check(const Params& p, Candidate* cand) {
    const PathTask& t = b_.task;
    const Constraints& c = t.constraints;
    const int n = b_.n;
    double violation = 0;
    std::string defect;
    auto flag = [&](double amount, const std::string& what) {
      if (!(amount > 0)) return;
      violation += amount;
      if (defect.empty()) defect = what;
    };
    cand->error = 0;
    cand->distance.assign(static_cast<size_t>(n), kInf);
    VecPhi phi;
    Coeffs co;
    for (int i = 0; i < n; ++i) {
      const double q = cand->q[static_cast<size_t>(i)];
      if (!std::isfinite(q) || !PointAt(p, q, &phi, &co)) {
        flag(1.0, "target " + std::to_string(i + 1) + ": the mechanism does not assemble on its mode at its input angle");
        continue;
      }
      const double dx = co.r_P(0, b_.point) - t.tx[static_cast<size_t>(i)];
      const double dy = co.r_P(1, b_.point) - t.ty[static_cast<size_t>(i)];
      cand->distance[static_cast<size_t>(i)] = std::hypot(dx, dy);
      cand->error += dx * dx + dy * dy;
    }
    // Link lengths, Grashof, the crank, the ground region.
    const bool full_turn = CheckParameterConstraints(model_, p, c, b_.checks, flag);
    // Order of the targets along the motion (free timing).
    std::vector<double> dq(static_cast<size_t>(n), 0.0);
    if (t.timing.free) {
      for (int i = 0; i < n; ++i) dq[static_cast<size_t>(i)] = Wrap(cand->q[static_cast<size_t>(i)] - cand->q[0]);
      // The last target where the first is (a closed curve's end): reached after a full turn.
      if (n > 2 && dq[static_cast<size_t>(n - 1)] < 1e-6) dq[static_cast<size_t>(n - 1)] += kTwoPi;
      if (c.order) {
        double back = 0;
        for (int i = 1; i < n; ++i) back += std::max(0.0, dq[static_cast<size_t>(i - 1)] - dq[static_cast<size_t>(i)]);
        flag(back, "the targets are not reached in input order");
      }
    }
    // The motion: from target to target (or the full turn), on the same mode, no dead point.
    const double step = kTwoPi / t.search.curve_samples;
    double mu_min = kInf, mu_max = -kInf;
    auto walk = [&](double q0, double q1, int from) {
      const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(q1 - q0) / step)));
      for (int s = 0; s <= steps; ++s) {
        const double q = q0 + (q1 - q0) * s / steps;
        if (!PointAt(p, q, &phi, &co)) {
          flag(1.0 / (steps + 1), from < 0 ? "the crank does not turn fully on the assembly mode"
                                           : "between targets " + std::to_string(from + 1) + " and " +
                                                 std::to_string(from + 2) +
                                                 " the mechanism leaves its assembly branch (a dead point)");
          continue;
        }
        if (C::NumTransmissionAngles(model_) > 0) {
          VecQ qv;
          qv.resize(1);
          qv(0) = q;
          TransmissionAngleVector mu;
          C::TransmissionAngles(model_, p, qv, phi, &mu);
          for (int k = 0; k < C::NumTransmissionAngles(model_); ++k) {
            mu_min = std::min(mu_min, mu(k));
            mu_max = std::max(mu_max, mu(k));
          }
        }
      }
    };
    if (violation == 0 || full_turn) {
      if (full_turn) {
        walk(cand->q[0], cand->q[0] + kTwoPi, -1);
      } else if (t.timing.free) {
        // Increasing input from the first target through the others (by their angle from it).
        std::vector<double> sorted(dq);
        std::sort(sorted.begin(), sorted.end());
        for (int i = 0; i + 1 < n; ++i)
          walk(cand->q[0] + sorted[static_cast<size_t>(i)], cand->q[0] + sorted[static_cast<size_t>(i + 1)], i);
      } else {
        for (int i = 0; i + 1 < n; ++i) walk(cand->q[static_cast<size_t>(i)], cand->q[static_cast<size_t>(i + 1)], i);
      }
    }
    cand->mu_min = mu_min;
    cand->mu_max = mu_max;
    if (c.has_mu && std::isfinite(mu_min)) {
      flag(c.mu_lo - mu_min, "the transmission angle falls below its bound");
      flag(mu_max - c.mu_hi, "the transmission angle rises above its bound");
    }
    if (!std::isfinite(cand->error)) flag(1.0, "the error is not finite");
    cand->violation = violation;
    cand->defect = defect;
  }

  /// Free timing: each target's input angle on the coupler curve (nearest sample, then
  /// Gauss–Newton in q). false if the curve has no assemblable sample.
  bool Project(const Params& p, std::vector<double>* q) {
    const PathTask& t = b_.task;
    const int samples = t.search.curve_samples;
    samples_x_.assign(static_cast<size_t>(samples), kInf);
    samples_y_.assign(static_cast<size_t>(samples), kInf);
    VecPhi phi;
    Coeffs co;
    bool any = false;
    for (int k = 0; k < samples; ++k) {
      if (!PointAt(p, kTwoPi * k / samples, &phi, &co)) continue;
      samples_x_[static_cast<size_t>(k)] = co.r_P(0, b_.point);
      samples_y_[static_cast<size_t>(k)] = co.r_P(1, b_.point);
      any = true;
    }
    if (!any) return false;
    for (int i = 0; i < b_.n; ++i) {
      const double tx = t.tx[static_cast<size_t>(i)], ty = t.ty[static_cast<size_t>(i)];
      int best = -1;
      double best_d = kInf;
      for (int k = 0; k < samples; ++k) {
        const double d = std::pow(samples_x_[static_cast<size_t>(k)] - tx, 2) + std::pow(samples_y_[static_cast<size_t>(k)] - ty, 2);
        if (d < best_d) best_d = d, best = k;
      }
      double qi = kTwoPi * best / samples;
      for (int it = 0; it < 4; ++it) {
        if (!PointAt(p, qi, &phi, &co)) break;
        const double ex = co.r_P(0, b_.point) - tx, ey = co.r_P(1, b_.point) - ty;
        const double kx = co.K_P(2 * b_.point, 0), ky = co.K_P(2 * b_.point + 1, 0);
        const double kk = kx * kx + ky * ky;
        if (!(kk > 0)) break;
        double dq = -(ex * kx + ey * ky) / kk;
        dq = std::max(-step_limit_, std::min(step_limit_, dq));
        double trial = qi + dq;
        VecPhi phi2;
        Coeffs co2;
        if (!PointAt(p, trial, &phi2, &co2)) break;
        const double e2 = std::pow(co2.r_P(0, b_.point) - tx, 2) + std::pow(co2.r_P(1, b_.point) - ty, 2);
        if (!(e2 < ex * ex + ey * ey)) break;
        qi = trial;
      }
      (*q)[static_cast<size_t>(i)] = qi;
    }
    return true;
  }

 private:
  using TransmissionAngleVector =
      Eigen::Matrix<double, ModelFeatures<M>::kNumTransmissionAngles, 1, 0,
                    ModelFeatures<M>::kNumTransmissionAngles == Eigen::Dynamic ? ModelView::kMaxTransmissionAngles
                                                                              : ModelFeatures<M>::kNumTransmissionAngles,
                    1>;
  const BoundPath<M>& b_;
  const M& model_;
  std::vector<double> samples_x_, samples_y_;
  double step_limit_ = 0.2;
};

}  // namespace mechgen::synthesis
