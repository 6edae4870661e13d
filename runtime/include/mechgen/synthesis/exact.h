/**
 * \file synthesis/exact.h
 * Exact path synthesis as a task (issue 44): `synthesis: path` with `kind: exact`, five
 * precision points of a four-bar's coupler point with both ground pivots given. Every isolated
 * solution by homotopy continuation (SolveFivePointsWithPivots, synthesis/exact_path.h); each
 * real one written into the task's model (its parameters named by the task) and judged by the
 * model's own generated kinematics and the defect checks:
 *   - the generated kinematics: at each point's crank angle (from the solution), M::Solve on
 *     either assembly mode of the four-bar's block; the mode whose coupler point is within
 *     kExactCheckTolerance (1 + |AD|) of the point reaches it; the mode reaching the first
 *     point is the one the written model assembles on (its `assembly:` hints are that
 *     configuration, WriteSynthesizedModel);
 *   - one branch (the side of BD on which C lies, the same at all five), in order (the crank
 *     turning one way meets the points in the task's order within one turn), Grashof and
 *     whether the crank turns fully: the verdicts of exact_path.h;
 *   - for a solution on one branch and in order: the motion from point to point (the crank in
 *     steps of at most 1 deg, the way it turns) assembles on the written mode, regular by the
 *     project's one threshold (SolveOnMode), and the runtime's continuation (PositionSolver,
 *     steps of at most 10 deg) follows it through the five points, each reached within the
 *     tolerance: a solution that passes is defect-free.
 * A path that fails or ends at a singular point is a row of its own with its figures (t, the
 * residual, rcond), never dropped; the run is `complete` only when every path ended at a
 * nonsingular solution or at infinity and no two reached one solution.
 * Needs yaml-cpp and the runtime's position solver.
 */
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "mechgen/io/csv.h"
#include "mechgen/position/solver.h"
#include "mechgen/synthesis/exact_path.h"
#include "mechgen/synthesis/nine_point.h"
#include "mechgen/synthesis/output.h"
#include "mechgen/synthesis/task.h"
#include "mechgen/table/columns.h"

namespace mechgen::synthesis {

/// A real solution reaches a point when the generated coupler point is this close, relative to
/// 1 + |AD| (issue 44: "checked to 1e-8 by the generated kinematics").
constexpr double kExactCheckTolerance = 1e-8;

/// A `kind: exact` path task (docs/synthesis.md).
struct ExactTask {
  std::string file, model;
  std::string point;  ///< the model's coupler point, e.g. coupler.P
  FivePointTask five;
  /// Nine targets and no pivots: the general nine-point problem (nine_point.h; RunNinePointTask).
  bool nine = false;
  nine_point::NinePoints nine_points{};
  /// The model's parameters for the crank a, coupler b, rocker c, ground d, the coupler point
  /// xi, eta, and the frame x0, y0, theta0, in this order; the last three "" when the task does
  /// not name them (a model whose frame is fixed: its pivots must be the task's).
  std::vector<std::string> parameters;
  int point_line = 1, point_column = 1, pivots_line = 1, pivots_column = 1, params_line = 1, params_column = 1;
};

inline const std::vector<std::string>& ExactParameterKeys() {
  static const std::vector<std::string> keys = {"crank", "coupler", "rocker", "ground", "xi", "eta", "x0", "y0", "theta0"};
  return keys;
}

/// A path task's `kind:` ("search" without one), "" and *error when the file cannot be read or
/// is not YAML (ParseTask and ParseExactTask say what else is wrong).
inline std::string PathTaskKind(const std::string& path, std::string* error) {
  std::string text;
  if (!task_internal::ReadTaskText(path, &text, error)) return "";
  try {
    const YAML::Node root = YAML::Load(text);
    if (root.IsMap() && root["kind"] && root["kind"].IsScalar()) return root["kind"].Scalar();
    return "search";
  } catch (const YAML::Exception& e) {
    *error = task_internal::Where(path, e.mark) + "not valid YAML: " + e.msg;
    return "";
  }
}

/// Reads a `synthesis: path`, `kind: exact` task; false and *error (FILE:LINE:COLUMN: error:
/// what to change) on the first problem.
inline bool ParseExactTask(const std::string& path, ExactTask* task, std::string* error) {
  using namespace task_internal;
  *task = ExactTask();
  task->file = path;
  YAML::Node root;
  if (!LoadTaskRoot(path, "`synthesis: path`, `kind: exact`, `point`, `pivots`, `targets`, `parameters`", &root, error))
    return false;
  try {
    Known(path, root, {"synthesis", "kind", "model", "point", "pivots", "targets", "parameters"},
          "an exact path task (kind: exact)");
    const YAML::Node kind = Required(path, root, "synthesis", "synthesis: path");
    if (!kind.IsScalar() || kind.Scalar() != "path")
      throw Error{Where(path, kind.Mark()) + "synthesis: kind: exact is path synthesis; write synthesis: path"};
    const YAML::Node exact = Required(path, root, "kind", "kind: exact");
    if (!exact.IsScalar() || exact.Scalar() != "exact")
      throw Error{Where(path, exact.Mark()) + "kind: expected exact (or no kind: for the search)"};
    if (const YAML::Node m = root["model"]) {
      if (!m.IsScalar()) throw Error{Where(path, m.Mark()) + "model: expected a file name"};
      task->model = m.Scalar();
    }
    const YAML::Node point = Required(path, root, "point", "the model's coupler point that passes through the targets, e.g. coupler.P");
    if (!point.IsScalar()) throw Error{Where(path, point.Mark()) + "point: expected a point name such as coupler.P"};
    task->point = point.Scalar();
    task->point_line = point.Mark().line + 1, task->point_column = point.Mark().column + 1;

    const YAML::Node pivots = root["pivots"];
    task->nine = !pivots;
    if (pivots) {
      if (!pivots.IsMap()) throw Error{Where(path, pivots.Mark()) + "pivots: expected {crank: [x, y], rocker: [x, y]}"};
      Known(path, pivots, {"crank", "rocker"}, "pivots");
      task->pivots_line = pivots.Mark().line + 1, task->pivots_column = pivots.Mark().column + 1;
      for (const char* key : {"crank", "rocker"}) {
        const YAML::Node v = Required(path, pivots, key, std::string("the ") + key + "'s ground pivot [x, y]");
        if (!v.IsSequence() || v.size() != 2) throw Error{Where(path, v.Mark()) + "pivots." + key + ": expected [x, y]"};
        std::array<double, 2>& xy = key[0] == 'c' ? task->five.crank_pivot : task->five.rocker_pivot;
        xy[0] = Number(path, v[0], std::string("pivots.") + key + " x");
        xy[1] = Number(path, v[1], std::string("pivots.") + key + " y");
      }
      const double ground = std::hypot(task->five.rocker_pivot[0] - task->five.crank_pivot[0],
                                       task->five.rocker_pivot[1] - task->five.crank_pivot[1]);
      if (!(ground > 0) || !std::isfinite(ground))
        throw Error{Where(path, pivots.Mark()) + "pivots: the crank's and the rocker's pivots must be two distinct points"};
    }

    const YAML::Node targets =
        Required(path, root, "targets", "five precision points with pivots:, nine without, [[x, y], ...]");
    const size_t wanted = task->nine ? 9 : 5;
    if (!targets.IsSequence() || targets.size() != wanted)
      throw Error{Where(path, targets.Mark()) + "targets: kind: exact takes exactly " +
                  (task->nine ? std::string("nine precision points [[x, y], ...] without pivots (the general nine-point "
                                            "problem: 8652 four-bars for generic points)")
                              : std::string("five precision points [[x, y], ...] with both pivots given (finitely many "
                                            "four-bars, 36 for generic data)")) +
                  "; got " + (targets.IsSequence() ? std::to_string(targets.size()) : std::string("no list")) +
                  (task->nine ? "; with five points give pivots: {crank: [x, y], rocker: [x, y]}"
                              : "; for nine points leave out pivots:") +
                  "; for another number use the search (no kind:)"};
    for (size_t j = 0; j < wanted; ++j) {
      const YAML::Node t = targets[j];
      if (!t.IsSequence() || t.size() != 2) throw Error{Where(path, t.Mark()) + "a target: expected [x, y]"};
      std::array<double, 2>& xy = task->nine ? task->nine_points[j] : task->five.points[j];
      xy = {Number(path, t[0], "target x"), Number(path, t[1], "target y")};
      for (size_t k = 0; k < j; ++k)
        if ((task->nine ? task->nine_points[k] : task->five.points[k]) == xy)
          throw Error{Where(path, t.Mark()) + "target " + std::to_string(j + 1) + " is target " + std::to_string(k + 1) +
                      " again; give " + (task->nine ? "nine" : "five") + " distinct points"};
    }

    const YAML::Node params =
        Required(path, root, "parameters",
                 "the model's parameters {crank: a, coupler: b, rocker: c, ground: d, xi: xi, eta: eta} (and x0: x0, "
                 "y0: y0, theta0: theta0 when the model places its frame by them)");
    if (!params.IsMap()) throw Error{Where(path, params.Mark()) + "parameters: expected a mapping"};
    Known(path, params, ExactParameterKeys(), "parameters");
    task->params_line = params.Mark().line + 1, task->params_column = params.Mark().column + 1;
    const int placed = (params["x0"] ? 1 : 0) + (params["y0"] ? 1 : 0) + (params["theta0"] ? 1 : 0);
    if (placed != 0 && placed != 3)
      throw Error{Where(path, params.Mark()) + "parameters: give the frame's x0, y0 and theta0 together, or none (a model "
                                                "whose pivots are fixed where the task puts them)"};
    for (const std::string& key : ExactParameterKeys()) {
      const YAML::Node v = params[key];
      if (!v) {
        if (placed == 3 || (key != "x0" && key != "y0" && key != "theta0"))
          Required(path, params, key, "the model's parameter for it");
        task->parameters.push_back("");
        continue;
      }
      if (!v.IsScalar()) throw Error{Where(path, v.Mark()) + "parameters." + key + ": expected a parameter name"};
      for (const std::string& other : task->parameters)
        if (other == v.Scalar())
          throw Error{Where(path, v.Mark()) + "parameters." + key + ": '" + v.Scalar() + "' is named twice"};
      task->parameters.push_back(v.Scalar());
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

/// A task bound to the model M: the point's index and the parameters' names checked.
template <class M>
struct BoundExact {
  const M* model = nullptr;  ///< reached through ModelCalls<M> (a generated model, or the model view); outlives this
  ExactTask task;
  int point = -1;
  typename ModelTypes<M>::Params base;  ///< every other parameter (the model's, or --set's)
};

/// The parameters of the four-bar `bar` in the model (base's for every parameter the task does not name).
template <class M, size_t K>
typename ModelTypes<M>::Params ExactParams(const BoundExact<M>& b, const FourBarOf<K>& bar) {
  using C = ModelCalls<M>;
  auto p = b.base;
  const double values[9] = {bar.a, bar.b, bar.c, bar.d, bar.xi, bar.eta, bar.x0, bar.y0, bar.theta0};
  for (size_t k = 0; k < 9; ++k)
    if (!b.task.parameters[k].empty()) *C::FindParameter(*b.model, &p, b.task.parameters[k].c_str()) = values[k];
  C::ParametersSet(*b.model, &p);
  return p;
}

/// Checks the task against the model: one revolute input, the point among its outputs, the
/// parameters its own, and its ground pivots where the task puts them (its ground points, with
/// the ground's length and the frame set from the pivots). false and *error (the task file's
/// line and column) otherwise.
template <class M>
bool BindExactTask(const M& model, const ExactTask& task, const typename ModelTypes<M>::Params& base,
                   BoundExact<M>* out, std::string* error) {
  using C = ModelCalls<M>;
  auto where = [&](int line, int column) {
    return task.file + ":" + std::to_string(line) + ":" + std::to_string(column) + ": error: ";
  };
  BoundExact<M> b;
  b.model = &model;
  b.task = task;
  b.base = base;
  if (C::Nq(model) != 1 || !C::QIsAngle(model, 0))
    return *error = where(1, 1) + "kind: exact needs a four-bar model with one revolute input (the crank's angle); '" +
                    std::string(C::Name(model)) + "' has " + std::to_string(C::Nq(model)) + " input(s)",
           false;
  if (C::NumPoints(model) == 0) {
    return *error = where(task.point_line, task.point_column) + "the model '" + std::string(C::Name(model)) +
                    "' has no output points; add the coupler point to its outputs: points:",
           false;
  } else {
    std::string known;
    for (int k = 0; k < C::NumPoints(model); ++k) {
      if (task.point == C::PointName(model, k)) b.point = k;
      known += (k ? ", " : "") + std::string(C::PointName(model, k));
    }
    if (b.point < 0)
      return *error = where(task.point_line, task.point_column) + "point: '" + task.point +
                      "' is not one of the model's output points (" + known + ")",
             false;
  }
  for (size_t k = 0; k < task.parameters.size(); ++k) {
    const std::string& name = task.parameters[k];
    if (name.empty()) continue;
    if (C::FindParameter(model, &b.base, name.c_str()) == nullptr) {
      std::string names;
      for (int i = 0; i < C::NumFreeParameters(model); ++i)
        names += (names.empty() ? "" : ", ") + std::string(C::FreeParameterName(model, i));
      return *error = where(task.params_line, task.params_column) + "parameters." + ExactParameterKeys()[k] + ": '" + name +
                      "' is not a parameter of the model (" + names + ")",
             false;
    }
  }
  // The ground pivots: the model's ground points with the ground's length (and the frame) set
  // from the task's pivots must include both (nine points: the pivots are unknowns).
  if (!task.nine && C::NumScenePoints(model) > 0) {
    const auto& A = task.five.crank_pivot;
    const auto& D = task.five.rocker_pivot;
    ExactFourBar frame;
    frame.a = 1, frame.b = 1, frame.c = 1, frame.xi = 0, frame.eta = 0;
    frame.d = std::hypot(D[0] - A[0], D[1] - A[1]);
    frame.x0 = A[0], frame.y0 = A[1], frame.theta0 = std::atan2(D[1] - A[1], D[0] - A[0]);
    auto p = b.base;
    const std::string& ground = task.parameters[3];
    *C::FindParameter(model, &p, ground.c_str()) = frame.d;
    const double placement[3] = {frame.x0, frame.y0, frame.theta0};
    for (size_t k = 6; k < 9; ++k)
      if (!task.parameters[k].empty()) *C::FindParameter(model, &p, task.parameters[k].c_str()) = placement[k - 6];
    C::ParametersSet(model, &p);
    typename ModelTypes<M>::MatScene r;
    GroundScene(model, p, &r);
    const double tol = 1e-9 * (1 + frame.d + std::hypot(A[0], A[1]) + std::hypot(D[0], D[1]));
    bool has_a = false, has_d = false;
    std::string seen;
    for (int k = 0; k < C::NumScenePoints(model); ++k) {
      if (C::ScenePointLink(model, k) != C::GroundLink(model)) continue;
      has_a = has_a || std::hypot(r(0, k) - A[0], r(1, k) - A[1]) <= tol;
      has_d = has_d || std::hypot(r(0, k) - D[0], r(1, k) - D[1]) <= tol;
      seen += (seen.empty() ? "" : ", ") + std::string(C::ScenePointName(model, k)) + " (" +
              Short(r(0, k), 9) + ", " + Short(r(1, k), 9) + ")";
    }
    if (!has_a || !has_d)
      return *error = where(task.pivots_line, task.pivots_column) + "pivots: with " + ground + " = " + Short(frame.d, 9) +
                      (task.parameters[6].empty() ? std::string()
                                                  : " and the frame " + task.parameters[6] + ", " + task.parameters[7] +
                                                        ", " + task.parameters[8] + " set from the pivots") +
                      " the model's ground points are " + seen + ", not the task's pivots; name the parameters that place " +
                      "the model's frame (parameters: {x0: ..., y0: ..., theta0: ...}) or give the pivots where the " +
                      "model has them",
             false;
  }
  *out = b;
  return true;
}

/// The same on a generated model's type (its one object, GeneratedModel<M>()).
template <class M>
bool BindExactTask(const ExactTask& task, const typename M::template ParamsT<double>& base, BoundExact<M>* out,
                   std::string* error) {
  return BindExactTask(GeneratedModel<M>(), task, base, out, error);
}

/// One row of the answer: a distinct nonsingular solution (real or complex), or a path that
/// ended singular or failed.
struct ExactRow {
  int number = 0;                ///< 1-based, the CSV's `solution`
  std::string status;            ///< "real", "complex", "singular", "failed"
  int path = -1;                 ///< the first path that reached it (0-based start solution)
  double t = 1, residual = 0, rcond = 0;
  homotopy::VecN<12> z = homotopy::VecN<12>::Zero();  ///< on the scaled data (exact_path.h)
  bool has_bar = false;          ///< a real solution: `bar` and the checks below
  ExactFourBar bar;
  int mode = 0;                  ///< the block-0 assembly mode reaching the first point (the written model's), 0 none
  std::array<int, 5> point_mode{};       ///< the mode reaching each point (0: neither)
  std::array<double, 5> distance{};      ///< the generated coupler point's distance from each point on point_mode (or the nearer mode)
  double check = 0;              ///< the largest of `distance`
  bool reached = false;          ///< every point reached (within the tolerance) on its point_mode
  std::string motion;            ///< "ok", "not run" (not on one branch in order), or why the motion fails
  std::string defect;            ///< "" defect-free, else the first: degenerate link, branch, order, kinematics, dead point, continuation
  std::string file;              ///< the written model's file name ("" none)
  std::string not_written;       ///< why no model file was written
  WrittenAssembly written;
};

/// What a `kind: exact` task gives.
struct ExactRun {
  ExactPathResult result;
  std::vector<ExactRow> rows;    ///< the distinct nonsingular solutions in the order reached, then the others
  int real = 0, defect_free = 0;
  bool complete = false;         ///< every path finite and distinct, or at infinity
  double seconds = 0;            ///< the continuation's wall time (report only)
};

namespace exact_internal {

template <class M>
double CouplerDistance(const BoundExact<M>& b, const typename ModelTypes<M>::Params& p, double q, int mode,
                       const std::array<double, 2>& target) {
  using C = ModelCalls<M>;
  typename C::Modes modes = C::DefaultModes(*b.model);
  modes[0] = mode;
  typename ModelTypes<M>::VecPhi phi;
  if (!SolveOnMode(*b.model, p, q, &phi, /*judge=*/false, &modes)) return kInf;
  typename ModelTypes<M>::VecQ qv;
  qv.resize(1);
  qv(0) = q;
  typename ModelTypes<M>::Coefficients co;
  C::Coeffs(*b.model, p, qv, phi, &co);
  const double d = std::hypot(co.r_P(0, b.point) - target[0], co.r_P(1, b.point) - target[1]);
  return std::isfinite(d) ? d : kInf;
}

/// The crank's angle at each point in the order of the motion: from the first point, turning
/// `direction` (+1, -1) by less than a turn to each next (direction 0: the nearest way).
template <size_t K>
std::vector<double> MotionAngles(const FourBarOf<K>& bar) {
  std::vector<double> q = {bar.crank[0]};
  for (int j = 1; j < static_cast<int>(K); ++j) {
    const double d = bar.crank[static_cast<size_t>(j)] - q.back();
    double step = std::remainder(d, kTwoPi);
    if (bar.direction != 0) {
      step = bar.direction * std::fmod(std::fmod(bar.direction * d, kTwoPi) + kTwoPi, kTwoPi);
    }
    q.push_back(q.back() + step);
  }
  return q;
}

/// The motion through the points on `modes`: the crank in steps of at most 1 deg assembles,
/// regular, and the runtime's continuation reaches every point (the K `points`); "" or why not.
template <class M, size_t K>
std::string MotionCheck(const BoundExact<M>& b, const typename ModelTypes<M>::Params& p, const FourBarOf<K>& bar,
                        const std::array<std::array<double, 2>, K>& points, const typename ModelCalls<M>::Modes& modes,
                        double tol, std::string* defect) {
  using C = ModelCalls<M>;
  const M& model = *b.model;
  const std::vector<double> q = MotionAngles(bar);
  typename ModelTypes<M>::VecPhi phi;
  for (int j = 0; j + 1 < static_cast<int>(K); ++j) {
    const double from = q[static_cast<size_t>(j)], to = q[static_cast<size_t>(j + 1)];
    const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(to - from) / (M_PI / 180))));
    for (int s = 1; s < steps; ++s) {
      const double at = from + (to - from) * s / steps;
      if (!SolveOnMode(model, p, at, &phi, /*judge=*/true, &modes)) {
        *defect = "dead point";
        return "between points " + std::to_string(j + 1) + " and " + std::to_string(j + 2) + " the mechanism does not " +
               "assemble regularly on its mode at crank angle " + Short(std::remainder(at, kTwoPi), 9) + " rad";
      }
    }
  }
  if (!SolveOnMode(model, p, q[0], &phi, /*judge=*/true, &modes)) {
    *defect = "dead point";
    return "point 1 is a singular configuration";
  }
  position::PositionSolver<M> solver(model, position::Options(), p);
  typename ModelTypes<M>::VecQ qv;
  qv.resize(1);
  qv(0) = q[0];
  *defect = "continuation";
  if (solver.Assemble(qv, phi, 0, nullptr) != position::Status::kConverged)
    return "the runtime cannot assemble at point 1";
  typename ModelTypes<M>::Coefficients co;
  for (int j = 1; j < static_cast<int>(K); ++j) {
    const double from = q[static_cast<size_t>(j - 1)], to = q[static_cast<size_t>(j)];
    const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(to - from) / (10 * M_PI / 180))));
    for (int s = 1; s <= steps; ++s) {
      qv(0) = from + (to - from) * s / steps;
      if (solver.MoveTo(qv, nullptr) != position::Status::kConverged)
        return "the continuation stops before point " + std::to_string(j + 1);
    }
    C::Coeffs(model, p, solver.state().q, solver.state().phi, &co);
    const auto& P = points[static_cast<size_t>(j)];
    const double d = std::hypot(co.r_P(0, b.point) - P[0], co.r_P(1, b.point) - P[1]);
    if (!(d <= tol))
      return "the continuation reaches point " + std::to_string(j + 1) + " at a distance " + Short(d, 3) +
             " (another branch)";
  }
  defect->clear();
  return "ok";
}

/// The crank's reach on `modes` about q0 (where it assembles regularly): [*lo, *hi] from the
/// first failures up and down (0.5 deg steps, then 40 bisections, less 1e-3 rad); true when it
/// turns fully (no failure within a turn either way).
template <class M>
bool ReachAbout(const M& model, const typename ModelTypes<M>::Params& p, double q0,
                const typename ModelCalls<M>::Modes& modes, double* lo, double* hi) {
  typename ModelTypes<M>::VecPhi phi;
  auto ok = [&](double q) { return SolveOnMode(model, p, q, &phi, /*judge=*/true, &modes); };
  const double step = M_PI / 360;
  double ends[2] = {q0, q0};
  for (int k = 0; k < 2; ++k) {
    const double sign = k == 0 ? -1 : 1;
    double good = q0, bad = q0;
    bool failed = false;
    for (int s = 1; s <= 720 && !failed; ++s) {
      const double q = q0 + sign * step * s;
      if (ok(q)) good = q; else bad = q, failed = true;
    }
    if (!failed) return true;
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (good + bad);
      (ok(mid) ? good : bad) = mid;
    }
    ends[k] = std::abs(good - q0) > 1e-3 ? good - sign * 1e-3 : q0;
  }
  *lo = ends[0], *hi = ends[1];
  return false;
}

// The model file of a real solution of an exact task (five points or nine): the model's text
// with the solution's parameters (the task's named ones), assembled on `modes` (modes[0] the
// mode reaching point 1); its range the motion through the points for a defect-free solution,
// for another its crank's reach on that mode about point 1 (WriteSynthesizedModel narrows the
// range to it when the crank does not turn fully: the generator refuses a range where the loop
// cannot close). False with *not_written saying why none is written.
template <class M, class Bar>
bool SolutionModel(const BoundExact<M>& b, const typename ModelTypes<M>::Params& p, const Bar& bar, bool defect_free,
                   const typename ModelCalls<M>::Modes& modes, const std::string& model_text, std::string* text,
                   WrittenAssembly* written, std::string* not_written) {
  if (bar.defect == "degenerate link") {
    *not_written = "a link of zero length";
    return false;
  }
  if (modes[0] == 0) {
    *not_written = "the generated kinematics does not reach point 1 on either mode";
    return false;
  }
  std::vector<std::string> names;
  for (const std::string& n : b.task.parameters)
    if (!n.empty()) names.push_back(n);
  std::vector<double> motion = MotionAngles(bar);
  double lo = 0, hi = 0;
  if (!defect_free && !ReachAbout(*b.model, p, bar.crank[0], modes, &lo, &hi)) motion = {bar.crank[0], lo, hi};
  std::string error;
  if (WriteSynthesizedModel(*b.model, model_text, p, names, motion, text, written, &error, &modes)) return true;
  *not_written = error;
  return false;
}

}  // namespace exact_internal

/**
 * \brief Solves the task, checks every real solution with the model's generated kinematics and
 *        the defect checks, and writes each real one (no link of zero length) into the model's
 *        text (`models`: file name, text; nothing when model_text is empty).
 */
template <class M>
ExactRun RunExactTask(const BoundExact<M>& b, const std::string& model_text, const std::string& model_stem,
                      std::vector<std::pair<std::string, std::string>>* models,
                      const ExactPathOptions& options = ExactPathOptions()) {
  using namespace exact_internal;
  ExactRun run;
  const auto t0 = std::chrono::steady_clock::now();
  run.result = SolveFivePointsWithPivots(b.task.five, options);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const ExactPathResult& r = run.result;
  const auto& sol = r.solutions;
  run.complete = sol.failed == 0 && sol.singular == 0 && sol.duplicates == 0 &&
                 r.num_solutions + sol.at_infinity == r.paths && r.paths > 0;
  const double tol = kExactCheckTolerance * (1 + r.scale);
  // The distinct nonsingular solutions, each with the first path that reached it.
  for (size_t k = 0; k < sol.finite.size(); ++k) {
    ExactRow row;
    row.number = static_cast<int>(run.rows.size()) + 1;
    row.z = sol.finite[k];
    for (const auto& path : sol.paths)
      if (path.status == homotopy::PathStatus::kFinite && path.z == sol.finite[k]) {
        row.path = path.start, row.t = path.t, row.residual = path.residual, row.rcond = path.rcond;
        break;
      }
    row.status = "complex";
    for (const ExactFourBar& bar : r.real)
      if (bar.solution == static_cast<int>(k)) row.status = "real", row.has_bar = true, row.bar = bar;
    run.rows.push_back(row);
  }
  for (ExactRow& row : run.rows) {
    if (!row.has_bar) continue;
    ++run.real;
    const ExactFourBar& bar = row.bar;
    const auto p = ExactParams(b, bar);
    // The generated kinematics at each point's crank angle, on either mode.
    row.reached = true;
    for (int j = 0; j < 5; ++j) {
      const auto& P = b.task.five.points[static_cast<size_t>(j)];
      const double on_plus = CouplerDistance(b, p, bar.crank[static_cast<size_t>(j)], 1, P);
      const double on_minus = CouplerDistance(b, p, bar.crank[static_cast<size_t>(j)], -1, P);
      const int m = on_plus <= on_minus ? 1 : -1;
      const double d = std::min(on_plus, on_minus);
      row.point_mode[static_cast<size_t>(j)] = d <= tol ? m : 0;
      row.distance[static_cast<size_t>(j)] = d;
      row.check = std::max(row.check, d);
      row.reached = row.reached && d <= tol;
    }
    row.mode = row.point_mode[0];
    row.defect = bar.defect;
    row.motion = "not run";
    if (row.defect.empty() && !row.reached) row.defect = "kinematics";
    if (row.defect.empty()) {
      typename ModelCalls<M>::Modes modes = ModelCalls<M>::DefaultModes(*b.model);
      modes[0] = row.mode;
      std::string defect;
      row.motion = MotionCheck(b, p, bar, b.task.five.points, modes, tol, &defect);
      row.defect = defect;
    }
    if (row.defect.empty()) ++run.defect_free;
    // The model file.
    if (model_text.empty() || models == nullptr) continue;
    typename ModelCalls<M>::Modes modes = ModelCalls<M>::DefaultModes(*b.model);
    modes[0] = row.mode;
    std::string text;
    if (!SolutionModel(b, p, bar, row.defect.empty(), modes, model_text, &text, &row.written, &row.not_written)) continue;
    char name[64];
    std::snprintf(name, sizeof name, "%s_exact_%02d.yaml", model_stem.c_str(), row.number);
    row.file = name;
    models->emplace_back(row.file, text);
  }
  // The paths that ended neither at a nonsingular solution nor at infinity: rows of their own.
  for (const auto& path : sol.paths) {
    if (path.status != homotopy::PathStatus::kSingular && path.status != homotopy::PathStatus::kFailed) continue;
    ExactRow row;
    row.number = static_cast<int>(run.rows.size()) + 1;
    row.status = path.status == homotopy::PathStatus::kSingular ? "singular" : "failed";
    row.path = path.start, row.t = path.t, row.residual = path.residual, row.rcond = path.rcond;
    row.z = path.z;
    run.rows.push_back(row);
  }
  return run;
}

/// solutions.csv: one row per ExactRow, the counts and conventions in `#` lines.
inline std::string ExactCsv(const ExactRun& run, const std::string& model_name, const std::string& task_file) {
  using Row = ExactRow;
  const double nan = std::nan("");
  // Every cell a finite number or empty, and no text cell with a comma.
  const auto finite = [nan](double x) { return std::isfinite(x) ? x : nan; };
  const auto cell = [](std::string text) {
    std::replace(text.begin(), text.end(), ',', ';');
    return text;
  };
  table::Columns<Row> columns;
  table::Builder<Row> add(&columns, "");
  add.Text("solution", "the row's number", [](const Row& r) { return std::to_string(r.number); });
  add.Text("status",
           "real or complex (a distinct nonsingular solution), singular (a path that reached t = 1 where F_z is singular "
           "or Newton did not settle) or failed (the step fell below its minimum: t says where)",
           [](const Row& r) { return r.status; });
  add.Text("path", "the first path (0-based start solution of the 256) that reached it",
           [](const Row& r) { return std::to_string(r.path); });
  add.Number("t", "1", "where the path stopped (1: the target system)", [finite](const Row& r) { return finite(r.t); });
  add.Number("residual", "1", "|F(z)|_inf of the polynomial system on the scaled data at the end (0 when not reached)",
             [finite](const Row& r) { return finite(r.residual); });
  add.Number("rcond", "1", "smallest over largest singular value of F_z at the end",
             [finite](const Row& r) { return finite(r.rcond); });
  const char* unknowns[12] = {"x", "xbar", "y", "ybar", "Q1", "Q1bar", "Q2", "Q2bar", "Q3", "Q3bar", "Q4", "Q4bar"};
  for (int i = 0; i < 12; ++i) {
    const std::string u = unknowns[i];
    const std::string what =
        i < 4 ? (i < 2 ? "B_1 - P_1 (the crank's coupler joint from point 1)" : "C_1 - P_1 (the rocker's coupler joint from point 1)")
              : "the coupler's turn e^{i theta_j} from point 1 to point " + std::to_string((i - 4) / 2 + 2);
    const std::string kind = i % 2 == 0 ? "" : " (isotropic partner: its conjugate for a real solution)";
    add.Number(u + "_re", "1", "real part of " + u + ": " + what + kind + ", lengths divided by |AD|",
               [i, finite](const Row& r) { return finite(r.z(i).real()); });
    add.Number(u + "_im", "1", "imaginary part of " + u, [i, finite](const Row& r) { return finite(r.z(i).imag()); });
  }
  struct Named {
    const char* name;
    const char* unit;
    const char* what;
    double ExactFourBar::*member;
  };
  const Named bar_columns[] = {
      {"a", "model length", "crank AB", &ExactFourBar::a},
      {"b", "model length", "coupler BC", &ExactFourBar::b},
      {"c", "model length", "rocker DC", &ExactFourBar::c},
      {"d", "model length", "ground AD", &ExactFourBar::d},
      {"xi", "model length", "coupler point along BC from B", &ExactFourBar::xi},
      {"eta", "model length", "coupler point normal to BC (to the left of B -> C)", &ExactFourBar::eta},
      {"x0", "model length", "crank pivot A x", &ExactFourBar::x0},
      {"y0", "model length", "crank pivot A y", &ExactFourBar::y0},
      {"theta0", "rad", "angle of the ground line A -> D from +x, counter-clockwise", &ExactFourBar::theta0}};
  for (const Named& n : bar_columns) {
    const auto member = n.member;
    add.Number(n.name, n.unit, std::string(n.what) + " (real solutions)",
               [member, nan](const Row& r) { return r.has_bar ? r.bar.*member : nan; });
  }
  for (int j = 0; j < 5; ++j)
    add.Number("crank_" + std::to_string(j + 1), "rad",
               "the crank's angle AB from +x, counter-clockwise, in (-pi, pi], at point " + std::to_string(j + 1),
               [j, nan](const Row& r) { return r.has_bar ? r.bar.crank[static_cast<size_t>(j)] : nan; });
  for (int j = 0; j < 5; ++j)
    add.Text("branch_" + std::to_string(j + 1),
             "the side of the diagonal B -> D on which C lies at point " + std::to_string(j + 1) +
                 ": sign of (D - B) x (C - B), +1 left, -1 right, 0 on it",
             [j](const Row& r) { return r.has_bar ? std::to_string(r.bar.branch[static_cast<size_t>(j)]) : std::string(); });
  add.Text("one_branch", "yes: C on one side of BD at all five points (necessary to reach them in one motion)",
           [](const Row& r) { return r.has_bar ? std::string(r.bar.same_branch ? "yes" : "no") : std::string(); });
  add.Text("order",
           "+1: the crank turning counter-clockwise meets the points in the task's order within one turn, -1: clockwise, "
           "0: neither",
           [](const Row& r) { return r.has_bar ? std::to_string(r.bar.direction) : std::string(); });
  add.Text("grashof", "yes: s + l <= p + q", [](const Row& r) {
    return r.has_bar ? std::string(r.bar.grashof ? "yes" : "no") : std::string();
  });
  add.Text("crank_turns", "yes: Grashof with the crank or the ground the shortest link", [](const Row& r) {
    return r.has_bar ? std::string(r.bar.crank_turns ? "yes" : "no") : std::string();
  });
  add.Text("mode",
           "the model's assembly mode (block 0, +1 or -1) on which the generated kinematics reaches point 1: the written "
           "model's; 0 neither",
           [](const Row& r) { return r.has_bar ? std::to_string(r.mode) : std::string(); });
  for (int j = 0; j < 5; ++j)
    add.Text("mode_" + std::to_string(j + 1),
             "the mode on which the generated kinematics reaches point " + std::to_string(j + 1) + " (0: neither)",
             [j](const Row& r) { return r.has_bar ? std::to_string(r.point_mode[static_cast<size_t>(j)]) : std::string(); });
  add.Number("check", "model length",
             "the largest distance of the generated coupler point from a point at its crank angle, on the mode reaching it "
             "(the nearer mode where neither does)",
             [nan](const Row& r) { return r.has_bar && std::isfinite(r.check) ? r.check : nan; });
  add.Text("motion",
           "ok: from point to point (1 deg steps, the way the crank turns) the mechanism assembles regularly on its mode "
           "and the runtime's continuation reaches every point; not run: not on one branch in order; else why not",
           [cell](const Row& r) { return r.has_bar ? cell(r.motion) : std::string(); });
  add.Text("defect",
           "empty: defect-free; else the first failing check: degenerate link, branch, order, kinematics (a point not "
           "reached by the generated kinematics), dead point, continuation",
           [cell](const Row& r) { return cell(r.defect); });
  add.Text("model_file", "the model file written for this solution (empty: none, see the report)",
           [](const Row& r) { return r.file; });
  const auto& s = run.result.solutions;
  std::ostringstream out;
  out << "# mechgen synthesize, model " << model_name << ", task " << task_file
      << ": exact path synthesis (kind: exact), every isolated solution by homotopy continuation\n";
  out << "# status: " << (run.complete ? "complete" : "INCOMPLETE") << "; paths " << run.result.paths
      << ", nonsingular solutions " << run.result.num_solutions << " (real " << run.real << ", complex "
      << run.result.num_solutions - run.real << "), at infinity " << s.at_infinity << ", singular " << s.singular
      << ", failed " << s.failed << ", two paths at one solution " << s.duplicates << ", tracked again " << s.retracked
      << "; real and defect-free " << run.defect_free << "\n";
  out << "# lengths in the model's unit, angles in radians counter-clockwise from +x; the points are numbered 1 to 5 in "
         "the task's order\n";
  DescribeColumns(columns, out);
  WriteCsvHeader(columns, out);
  for (const Row& r : run.rows) WriteCsvRow(columns, r, out);
  return out.str();
}

/// report.txt: the counts, the time, and each real solution with its verdicts.
inline std::string ExactReport(const ExactRun& run, const ExactTask& task) {
  const auto& s = run.result.solutions;
  std::ostringstream o;
  o << "exact path synthesis (kind: exact): five points, pivots A (" << Num(task.five.crank_pivot[0]) << ", "
    << Num(task.five.crank_pivot[1]) << "), D (" << Num(task.five.rocker_pivot[0]) << ", " << Num(task.five.rocker_pivot[1])
    << ")\n";
  o << "status: " << (run.complete ? "complete (every path ended at a distinct nonsingular solution or at infinity)"
                                   : "INCOMPLETE: a path failed, ended singular or reached another path's solution; "
                                     "those are rows of solutions.csv with their figures")
    << "\n";
  o << "paths: " << run.result.paths << " (the 5-homogeneous Bezout count), at infinity " << s.at_infinity
    << ", singular " << s.singular << ", failed " << s.failed << ", two paths at one solution " << s.duplicates
    << ", tracked again with a finer step " << s.retracked << "\n";
  o << "isolated solutions: " << run.result.num_solutions << " (36 for generic data), real " << run.real
    << ", real and defect-free " << run.defect_free << "\n";
  o << "time: " << Short(run.seconds, 3) << " s (the continuation)\n\n";
  for (const ExactRow& r : run.rows) {
    if (r.status == "complex") continue;
    if (!r.has_bar) {
      o << "solution " << r.number << ": " << r.status << " (path " << r.path << ", t " << Short(r.t, 9) << ", residual "
        << Short(r.residual, 3) << ", rcond " << Short(r.rcond, 3) << ")\n";
      continue;
    }
    const ExactFourBar& b = r.bar;
    o << "solution " << r.number << ": a " << Short(b.a, 9) << ", b " << Short(b.b, 9) << ", c " << Short(b.c, 9) << ", d "
      << Short(b.d, 9) << ", xi " << Short(b.xi, 9) << ", eta " << Short(b.eta, 9) << "\n";
    o << "  crank angles (deg):";
    for (double q : b.crank) o << " " << Short(ToDegrees(q), 7);
    o << "\n  generated kinematics: every point within " << Short(r.check, 3) << " on mode";
    for (int m : r.point_mode) o << " " << m;
    o << (r.reached ? " (passes)" : " (FAILS)") << "\n";
    o << "  branch: " << (b.same_branch ? "one" : "changes") << ", order: "
      << (b.direction > 0 ? "counter-clockwise" : b.direction < 0 ? "clockwise" : "no") << ", Grashof: "
      << (b.grashof ? "yes" : "no") << ", crank turns: " << (b.crank_turns ? "yes" : "no") << ", motion: " << r.motion
      << "\n  verdict: " << (r.defect.empty() ? "defect-free" : "defect: " + r.defect) << "\n";
    if (!r.file.empty()) {
      o << "  model file: " << r.file << " (assembly on mode " << r.mode << ", branch " << r.written.branch << ", "
        << Short(r.written.q, 9) << " rad";
      if (r.written.range_written)
        o << "; range narrowed to [" << Short(r.written.range_lo, 9) << ", " << Short(r.written.range_hi, 9) << "]"
          << (r.defect.empty() ? ": the motion through the points" : ": the crank's reach on its mode about point 1");
      if (!r.written.continuation.empty()) o << "; " << r.written.continuation;
      o << ")\n";
    } else {
      o << "  model file: none (" << r.not_written << ")\n";
    }
  }
  return o.str();
}


/// A real four-bar of a nine-point task checked by the model's generated kinematics (the
/// five-point checks of RunExactTask on nine points) and its model file.
struct NineRow {
  int mode = 0;                     ///< the block-0 assembly mode reaching point 1 (the written model's), 0 none
  std::array<int, 9> point_mode{};  ///< the mode reaching each point (0: neither)
  double check = 0;                 ///< the generated coupler point's largest distance from a point (model length)
  bool reached = false;             ///< every point within kExactCheckTolerance (1 + |AD|) on its point_mode
  std::string motion = "not run";   ///< "ok", "not run" (not on one branch in order), or why the motion fails
  std::string defect;               ///< "" defect-free, else the first: degenerate link, branch, order, kinematics, dead point, continuation
  std::string file;                 ///< the written model's file name ("" none)
  std::string not_written;          ///< why no model file was written
  WrittenAssembly written;
};

/// What a nine-point `kind: exact` task gives (nine_point.h): the solve, each real four-bar's
/// largest distance from the points by the closed-form kinematics at its crank angles
/// (nine_point::Configuration on its branch), with a model: its checks by the model's generated
/// kinematics and its model file (`rows`), and the drawings of the defect-free ones.
struct NinePointRun {
  nine_point::NinePointResult result;
  std::vector<double> check;  ///< per real four-bar (result.real), in model length
  std::vector<NineRow> rows;  ///< per real four-bar, when checked against a model (else empty)
  std::vector<std::pair<std::string, std::string>> drawings;  ///< file name, SVG
  int defect_free = 0;    ///< real four-bars whose verdict is empty (rows' when checked against a model)
  bool complete = false;  ///< no path to the points lost, the monodromy stopped by its stall rule
  /// The verdict of real four-bar k: the model's checks when there are rows, else the closed form's.
  const std::string& Defect(size_t k) const { return rows.empty() ? result.real[k].bar.defect : rows[k].defect; }
};

namespace exact_internal {
/// The closed-form check of every real four-bar, completeness, the drawings of the defect-free.
inline void FinishNinePointRun(const nine_point::NinePoints& points, int max_loops, NinePointRun* run) {
  const auto& r = run->result;
  run->complete = r.lost == 0 && r.monodromy.loops < max_loops;
  run->check.clear();
  run->drawings.clear();
  run->defect_free = 0;
  for (size_t k = 0; k < r.real.size(); ++k) {
    const nine_point::NineSolution& s = r.real[k];
    double worst = 0;
    for (size_t j = 0; j < 9; ++j) {
      homotopy::Complex B, C, P;
      const bool ok = s.bar.branch[j] != 0 && nine_point::Configuration(s.bar, s.bar.crank[j], s.bar.branch[j], &B, &C, &P);
      const double d = ok ? std::abs(P - homotopy::Complex(points[j][0], points[j][1])) : kInf;
      worst = std::max(worst, std::isfinite(d) ? d : kInf);
    }
    run->check.push_back(worst);
    if (!run->Defect(k).empty()) continue;
    ++run->defect_free;
    char name[64];
    std::snprintf(name, sizeof name, "four_bar_%04d.svg", s.bar.solution + 1);
    run->drawings.emplace_back(name, nine_point::NineBarSvg(s.bar, points,
                                                            "solution " + std::to_string(s.bar.solution + 1) + ", class " +
                                                                std::to_string(s.klass + 1) +
                                                                (s.bar.crank_turns ? ", the crank turns" : "")));
  }
}
}  // namespace exact_internal

/**
 * \brief Checks each real four-bar of a solved nine-point task with the model's generated
 *        kinematics and the defect checks, as RunExactTask does for five points (the coupler
 *        point at each point's crank angle on either mode within kExactCheckTolerance (1 + |AD|),
 *        then the motion from point to point on the mode reaching point 1), and writes each one
 *        (no link of zero length) into the model's text (`models`: <stem>_nine_NNNN.yaml, NNNN
 *        its solution; nothing when model_text is empty).
 */
template <class M>
NinePointRun CheckNinePointRun(const BoundExact<M>& b, nine_point::NinePointResult result, int max_loops,
                               const std::string& model_text, const std::string& model_stem,
                               std::vector<std::pair<std::string, std::string>>* models) {
  using namespace exact_internal;
  NinePointRun run;
  run.result = std::move(result);
  const auto& points = b.task.nine_points;
  for (const nine_point::NineSolution& s : run.result.real) {
    NineRow row;
    const nine_point::NineBar& bar = s.bar;
    const double tol = kExactCheckTolerance * (1 + bar.d);
    const auto p = ExactParams(b, bar);
    row.reached = true;
    for (size_t j = 0; j < 9; ++j) {
      const double on_plus = CouplerDistance(b, p, bar.crank[j], 1, points[j]);
      const double on_minus = CouplerDistance(b, p, bar.crank[j], -1, points[j]);
      const double d = std::min(on_plus, on_minus);
      row.point_mode[j] = d <= tol ? (on_plus <= on_minus ? 1 : -1) : 0;
      row.check = std::max(row.check, d);
      row.reached = row.reached && d <= tol;
    }
    row.mode = row.point_mode[0];
    row.defect = bar.defect;
    if (row.defect.empty() && !row.reached) row.defect = "kinematics";
    typename ModelCalls<M>::Modes modes = ModelCalls<M>::DefaultModes(*b.model);
    modes[0] = row.mode;
    if (row.defect.empty()) {
      std::string defect;
      row.motion = MotionCheck(b, p, bar, points, modes, tol, &defect);
      row.defect = defect;
    }
    std::string text;
    if (!model_text.empty() && models != nullptr &&
        SolutionModel(b, p, bar, row.defect.empty(), modes, model_text, &text, &row.written, &row.not_written)) {
      char name[96];
      std::snprintf(name, sizeof name, "%s_nine_%04d.yaml", model_stem.c_str(), bar.solution + 1);
      row.file = name;
      models->emplace_back(row.file, text);
    }
    run.rows.push_back(row);
  }
  FinishNinePointRun(points, max_loops, &run);
  return run;
}

/// The nine-point task with its model: SolveNinePoints, then CheckNinePointRun.
template <class M>
NinePointRun RunNinePointTask(const BoundExact<M>& b, const std::string& model_text, const std::string& model_stem,
                              std::vector<std::pair<std::string, std::string>>* models, int threads) {
  nine_point::NinePointOptions o;
  o.monodromy.threads = std::max(1, threads);
  return CheckNinePointRun(b, nine_point::SolveNinePoints(b.task.nine_points, o), o.monodromy.max_loops, model_text,
                           model_stem, models);
}

/// solutions.csv of a nine-point task: one row per real four-bar.
inline std::string NinePointCsv(const NinePointRun& run, const std::string& model_name, const std::string& task_file) {
  struct Row {
    const nine_point::NineSolution* s;
    double check;
    std::string file;
    const NineRow* model;  ///< the generated kinematics' checks (null: no model)
    const std::string* defect;
  };
  std::vector<Row> rows;
  size_t drawn = 0;
  for (size_t k = 0; k < run.result.real.size(); ++k) {
    Row row{&run.result.real[k], run.check[k], "", run.rows.empty() ? nullptr : &run.rows[k], &run.Defect(k)};
    if (row.defect->empty() && drawn < run.drawings.size()) row.file = run.drawings[drawn++].first;
    rows.push_back(row);
  }
  table::Columns<Row> columns;
  table::Builder<Row> add(&columns, "");
  add.Text("solution", "the row's number", [](const Row& r) { return std::to_string(r.s->bar.solution + 1); });
  add.Text("class", "its class (the six four-bars of one class: two labellings of three Roberts cognates)",
           [](const Row& r) { return std::to_string(r.s->klass + 1); });
  add.Number("residual", "1", "|F(z)|_inf of the polynomial system on the scaled points",
             [](const Row& r) { return r.s->residual; });
  struct Named {
    const char* name;
    const char* unit;
    const char* what;
    double nine_point::NineBar::*member;
  };
  const Named bar_columns[] = {
      {"a", "model length", "crank AB", &nine_point::NineBar::a},
      {"b", "model length", "coupler BC", &nine_point::NineBar::b},
      {"c", "model length", "rocker DC", &nine_point::NineBar::c},
      {"d", "model length", "ground AD", &nine_point::NineBar::d},
      {"xi", "model length", "coupler point along BC from B", &nine_point::NineBar::xi},
      {"eta", "model length", "coupler point normal to BC (to the left of B -> C)", &nine_point::NineBar::eta},
      {"x0", "model length", "crank pivot A x", &nine_point::NineBar::x0},
      {"y0", "model length", "crank pivot A y", &nine_point::NineBar::y0},
      {"theta0", "rad", "angle of the ground line A -> D from +x, counter-clockwise", &nine_point::NineBar::theta0}};
  for (const Named& n : bar_columns) {
    const auto member = n.member;
    add.Number(n.name, n.unit, n.what, [member](const Row& r) { return r.s->bar.*member; });
  }
  for (int j = 0; j < 9; ++j)
    add.Number("crank_" + std::to_string(j + 1), "rad",
               "the crank's angle AB from +x, counter-clockwise, in (-pi, pi], at point " + std::to_string(j + 1),
               [j](const Row& r) { return r.s->bar.crank[static_cast<size_t>(j)]; });
  for (int j = 0; j < 9; ++j)
    add.Text("branch_" + std::to_string(j + 1),
             "the side of B -> D on which C lies at point " + std::to_string(j + 1) + ": +1 left, -1 right, 0 on it",
             [j](const Row& r) { return std::to_string(r.s->bar.branch[static_cast<size_t>(j)]); });
  add.Text("one_branch", "yes: C on one side of BD at all nine points",
           [](const Row& r) { return std::string(r.s->bar.same_branch ? "yes" : "no"); });
  add.Text("order", "+1: the crank turning counter-clockwise meets the points in the task's order within one turn, "
                    "-1: clockwise, 0: neither",
           [](const Row& r) { return std::to_string(r.s->bar.direction); });
  add.Text("grashof", "yes: s + l <= p + q", [](const Row& r) { return std::string(r.s->bar.grashof ? "yes" : "no"); });
  add.Text("crank_turns", "yes: Grashof with the crank or the ground the shortest link",
           [](const Row& r) { return std::string(r.s->bar.crank_turns ? "yes" : "no"); });
  add.Number("check", "model length",
             "the largest distance of the coupler point by the closed-form kinematics (circle intersection at the crank "
             "angle, on the point's branch) from a point",
             [](const Row& r) { return std::isfinite(r.check) ? r.check : std::nan(""); });
  const double nan = std::nan("");
  add.Text("mode",
           "the model's assembly mode (block 0, +1 or -1) on which the generated kinematics reaches point 1: the written "
           "model's; 0 neither; empty: not checked against a model",
           [](const Row& r) { return r.model ? std::to_string(r.model->mode) : std::string(); });
  add.Number("generated_check", "model length",
             "the largest distance of the model's generated coupler point from a point at its crank angle, on the mode "
             "reaching it (the nearer mode where neither does); empty: not checked against a model",
             [nan](const Row& r) { return r.model && std::isfinite(r.model->check) ? r.model->check : nan; });
  add.Text("motion",
           "ok: from point to point (1 deg steps, the way the crank turns) the mechanism assembles regularly on its mode "
           "and the runtime's continuation reaches every point; not run: not on one branch in order; else why not",
           [](const Row& r) {
             std::string m = r.model ? r.model->motion : std::string();
             std::replace(m.begin(), m.end(), ',', ';');
             return m;
           });
  add.Text("defect",
           "empty: defect-free; else the first failing check: degenerate link, branch, order, kinematics (a point not "
           "reached by the generated kinematics), dead point, continuation",
           [](const Row& r) { return *r.defect; });
  add.Text("model_file", "the model file written for this four-bar (empty: none)",
           [](const Row& r) { return r.model ? r.model->file : std::string(); });
  add.Text("drawing", "the SVG drawn for a defect-free four-bar", [](const Row& r) { return r.file; });
  const auto& n = run.result;
  std::ostringstream out;
  out << "# mechgen synthesize, model " << model_name << ", task " << task_file
      << ": exact path synthesis (kind: exact), nine points, pivots free, by monodromy\n";
  out << "# status: " << (run.complete ? "complete" : "INCOMPLETE") << "; classes " << n.at_target.size()
      << " (1442 for generic points), solutions " << n.solutions << ", real classes " << n.real_classes
      << ", real four-bars " << n.real.size() << ", defect-free " << run.defect_free
      << (run.rows.empty() ? " (closed form)" : " (the model's generated kinematics and motion)") << "\n";
  out << "# lengths in the model's unit, angles in radians counter-clockwise from +x; the points are numbered 1 to 9 in "
         "the task's order\n";
  DescribeColumns(columns, out);
  WriteCsvHeader(columns, out);
  for (const Row& r : rows) WriteCsvRow(columns, r, out);
  return out.str();
}

/// report.txt of a nine-point task.
inline std::string NinePointReport(const NinePointRun& run) {
  const auto& r = run.result;
  const auto& m = r.monodromy;
  std::ostringstream o;
  o << "exact path synthesis (kind: exact): nine points, pivots free (Wampler, Morgan and Sommese 1992: 8652 "
       "four-bars, 1442 classes of six, for generic points)\n";
  o << "status: " << (run.complete ? "complete (every class reached the points; the monodromy stopped when three new "
                                     "loops found no new class)"
                                   : "INCOMPLETE: a class's path to the points failed or met another's, or the "
                                     "monodromy stopped at its loop limit")
    << "\n";
  o << "monodromy: " << m.classes.size() << " classes in " << m.loops << " loops, " << m.paths << " edges tracked, "
    << m.failed << " trips failed, " << Short(m.seconds, 4) << " s\n";
  o << "at the points: " << r.at_target.size() << " classes, " << r.solutions << " solutions, " << r.lost
    << " classes lost, " << r.retracked << " paths tracked again (a finer step, or a cognate's), " << r.detours
    << " detours for a lost class; " << r.paths << " paths in all\n";
  o << "real: " << r.real_classes << " classes, " << r.real.size() << " four-bars, defect-free " << run.defect_free
    << (run.rows.empty() ? " (closed form: branch, order, no degenerate link)"
                         : " (and the model's generated kinematics within 1e-8 (1 + |AD|), the motion from point to point)")
    << "\n";
  o << "time: " << Short(r.seconds, 4) << " s\n\n";
  for (size_t k = 0; k < r.real.size(); ++k) {
    const nine_point::NineSolution& s = r.real[k];
    const double check = run.check[k];
    if (!run.Defect(k).empty()) continue;
    const auto& b = s.bar;
    o << "solution " << b.solution + 1 << " (class " << s.klass + 1 << "): a " << Short(b.a, 9) << ", b " << Short(b.b, 9)
      << ", c " << Short(b.c, 9) << ", d " << Short(b.d, 9) << ", xi " << Short(b.xi, 9) << ", eta " << Short(b.eta, 9)
      << ", A (" << Short(b.x0, 9) << ", " << Short(b.y0, 9) << "), theta0 " << Short(b.theta0, 9) << "; "
      << (b.direction > 0 ? "counter-clockwise" : "clockwise") << ", Grashof " << (b.grashof ? "yes" : "no")
      << ", crank turns " << (b.crank_turns ? "yes" : "no") << ", closed form within " << Short(check, 3);
    if (!run.rows.empty())
      o << ", generated kinematics within " << Short(run.rows[k].check, 3) << " on mode " << run.rows[k].mode
        << (run.rows[k].file.empty() ? "" : ", model file " + run.rows[k].file);
    o << "\n";
  }
  return o.str();
}

}  // namespace mechgen::synthesis
