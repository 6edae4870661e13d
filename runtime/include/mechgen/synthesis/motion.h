/**
 * \file synthesis/motion.h
 * Motion generation as a task (issue 28): the body (the model's coupler) through poses (its
 * point and its angle). Five poses: the Burmester points (synthesis/burmester.h), every pair
 * of them a four-bar, each written into the model's parameters (a four-bar with its frame
 * placed: crank pivot (x0, y0), ground at theta0, as tests/synthesis/models/synth_fourbar.yaml;
 * the task names them) and run by the generated model: at each pose's crank angle, on the
 * model's assembly mode or its mirror (the other root of the four-bar's block, C on the other
 * side of BD: the one on which the model's coupler point is nearer pose 1; the model file is
 * then written on that mode), the coupler point must be the pose's point and the coupler's angle
 * the pose's angle (up to the constant between the body's x axis and BC) to 1e-9 of the
 * poses' size, and from pose to pose (the crank turning the way the poses go) the model must
 * stay on its mode. Of the pairs that pass, the one with the smallest ratio of its longest to
 * its shortest link is the answer (the first of equals). Four poses: the circle- and centre-point curves
 * (written as a CSV and an SVG by the command). More than five poses: the Burmester points of
 * five chosen poses (`seed_poses`), every pair's four-bar refined by Levenberg–Marquardt on the
 * pose errors of all poses (the nine parameters, the body's angle on the coupler and every
 * pose's crank angle; the generated Jacobian), checked on the model's mode as above but without
 * the 1e-9 requirement; the passing pair with the smallest error is the answer.
 * Needs yaml-cpp.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "mechgen/position/design.h"
#include "mechgen/synthesis/burmester.h"
#include "mechgen/synthesis/function.h"
#include "mechgen/synthesis/output.h"

namespace mechgen::synthesis {

struct MotionTask {
  std::string file, model;
  std::vector<Pose> poses;
  std::string point;           ///< the model's coupler point (the pose's point), e.g. coupler.P
  std::string coupler_angle;   ///< the coupler's angle among the model's phi, e.g. theta_coupler
  /// The model's parameters for a, b, c, d, xi, eta, x0, y0, theta0 (in this order).
  std::vector<std::string> parameters;
  int curve_rays = 3600;
  int line = 1, column = 1;  ///< where `parameters:` is
  int point_line = 1, point_column = 1, angle_line = 1, angle_column = 1;
  /// More than five poses: the five (0-based) whose Burmester points seed the least squares.
  std::vector<int> seed_poses;
  /// More than five poses, the global stage (`search: {subsets: N}`): besides seed_poses, N
  /// more five-pose subsets (every subset when N is at least their number) whose Burmester
  /// points seed the least squares too; 0: seed_poses only. The default, 21, takes every subset
  /// up to seven poses (C(7, 5) = 21, the seed poses among them: FivePoseSubsets) at the cost of
  /// 20 more Burmester curves: the seed poses alone missed the better optimum in 12 of 42
  /// perturbed tasks.
  int subsets = 21;
};

inline const std::vector<std::string>& MotionParameterKeys() {
  static const std::vector<std::string> keys = {"crank", "coupler", "rocker", "ground", "xi", "eta", "x0", "y0", "theta0"};
  return keys;
}

inline bool ParseMotionTask(const std::string& path, MotionTask* task, std::string* error) {
  using namespace task_internal;
  *task = MotionTask();
  task->file = path;
  YAML::Node root;
  if (!LoadTaskRoot(path, "`synthesis: motion`, `poses`, `point`, `parameters`", &root, error)) return false;
  try {
    Known(path, root, {"synthesis", "model", "poses", "point", "coupler_angle", "parameters", "seed_poses", "search"},
          "a motion task");
    if (const YAML::Node m = root["model"]) {
      if (!m.IsScalar()) throw Error{Where(path, m.Mark()) + "model: expected a file name"};
      task->model = m.Scalar();
    }
    const YAML::Node poses = Required(path, root, "poses", "the body's poses, [[x, y, angle], ...]");
    if (!poses.IsSequence() || poses.size() < 4)
      throw Error{Where(path, poses.Mark()) + "poses: expected four (the Burmester curves), five (the Burmester points) or "
                                               "more (least squares) [x, y, angle]"};
    for (const YAML::Node& p : poses) {
      if (!p.IsSequence() || p.size() != 3) throw Error{Where(path, p.Mark()) + "a pose: expected [x, y, angle]"};
      task->poses.push_back({Number(path, p[0], "pose x"), Number(path, p[1], "pose y"), Number(path, p[2], "pose angle", true)});
    }
    const YAML::Node point = Required(path, root, "point", "the model's coupler point that is the pose's point, e.g. coupler.P");
    if (!point.IsScalar()) throw Error{Where(path, point.Mark()) + "point: expected a point name"};
    task->point = point.Scalar();
    task->point_line = point.Mark().line + 1, task->point_column = point.Mark().column + 1;
    const YAML::Node angle = Required(path, root, "coupler_angle", "the coupler's angle among the model's dependent variables, e.g. theta_coupler");
    if (!angle.IsScalar()) throw Error{Where(path, angle.Mark()) + "coupler_angle: expected a dependent variable's name"};
    task->coupler_angle = angle.Scalar();
    task->angle_line = angle.Mark().line + 1, task->angle_column = angle.Mark().column + 1;
    // The four-bar's parameters: needed to write one (five poses or more), not for the curves.
    if (task->poses.size() >= 5)
      Required(path, root, "parameters",
               "the model's parameters {crank: a, coupler: b, rocker: c, ground: d, xi: xi, eta: eta, x0: x0, y0: y0, "
               "theta0: theta0}");
    if (const YAML::Node params = root["parameters"]) {
      if (!params.IsMap()) throw Error{Where(path, params.Mark()) + "parameters: expected a mapping"};
      Known(path, params, MotionParameterKeys(), "parameters");
      for (const std::string& key : MotionParameterKeys()) {
        const YAML::Node v = Required(path, params, key, "the model's parameter for it");
        if (!v.IsScalar()) throw Error{Where(path, v.Mark()) + "parameters." + key + ": expected a parameter name"};
        task->parameters.push_back(v.Scalar());
      }
      task->line = params.Mark().line + 1;
      task->column = params.Mark().column + 1;
    }
    const int n = static_cast<int>(task->poses.size());
    if (const YAML::Node sp = root["seed_poses"]) {
      if (n <= 5) throw Error{Where(path, sp.Mark()) + "seed_poses: only for more than five poses"};
      if (!sp.IsSequence() || sp.size() != 5)
        throw Error{Where(path, sp.Mark()) + "seed_poses: expected five pose numbers (1-based), e.g. [1, 2, 4, 5, 7]"};
      for (const YAML::Node& k : sp) {
        const int j = static_cast<int>(Count(path, k, "seed pose", 1, n)) - 1;
        for (int seen : task->seed_poses)
          if (seen == j) throw Error{Where(path, k.Mark()) + "seed_poses: pose " + std::to_string(j + 1) + " given twice"};
        task->seed_poses.push_back(j);
      }
      std::sort(task->seed_poses.begin(), task->seed_poses.end());
    } else if (n > 5) {
      // The first, the last and three evenly between.
      for (int k = 0; k < 5; ++k) task->seed_poses.push_back(static_cast<int>(std::lround(k * (n - 1) / 4.0)));
    }
    if (const YAML::Node s = root["search"]) {
      if (!s.IsMap()) throw Error{Where(path, s.Mark()) + "search: expected a mapping"};
      Known(path, s, {"curve_rays", "subsets"}, "search (motion task)");
      if (s["curve_rays"]) task->curve_rays = static_cast<int>(Count(path, s["curve_rays"], "curve_rays", 90, 1000000));
      if (const YAML::Node k = s["subsets"]) {
        if (n <= 5) throw Error{Where(path, k.Mark()) + "search.subsets: only for more than five poses (the least squares)"};
        task->subsets = static_cast<int>(Count(path, k, "subsets", 0, 100000));
      }
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

/// One pair of Burmester points as a four-bar, and what the generated model made of it.
struct MotionCandidate {
  int crank = 0, rocker = 0;       ///< indices into the Burmester points
  /// The assembly mode of the four-bar's block (block 0) through the poses: the model's
  /// (M::kDefaultModes[0]) or its mirror (the other root: C on the other side of BD); the
  /// model file is written on it (WriteSynthesizedModel's modes).
  int mode = 0;
  FourBarFromDyads fourbar;
  double worst_point = kInf, worst_angle = kInf;  ///< over the poses
  bool ok = false;
  std::string why;                 ///< when not ok
  double ratio = kInf;             ///< longest link / shortest link
  /// More than five poses: the least squares' error (sum over the poses of the squared point
  /// distance and (L x the angle error)^2, L the poses' size) and LM's iterations.
  double error = kInf;
  int iterations = 0;
};

struct MotionResult {
  std::vector<Dyad> points;
  /// The five poses (0-based) whose Burmester points each of `points` is, by index into
  /// `subsets`: 0 the seed poses (or the five poses), then the global stage's subsets.
  std::vector<int> point_subset;
  std::vector<std::vector<int>> subsets;
  std::vector<MotionCandidate> candidates;
  int chosen = -1;                 ///< index into candidates, -1 none
  std::vector<CurvePoint> curve;   ///< four poses
  long long evaluations = 0;       ///< more than five poses: the least squares' residual evaluations
  int model_mode = 0;              ///< the model's own mode of the four-bar's block (M::kDefaultModes[0])
};

namespace motion_internal {

/// The global stage's five-pose subsets of n poses: `count` of the C(n, 5) in lexicographic
/// order, evenly spread over it (ranks floor(i C / count), i = 0 .. count - 1; every one when
/// count >= C), less `seed` (the seed poses, already used). Unranked by the combinatorial
/// number system (exact in long double below 2^64: n up to about 10^4).
inline std::vector<std::vector<int>> FivePoseSubsets(int n, int count, const std::vector<int>& seed) {
  std::vector<std::vector<int>> out;
  if (count <= 0 || n < 5) return out;
  auto choose = [](long double m, int k) {
    if (m < k) return 0.0L;
    long double c = 1;
    for (int i = 0; i < k; ++i) c = c * (m - i) / (i + 1);
    return c;
  };
  const long double total = choose(n, 5);
  const long double want = std::min(static_cast<long double>(count), total);
  for (long double i = 0; i < want; ++i) {
    long double rank = std::floor(i * total / want);
    std::vector<int> sub;
    int v = 0;
    for (int pos = 0; pos < 5; ++pos) {
      for (;; ++v) {
        const long double below = choose(n - 1 - v, 4 - pos);  // subsets with v at this position
        if (rank < below) break;
        rank -= below;
      }
      sub.push_back(v++);
    }
    if (sub != seed) out.push_back(sub);
  }
  return out;
}
/// The pose errors of a placed four-bar (the task's nine parameters, then gamma: the body's
/// angle minus the coupler's) over the crank angles q_j, with the generated Jacobian:
/// dr_P/dp and dphi/dp (EvalDesignDerivatives), K_P and K (EvalCoefficients).
/// Residuals per pose: r_P - P_j (two) and L * wrap(phi_coupler + gamma - alpha_j).
template <class M>
class PoseResiduals : public ceres::CostFunction {
 public:
  using C = ModelCalls<M>;
  PoseResiduals(const M& model, const std::vector<Pose>& poses, const typename ModelTypes<M>::Params& base,
                const std::vector<std::string>& names, const std::vector<int>& column, int point, int angle, double L,
                long long* evaluations, const typename C::Modes& modes)
      : model_(model), poses_(poses), base_(base), names_(names), column_(column), point_(point), angle_(angle), L_(L),
        evaluations_(evaluations), modes_(modes) {
    set_num_residuals(3 * static_cast<int>(poses.size()));
    mutable_parameter_block_sizes()->push_back(10);
    mutable_parameter_block_sizes()->push_back(static_cast<int32_t>(poses.size()));
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const int n = static_cast<int>(poses_.size());
    *evaluations_ += (jacobians != nullptr) ? 1 + 10 + n : 1;
    typename ModelTypes<M>::Params p = base_;
    for (size_t k = 0; k < 9; ++k) *C::FindParameter(model_, &p, names_[k].c_str()) = parameters[0][k];
    C::ParametersSet(model_, &p);
    const double gamma = parameters[0][9];
    typename ModelTypes<M>::VecPhi phi;
    typename ModelTypes<M>::Coefficients co;
    position::DesignOf<M> design;
    for (int j = 0; j < n; ++j) {
      typename ModelTypes<M>::VecQ qv;
      qv.resize(1);
      qv(0) = parameters[1][j];
      if (!SolveOnMode(model_, p, qv(0), &phi, /*judge=*/true, &modes_)) return false;
      C::Coeffs(model_, p, qv, phi, &co);
      const Pose& pose = poses_[static_cast<size_t>(j)];
      residuals[3 * j] = co.r_P(0, point_) - pose.x;
      residuals[3 * j + 1] = co.r_P(1, point_) - pose.y;
      residuals[3 * j + 2] = L_ * WrapPi(phi(angle_) + gamma - pose.angle);
      if (jacobians == nullptr) continue;
      C::Design(model_, p, qv, phi, &design);
      for (int a = 0; a < 3; ++a) {
        const int row = 3 * j + a;
        if (jacobians[0] != nullptr) {
          for (int k = 0; k < 9; ++k) {
            const int col = column_[static_cast<size_t>(k)];
            jacobians[0][row * 10 + k] = a < 2 ? design.dr_P_dp(2 * point_ + a, col) : L_ * design.dphi_dp(angle_, col);
          }
          jacobians[0][row * 10 + 9] = a < 2 ? 0.0 : L_;
        }
        if (jacobians[1] != nullptr) {
          for (int k = 0; k < n; ++k)
            jacobians[1][row * n + k] = k != j ? 0.0 : (a < 2 ? co.K_P(2 * point_ + a, 0) : L_ * co.K(angle_, 0));
        }
      }
    }
    return true;
  }

 private:
  const M& model_;
  const std::vector<Pose>& poses_;
  typename ModelTypes<M>::Params base_;
  const std::vector<std::string>& names_;
  const std::vector<int>& column_;
  int point_, angle_;
  double L_;
  long long* evaluations_;
  typename C::Modes modes_;  ///< the assembly mode of the poses (the model's or its mirror)
};
}  // namespace motion_internal

/// "assembly mode" or "mirror assembly mode" (block 0's mode against the model's).
template <class M>
std::string ModeName(const M& model, int mode) {
  return mode == ModelCalls<M>::DefaultModes(model)[0] ? "assembly mode" : "mirror assembly mode";
}
template <class M>
std::string ModeName(int mode) {
  return ModeName(M(), mode);
}

/// Five poses: the Burmester points and their four-bars on the model (reached through
/// ModelCalls<M>: a generated model, or the model view); four poses: the curves. More than
/// five poses: the least squares on the generated design derivatives (ModelCalls<M>::Design).
template <class M>
bool SynthesizeMotion(const M& model, const MotionTask& task, const typename ModelTypes<M>::Params& base,
                      MotionResult* out, std::string* error) {
  using C = ModelCalls<M>;
  using Params = typename ModelTypes<M>::Params;
  using VecQ = typename ModelTypes<M>::VecQ;
  using VecPhi = typename ModelTypes<M>::VecPhi;
  using Modes = typename C::Modes;
  int point = -1, angle = -1;
  for (int m = 0; m < C::NumPoints(model); ++m)
    if (task.point == C::PointName(model, m)) point = m;
  for (int i = 0; i < C::Nphi(model); ++i)
    if (task.coupler_angle == C::PhiName(model, i)) angle = i;
  if (point < 0)
    return *error = bind_internal::Where(task.file, task.point_line, task.point_column) + "point '" + task.point +
                    "' is not among the model's output points (" +
                    bind_internal::List(C::NumPoints(model), [&](int m) { return C::PointName(model, m); }) + ")",
           false;
  if (angle < 0)
    return *error = bind_internal::Where(task.file, task.angle_line, task.angle_column) + "coupler_angle '" +
                    task.coupler_angle + "' is not one of the model's dependent variables (" +
                    bind_internal::List(C::Nphi(model), [&](int i) { return C::PhiName(model, i); }) + ")",
           false;
  if (C::Nq(model) != 1) {
    return *error = task.file + ": error: motion generation needs a one-input four-bar model", false;
  } else {
    // The task's nine parameters set in p (the derived ones brought up to date).
    auto set_parameters = [&](Params* p, const double* values) {
      for (size_t k = 0; k < 9; ++k) *C::FindParameter(model, p, task.parameters[k].c_str()) = values[k];
      C::ParametersSet(model, p);
    };
    {
      Params p = base;
      for (const std::string& name : task.parameters)
        if (C::FindParameter(model, &p, name.c_str()) == nullptr)
          return *error = task.file + ":" + std::to_string(task.line) + ":" + std::to_string(task.column) +
                          ": error: parameters: no parameter '" + name + "' in the model",
                 false;
    }
    MotionResult r;
    r.model_mode = C::DefaultModes(model)[0];
    const std::vector<Pose>& poses = task.poses;
    const double L = burmester_internal::Scale(poses);
    if (poses.size() == 4) {
      Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
      for (const Pose& p : poses) centroid += Eigen::Vector2d(p.x, p.y);
      r.curve = FourPoseCurve(poses, centroid / 4.0 + Eigen::Vector2d(0.1234567 * L, 0.0765432 * L), task.curve_rays);
      *out = r;
      return true;
    }
    const bool lsq = poses.size() > 5;
    std::vector<int> column(9, -1);
    if (lsq) {
      if (!C::HasDesign(model)) {
        return *error = task.file + ": error: more than five poses need the model's `design:` section (the least squares' "
                                    "Jacobian)",
               false;
      } else {
        for (size_t k = 0; k < 9; ++k) {
          for (int d = 0; d < C::NumDesign(model); ++d)
            if (task.parameters[k] == C::DesignName(model, d)) column[k] = d;
          if (column[k] < 0)
            return *error = task.file + ":" + std::to_string(task.line) + ":" + std::to_string(task.column) +
                            ": error: parameters: '" + task.parameters[k] +
                            "' is not in the model's design: list (more than five poses: all nine must be)",
                   false;
        }
      }
    }
    const int n = static_cast<int>(poses.size());
    // The five poses whose Burmester points seed: the five, or the seed poses and then the
    // global stage's subsets (each pair of a subset's points a start of the least squares).
    r.subsets.push_back(lsq ? task.seed_poses : std::vector<int>{0, 1, 2, 3, 4});
    if (lsq)
      for (std::vector<int>& sub : motion_internal::FivePoseSubsets(n, task.subsets, task.seed_poses))
        r.subsets.push_back(std::move(sub));
    for (size_t set = 0; set < r.subsets.size(); ++set) {
      std::vector<Pose> five;
      for (int k : r.subsets[set]) five.push_back(poses[static_cast<size_t>(k)]);
      const int first = static_cast<int>(r.points.size());
      for (const Dyad& d : BurmesterPoints(five, task.curve_rays))
        r.points.push_back(d), r.point_subset.push_back(static_cast<int>(set));
      const int last = static_cast<int>(r.points.size());
      for (int i = first; i < last; ++i) {
        for (int j = first; j < last; ++j) {
          if (i == j) continue;
          MotionCandidate c;
          c.crank = i, c.rocker = j;
          c.fourbar = FourBarOfDyads(poses, r.points[static_cast<size_t>(i)], r.points[static_cast<size_t>(j)]);
          FourBarFromDyads& f = c.fourbar;
          double gamma_fit = 0;
          // The mode: the model's, or its mirror when the model's coupler is not at pose 1 on
          // it (the other root of the four-bar's block: C on the other side of BD).
          Modes modes = C::DefaultModes(model);
          {
            Params p = base;
            const double values[9] = {f.a, f.b, f.c, f.d, f.xi, f.eta, f.x0, f.y0, f.theta0};
            set_parameters(&p, values);
            auto distance = [&](const Modes& m) {
              VecPhi phi;
              if (!SolveOnMode(model, p, f.crank_angle[0], &phi, /*judge=*/false, &m)) return kInf;
              VecQ qv;
              qv.resize(1);
              qv(0) = f.crank_angle[0];
              typename ModelTypes<M>::Coefficients co;
              C::Coeffs(model, p, qv, phi, &co);
              const double d = std::hypot(co.r_P(0, point) - poses[0].x, co.r_P(1, point) - poses[0].y);
              return std::isfinite(d) ? d : kInf;
            };
            Modes mirror = modes;
            mirror[0] = -mirror[0];
            if (distance(mirror) < distance(modes)) modes = mirror;
          }
          c.mode = modes[0];
          if constexpr (C::kView || HasDesignDerivatives<M>::value) {
            if (lsq) {
              // Least squares of the pose errors over all poses from this pair's four-bar.
              std::vector<double> x = {f.a, f.b, f.c, f.d, f.xi, f.eta, f.x0, f.y0, f.theta0, 0.0};
              std::vector<double> q = f.crank_angle;
              {
                // gamma: the body's angle minus the coupler's at the first pose (the coupler along BC).
                const Eigen::Vector2d B = CirclePointAt(poses[0], r.points[static_cast<size_t>(i)].k);
                const Eigen::Vector2d C = CirclePointAt(poses[0], r.points[static_cast<size_t>(j)].k);
                x[9] = WrapPi(poses[0].angle - std::atan2(C.y() - B.y(), C.x() - B.x()));
              }
              auto* cost = new motion_internal::PoseResiduals<M>(model, poses, base, task.parameters, column, point,
                                                                 angle, L, &r.evaluations, modes);
              ceres::Problem problem;
              problem.AddResidualBlock(cost, nullptr, x.data(), q.data());
              // The start must assemble at every pose (else Ceres refuses it, and says so on stderr).
              std::vector<double> start_residuals(static_cast<size_t>(3 * n));
              const double* start_blocks[2] = {x.data(), q.data()};
              const bool starts = cost->Evaluate(start_blocks, start_residuals.data(), nullptr);
              for (int k = 0; k < 4; ++k) problem.SetParameterLowerBound(x.data(), k, 1e-9 * L);
              const ceres::Solver::Options options = LocalSolverOptions();
              ceres::Solver::Summary summary;
              if (starts) ceres::Solve(options, &problem, &summary);
              c.iterations = static_cast<int>(summary.iterations.size());
              if (starts && summary.IsSolutionUsable()) {
                f.a = x[0], f.b = x[1], f.c = x[2], f.d = x[3], f.xi = x[4], f.eta = x[5], f.x0 = x[6], f.y0 = x[7];
                f.theta0 = x[8];
                f.crank_angle = q;
                gamma_fit = x[9];
                c.error = 2 * summary.final_cost;
              } else {
                c.why = "the least squares could not start from this pair (the model does not assemble at every pose)";
              }
            }
          }
          Params p = base;
          const double values[9] = {f.a, f.b, f.c, f.d, f.xi, f.eta, f.x0, f.y0, f.theta0};
          set_parameters(&p, values);
          auto solve = [&](double q, VecPhi* phi) { return SolveOnMode(model, p, q, phi, /*judge=*/true, &modes); };
          VecPhi phi;
          typename ModelTypes<M>::Coefficients co;
          c.worst_point = c.worst_angle = 0;
          double offset = -gamma_fit;
          for (int k = 0; k < n && c.why.empty(); ++k) {
            const double q = f.crank_angle[static_cast<size_t>(k)];
            if (!solve(q, &phi)) {
              c.why =
                  "pose " + std::to_string(k + 1) + ": the model does not assemble on its " + ModeName(model, c.mode);
              break;
            }
            VecQ qv;
            qv.resize(1);
            qv(0) = q;
            C::Coeffs(model, p, qv, phi, &co);
            const double dp = std::hypot(co.r_P(0, point) - poses[static_cast<size_t>(k)].x,
                                         co.r_P(1, point) - poses[static_cast<size_t>(k)].y);
            if (k == 0 && !lsq) offset = phi(angle) - poses[0].angle;
            const double da = std::abs(WrapPi(phi(angle) - poses[static_cast<size_t>(k)].angle - offset));
            c.worst_point = std::max(c.worst_point, dp);
            c.worst_angle = std::max(c.worst_angle, da);
            if (!lsq && (!(dp <= 1e-9 * std::max(1.0, L)) || !(da <= 1e-9)))
              c.why = "pose " + std::to_string(k + 1) + ": the model's coupler is not there on its " +
                      ModeName(model, c.mode) + " (pose 1 on it, this pose on the other: the poses on two branches)";
          }
          // From pose to pose, the crank turning the way the poses go.
          double sum = 0;
          for (int k = 0; k + 1 < n; ++k)
            sum += WrapPi(f.crank_angle[static_cast<size_t>(k + 1)] - f.crank_angle[static_cast<size_t>(k)]);
          const double dir = sum >= 0 ? 1.0 : -1.0;
          for (int k = 0; k + 1 < n && c.why.empty(); ++k) {
            const double q0 = f.crank_angle[static_cast<size_t>(k)];
            const double span = Wrap(dir * (f.crank_angle[static_cast<size_t>(k + 1)] - q0));
            const int steps = std::max(1, static_cast<int>(std::ceil(span / (kTwoPi / 720))));
            for (int s = 1; s < steps && c.why.empty(); ++s)
              if (!solve(q0 + dir * span * s / steps, &phi))
                c.why = "between poses " + std::to_string(k + 1) + " and " + std::to_string(k + 2) +
                        ": the model leaves its " + ModeName(model, c.mode) + " (a dead point or no closure)";
          }
          c.ok = c.why.empty();
          c.ratio = std::max({f.a, f.b, f.c, f.d}) / std::min({f.a, f.b, f.c, f.d});
          // Five poses: the smallest link ratio; more: the smallest error (ties within 1e-12 L^2
          // of it: the smaller link ratio).
          if (c.ok) {
            const MotionCandidate* best = r.chosen < 0 ? nullptr : &r.candidates[static_cast<size_t>(r.chosen)];
            const bool better =
                best == nullptr || (lsq ? (c.error < best->error - 1e-12 * L * L ||
                                           (std::abs(c.error - best->error) <= 1e-12 * L * L && c.ratio < best->ratio))
                                        : c.ratio < best->ratio);
            if (better) r.chosen = static_cast<int>(r.candidates.size());
          }
          r.candidates.push_back(c);
        }
      }
    }
    *out = r;
    return true;
  }
}

/// The same on a generated model's type (default-constructed: its functions are static).
template <class M>
bool SynthesizeMotion(const MotionTask& task, const typename M::template ParamsT<double>& base, MotionResult* out,
                      std::string* error) {
  return SynthesizeMotion(M(), task, base, out, error);
}

/// The crank's angle at each pose of a four-bar from dyads, unwrapped the way the crank turns
/// through them (the direction of the summed steps, each step within one turn), as
/// SynthesizeMotion checks the motion: the written model's assembly and range are made of it
/// (WriteSynthesizedModel).
inline std::vector<double> MotionInputs(const FourBarFromDyads& f) {
  const std::vector<double>& angle = f.crank_angle;
  double sum = 0;
  for (size_t k = 0; k + 1 < angle.size(); ++k) sum += WrapPi(angle[k + 1] - angle[k]);
  const double dir = sum >= 0 ? 1.0 : -1.0;
  std::vector<double> motion;
  if (angle.empty()) return motion;
  motion.push_back(angle[0]);
  for (size_t k = 0; k + 1 < angle.size(); ++k) motion.push_back(motion.back() + dir * Wrap(dir * (angle[k + 1] - angle[k])));
  return motion;
}

/// Four poses: the circle-point curve (blue; in the fixed frame at pose 1: K_1 = P_1 + R(alpha_1) k)
/// and the centre-point curve (red) as dots, the poses (black: the point and a tick along the
/// body's x axis), in an SVG of width 640; the view is the poses' neighbourhood (four times
/// their size about their centroid: far branches of the curves are cut at its edge).
inline std::string CurvesSvg(const MotionTask& task, const MotionResult& r) {
  const std::vector<Pose>& poses = task.poses;
  const double L = burmester_internal::Scale(poses);
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Pose& p : poses) centroid += Eigen::Vector2d(p.x, p.y);
  centroid /= static_cast<double>(poses.size());
  const double half = 4 * L, size = 600, margin = 20, scale = size / (2 * half);
  const double xmin = centroid.x() - half, ymax = centroid.y() + half;
  auto inside = [&](const Eigen::Vector2d& v) { return std::abs(v.x() - centroid.x()) <= half && std::abs(v.y() - centroid.y()) <= half; };
  auto X = [&](double x) { return Short(margin + (x - xmin) * scale, 7); };
  auto Y = [&](double y) { return Short(margin + (ymax - y) * scale, 7); };
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Short(size + 2 * margin) + "\" height=\"" +
                    Short(size + 2 * margin) +
                    "\">\n<title>Burmester curves of four poses: circle points (blue, at pose 1), centre points (red), "
                    "the poses (black)</title>\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (const CurvePoint& cp : r.curve) {
    const Eigen::Vector2d K = CirclePointAt(poses[0], cp.dyad.k);
    if (inside(K)) svg += "<circle cx=\"" + X(K.x()) + "\" cy=\"" + Y(K.y()) + "\" r=\"1\" fill=\"#1f5fa8\"/>\n";
    if (inside(cp.dyad.M))
      svg += "<circle cx=\"" + X(cp.dyad.M.x()) + "\" cy=\"" + Y(cp.dyad.M.y()) + "\" r=\"1\" fill=\"#c0392b\"/>\n";
  }
  for (size_t j = 0; j < poses.size(); ++j) {
    const Pose& p = poses[j];
    const double tx = p.x + 0.3 * L * std::cos(p.angle), ty = p.y + 0.3 * L * std::sin(p.angle);
    svg += "<circle cx=\"" + X(p.x) + "\" cy=\"" + Y(p.y) + "\" r=\"4\" fill=\"none\" stroke=\"black\"/>\n";
    svg += "<line x1=\"" + X(p.x) + "\" y1=\"" + Y(p.y) + "\" x2=\"" + X(tx) + "\" y2=\"" + Y(ty) + "\" stroke=\"black\"/>\n";
    svg += "<text x=\"" + X(p.x) + "\" y=\"" + Y(p.y) + "\" dx=\"6\" dy=\"-6\" font-size=\"12\" font-family=\"sans-serif\">" +
           std::to_string(j + 1) + "</text>\n";
  }
  svg += "</svg>\n";
  return svg;
}

inline std::string MotionReport(const MotionTask& task, const MotionResult& r) {
  std::string s = "# motion generation: " + std::to_string(task.poses.size()) + " poses (task " + task.file + ")\n";
  if (task.poses.size() == 4) {
    s += "the circle- and centre-point curves: " + std::to_string(r.curve.size()) + " points (curves.csv, curves.svg)\n";
    return s;
  }
  if (task.poses.size() > 5) {
    s += "least squares of the pose errors over all " + std::to_string(task.poses.size()) +
         " poses, seeded from the Burmester points of poses";
    for (int j : task.seed_poses) s += " " + std::to_string(j + 1);
    s += " (" + std::to_string(r.evaluations) + " residual evaluations)\n";
    if (r.subsets.size() > 1) {
      s += "global stage (search.subsets " + std::to_string(task.subsets) + "): the Burmester points of " +
           std::to_string(r.subsets.size() - 1) + " more five-pose subsets seed it too:";
      for (size_t k = 1; k < r.subsets.size(); ++k) {
        s += k > 1 ? ";" : "";
        for (int j : r.subsets[k]) s += " " + std::to_string(j + 1);
      }
      s += "\n";
    }
  }
  s += "Burmester points (real): " + std::to_string(r.points.size()) + "\n";
  for (size_t i = 0; i < r.points.size(); ++i) {
    const Dyad& d = r.points[i];
    s += "  " + std::to_string(i + 1) + ": centre (" + Num(d.M.x()) + ", " + Num(d.M.y()) + "), circle point (body) (" +
         Num(d.k.x()) + ", " + Num(d.k.y()) + "), radius " + Short(d.radius, 9) + ", residual " + Short(d.residual, 3) +
         (r.subsets.size() > 1 && i < r.point_subset.size() ? ", of poses" + [&] {
           std::string o;
           for (int j : r.subsets[static_cast<size_t>(r.point_subset[i])]) o += " " + std::to_string(j + 1);
           return o;
         }()
                                                             : std::string()) +
         "\n";
  }
  s += "four-bars (crank dyad, rocker dyad):\n";
  for (size_t i = 0; i < r.candidates.size(); ++i) {
    const MotionCandidate& c = r.candidates[i];
    s += "  " + std::to_string(c.crank + 1) + "," + std::to_string(c.rocker + 1) + ": a " + Short(c.fourbar.a) + " b " +
         Short(c.fourbar.b) + " c " + Short(c.fourbar.c) + " d " + Short(c.fourbar.d) + ": " +
         (c.ok ? "passes" + std::string(c.mode != 0 && c.mode != r.model_mode ? " on the mirror mode" : "") +
                     " (largest point error " + Short(c.worst_point, 3) + ", angle " + Short(c.worst_angle, 3) +
                      " rad; link ratio " + Short(c.ratio, 4) +
                      (task.poses.size() > 5 ? "; least-squares error " + Short(c.error, 4) + ", LM iterations " +
                                                   std::to_string(c.iterations)
                                             : std::string()) +
                      ")"
               : c.why) +
         (static_cast<int>(i) == r.chosen ? "  <- written" : "") + "\n";
  }
  return s;
}

}  // namespace mechgen::synthesis
