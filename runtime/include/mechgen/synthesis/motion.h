/**
 * \file synthesis/motion.h
 * Motion generation as a task (issue 28): the body (the model's coupler) through poses (its
 * point and its angle). Five poses: the Burmester points (synthesis/burmester.h), every pair
 * of them a four-bar, each written into the model's parameters (a four-bar with its frame
 * placed: crank pivot (x0, y0), ground at theta0, as tests/synthesis/models/synth_fourbar.yaml;
 * the task names them) and run by the generated model: at each pose's crank angle, on the
 * model's assembly mode, the coupler point must be the pose's point and the coupler's angle
 * the pose's angle (up to the constant between the body's x axis and BC) to 1e-9 of the
 * poses' size, and from pose to pose (the crank turning the way the poses go) the model must
 * stay on its mode. Of the pairs that pass, the one with the smallest ratio of its longest to
 * its shortest link is the answer (the first of equals). Four poses: the circle- and centre-point curves (written as a CSV by the command).
 * Needs yaml-cpp.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "mechgen/synthesis/burmester.h"
#include "mechgen/synthesis/function.h"

namespace mechgen::synthesis {

struct MotionTask {
  std::string file, model;
  std::vector<Pose> poses;
  std::string point;           ///< the model's coupler point (the pose's point), e.g. coupler.P
  std::string coupler_angle;   ///< the coupler's angle among the model's phi, e.g. theta_coupler
  /// The model's parameters for a, b, c, d, xi, eta, x0, y0, theta0 (in this order).
  std::vector<std::string> parameters;
  int curve_rays = 3600;
  int line = 1, column = 1;
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
    Known(path, root, {"synthesis", "model", "poses", "point", "coupler_angle", "parameters", "search"}, "a motion task");
    if (const YAML::Node m = root["model"]) {
      if (!m.IsScalar()) throw Error{Where(path, m.Mark()) + "model: expected a file name"};
      task->model = m.Scalar();
    }
    const YAML::Node poses = Required(path, root, "poses", "the body's poses, [[x, y, angle], ...]");
    if (!poses.IsSequence() || poses.size() < 4 || poses.size() > 5)
      throw Error{Where(path, poses.Mark()) + "poses: expected four (the Burmester curves) or five (the Burmester points) [x, y, angle]"};
    for (const YAML::Node& p : poses) {
      if (!p.IsSequence() || p.size() != 3) throw Error{Where(path, p.Mark()) + "a pose: expected [x, y, angle]"};
      task->poses.push_back({Number(path, p[0], "pose x"), Number(path, p[1], "pose y"), Number(path, p[2], "pose angle", true)});
    }
    const YAML::Node point = Required(path, root, "point", "the model's coupler point that is the pose's point, e.g. coupler.P");
    if (!point.IsScalar()) throw Error{Where(path, point.Mark()) + "point: expected a point name"};
    task->point = point.Scalar();
    const YAML::Node angle = Required(path, root, "coupler_angle", "the coupler's angle among the model's dependent variables, e.g. theta_coupler");
    if (!angle.IsScalar()) throw Error{Where(path, angle.Mark()) + "coupler_angle: expected a dependent variable's name"};
    task->coupler_angle = angle.Scalar();
    const YAML::Node params = Required(path, root, "parameters",
                                       "the model's parameters {crank: a, coupler: b, rocker: c, ground: d, xi: xi, eta: eta, x0: x0, y0: y0, theta0: theta0}");
    if (!params.IsMap()) throw Error{Where(path, params.Mark()) + "parameters: expected a mapping"};
    Known(path, params, MotionParameterKeys(), "parameters");
    for (const std::string& key : MotionParameterKeys()) {
      const YAML::Node v = Required(path, params, key, "the model's parameter for it");
      if (!v.IsScalar()) throw Error{Where(path, v.Mark()) + "parameters." + key + ": expected a parameter name"};
      task->parameters.push_back(v.Scalar());
    }
    task->line = params.Mark().line + 1;
    task->column = params.Mark().column + 1;
    if (const YAML::Node s = root["search"]) {
      if (!s.IsMap()) throw Error{Where(path, s.Mark()) + "search: expected a mapping"};
      Known(path, s, {"curve_rays"}, "search (motion task)");
      if (s["curve_rays"]) task->curve_rays = static_cast<int>(Count(path, s["curve_rays"], "curve_rays", 90, 1000000));
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
  FourBarFromDyads fourbar;
  double worst_point = kInf, worst_angle = kInf;  ///< over the poses
  bool ok = false;
  std::string why;                 ///< when not ok
  double ratio = kInf;             ///< longest link / shortest link
};

struct MotionResult {
  std::vector<Dyad> points;
  std::vector<MotionCandidate> candidates;
  int chosen = -1;                 ///< index into candidates, -1 none
  std::vector<CurvePoint> curve;   ///< four poses
};

/// Five poses: the Burmester points and their four-bars on M; four poses: the curves.
template <class M>
bool SynthesizeMotion(const MotionTask& task, const typename M::template ParamsT<double>& base, MotionResult* out,
                      std::string* error) {
  using Params = typename M::template ParamsT<double>;
  int point = -1, angle = -1;
  for (int m = 0; m < M::kNumPoints; ++m)
    if (task.point == M::kPointNames[static_cast<size_t>(m)]) point = m;
  for (int i = 0; i < M::kNphi; ++i)
    if (task.coupler_angle == M::kPhiNames[static_cast<size_t>(i)]) angle = i;
  if (point < 0) return *error = task.file + ": point '" + task.point + "' is not among the model's output points", false;
  if (angle < 0)
    return *error = task.file + ": coupler_angle '" + task.coupler_angle + "' is not one of the model's dependent variables",
           false;
  if constexpr (M::kNq != 1) {
    return *error = task.file + ": motion generation needs a one-input four-bar model", false;
  } else {
    {
      Params p = base;
      for (const std::string& name : task.parameters)
        if (p.Find(name.c_str()) == nullptr)
          return *error = task.file + ":" + std::to_string(task.line) + ":" + std::to_string(task.column) +
                          ": parameters: no parameter '" + name + "' in the model",
                 false;
    }
    MotionResult r;
    const std::vector<Pose>& poses = task.poses;
    const double L = burmester_internal::Scale(poses);
    if (poses.size() == 4) {
      Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
      for (const Pose& p : poses) centroid += Eigen::Vector2d(p.x, p.y);
      r.curve = FourPoseCurve(poses, centroid / 4.0 + Eigen::Vector2d(0.1234567 * L, 0.0765432 * L), task.curve_rays);
      *out = r;
      return true;
    }
    r.points = BurmesterPoints(poses, task.curve_rays);
    const int n = static_cast<int>(poses.size());
    for (int i = 0; i < static_cast<int>(r.points.size()); ++i) {
      for (int j = 0; j < static_cast<int>(r.points.size()); ++j) {
        if (i == j) continue;
        MotionCandidate c;
        c.crank = i, c.rocker = j;
        c.fourbar = FourBarOfDyads(poses, r.points[static_cast<size_t>(i)], r.points[static_cast<size_t>(j)]);
        const FourBarFromDyads& f = c.fourbar;
        Params p = base;
        const double values[9] = {f.a, f.b, f.c, f.d, f.xi, f.eta, f.x0, f.y0, f.theta0};
        for (size_t k = 0; k < 9; ++k) *p.Find(task.parameters[k].c_str()) = values[k];
        auto solve = [&](double q, Eigen::Matrix<double, M::kNphi, 1>* phi) {
          Eigen::Matrix<double, M::kNq, 1> qv;
          qv(0) = q;
          for (int i2 = 0; i2 < M::kNphi; ++i2) (*phi)(i2) = M::kAssemblyPhi[static_cast<size_t>(i2)];
          const auto report = M::Solve(p, qv, phi, M::kDefaultModes);
          using Status = decltype(report.status);
          return report.status == Status::kConverged && report.branch_measure > 1e-12 && phi->allFinite();
        };
        Eigen::Matrix<double, M::kNphi, 1> phi;
        typename M::template CoefficientsT<double> co;
        c.worst_point = c.worst_angle = 0;
        double offset = 0;
        for (int k = 0; k < n && c.why.empty(); ++k) {
          const double q = f.crank_angle[static_cast<size_t>(k)];
          if (!solve(q, &phi)) {
            c.why = "pose " + std::to_string(k + 1) + ": the model does not assemble on its mode";
            break;
          }
          Eigen::Matrix<double, M::kNq, 1> qv;
          qv(0) = q;
          M::Coeffs(p, qv, phi, &co);
          const double dp = std::hypot(co.r_P(0, point) - poses[static_cast<size_t>(k)].x, co.r_P(1, point) - poses[static_cast<size_t>(k)].y);
          if (k == 0) offset = phi(angle) - poses[0].angle;
          const double da = std::abs(WrapPi(phi(angle) - poses[static_cast<size_t>(k)].angle - offset));
          c.worst_point = std::max(c.worst_point, dp);
          c.worst_angle = std::max(c.worst_angle, da);
          if (!(dp <= 1e-9 * std::max(1.0, L)) || !(da <= 1e-9))
            c.why = "pose " + std::to_string(k + 1) + ": the model's coupler is not there on its assembly mode (the other mode's four-bar)";
        }
        // From pose to pose, the crank turning the way the poses go.
        double sum = 0;
        for (int k = 0; k + 1 < n; ++k) sum += WrapPi(f.crank_angle[static_cast<size_t>(k + 1)] - f.crank_angle[static_cast<size_t>(k)]);
        const double dir = sum >= 0 ? 1.0 : -1.0;
        for (int k = 0; k + 1 < n && c.why.empty(); ++k) {
          const double q0 = f.crank_angle[static_cast<size_t>(k)];
          const double span = Wrap(dir * (f.crank_angle[static_cast<size_t>(k + 1)] - q0));
          const int steps = std::max(1, static_cast<int>(std::ceil(span / (kTwoPi / 720))));
          for (int s = 1; s < steps && c.why.empty(); ++s)
            if (!solve(q0 + dir * span * s / steps, &phi))
              c.why = "between poses " + std::to_string(k + 1) + " and " + std::to_string(k + 2) +
                      ": the model leaves its assembly mode (a dead point or no closure)";
        }
        c.ok = c.why.empty();
        c.ratio = std::max({f.a, f.b, f.c, f.d}) / std::min({f.a, f.b, f.c, f.d});
        if (c.ok && (r.chosen < 0 || c.ratio < r.candidates[static_cast<size_t>(r.chosen)].ratio))
          r.chosen = static_cast<int>(r.candidates.size());
        r.candidates.push_back(c);
      }
    }
    *out = r;
    return true;
  }
}

inline std::string MotionReport(const MotionTask& task, const MotionResult& r) {
  std::string s = "# motion generation: " + std::to_string(task.poses.size()) + " poses (task " + task.file + ")\n";
  if (task.poses.size() == 4) {
    s += "the circle- and centre-point curves: " + std::to_string(r.curve.size()) + " points (curves.csv)\n";
    return s;
  }
  s += "Burmester points (real): " + std::to_string(r.points.size()) + "\n";
  for (size_t i = 0; i < r.points.size(); ++i) {
    const Dyad& d = r.points[i];
    s += "  " + std::to_string(i + 1) + ": centre (" + Num(d.M.x()) + ", " + Num(d.M.y()) + "), circle point (body) (" +
         Num(d.k.x()) + ", " + Num(d.k.y()) + "), radius " + Short(d.radius, 9) + ", residual " + Short(d.residual, 3) + "\n";
  }
  s += "four-bars (crank dyad, rocker dyad):\n";
  for (size_t i = 0; i < r.candidates.size(); ++i) {
    const MotionCandidate& c = r.candidates[i];
    s += "  " + std::to_string(c.crank + 1) + "," + std::to_string(c.rocker + 1) + ": a " + Short(c.fourbar.a) + " b " +
         Short(c.fourbar.b) + " c " + Short(c.fourbar.c) + " d " + Short(c.fourbar.d) + ": " +
         (c.ok ? "passes (largest point error " + Short(c.worst_point, 3) + ", angle " + Short(c.worst_angle, 3) +
                      " rad; link ratio " + Short(c.ratio, 4) + ")"
               : c.why) +
         (static_cast<int>(i) == r.chosen ? "  <- written" : "") + "\n";
  }
  return s;
}

}  // namespace mechgen::synthesis
