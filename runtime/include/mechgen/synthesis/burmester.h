/**
 * \file synthesis/burmester.h
 * Motion generation by Burmester theory (issue 28, the exact method): a body (the coupler) is
 * to pass through poses j = 0..n-1, each its reference point P_j and its angle alpha_j. A dyad
 * is a ground pivot M (the centre point) and a moving pivot k fixed in the body (the circle
 * point, in the body's frame: origin P, x axis at alpha), at K_j = P_j + R(alpha_j) k in pose
 * j; it guides the body when |K_j - M| is the same in every pose:
 *   e_j(M, k) = (|K_j - M|^2 - |K_0 - M|^2) / 2 = c_j(k) - a_j(k) . M = 0,  j = 1..n-1,
 *   a_j(k) = P_j - P_0 + (R_j - R_0) k,
 *   c_j(k) = (|P_j|^2 - |P_0|^2) / 2 + (R_j^T P_j - R_0^T P_0) . k
 * (|k|^2 cancels): linear in M for a given k, and in k for a given M.
 *  - Three poses: every circle point k has its centre point: the 2 x 2 solve A(k) M = c(k) (the
 *    circumcentre of K_0, K_1, K_2).
 *  - Four poses: k is a circle point where the 3 x 3 matrix [A(k) | c(k)] is singular: the
 *    circle-point curve (a cubic); its centres M (the least-squares solve, consistent on the
 *    curve) the centre-point curve. Traced along rays k = base + s (cos phi, sin phi), s > 0,
 *    phi over a full turn: on each ray the determinant is a cubic in s (interpolated through
 *    four values of s: exact up to rounding), its real positive roots by the companion
 *    matrix's eigenvalues, polished by Newton on the cubic.
 *  - Five poses: the Burmester points, where the circle-point curve of poses 0..3 also meets
 *    pose 4's equation: along the traced curve (roots matched from ray to ray) e_4(M(k), k)
 *    changes sign; each change is polished by Newton on the four equations in (M, k). At most
 *    four are real; each gives a dyad; any two give a four-bar (FourBarOfDyads).
 * Every point found is checked in the distance form |K_j - M| - |K_0 - M| (not the bilinear
 * form it was solved in). Header-only, Eigen.
 */
#pragma once

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include <Eigen/Dense>

namespace mechgen::synthesis {

/// A pose of the body: its reference point and its angle (rad).
struct Pose {
  double x = 0, y = 0, angle = 0;
};

/// A dyad: the centre point M (ground) and the circle point k (body frame).
struct Dyad {
  Eigen::Vector2d M = Eigen::Vector2d::Zero();
  Eigen::Vector2d k = Eigen::Vector2d::Zero();
  double radius = 0;     ///< |K_0 - M|
  double residual = 0;   ///< max_j | |K_j - M| - |K_0 - M| | over the poses used
};

namespace burmester_internal {

inline Eigen::Matrix2d Rot(double a) {
  Eigen::Matrix2d R;
  R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return R;
}
inline Eigen::Vector2d P(const Pose& p) { return Eigen::Vector2d(p.x, p.y); }

/// Rows j = 1..m of A(k) (m x 2) and c(k) for the poses 0..m.
inline void System(const std::vector<Pose>& poses, int m, const Eigen::Vector2d& k, Eigen::MatrixXd* A,
                   Eigen::VectorXd* c) {
  A->resize(m, 2);
  c->resize(m);
  const Eigen::Vector2d P0 = P(poses[0]);
  const Eigen::Matrix2d R0 = Rot(poses[0].angle);
  for (int j = 1; j <= m; ++j) {
    const Eigen::Vector2d Pj = P(poses[static_cast<size_t>(j)]);
    const Eigen::Matrix2d Rj = Rot(poses[static_cast<size_t>(j)].angle);
    A->row(j - 1) = (Pj - P0 + (Rj - R0) * k).transpose();
    (*c)(j - 1) = 0.5 * (Pj.squaredNorm() - P0.squaredNorm()) + (Rj.transpose() * Pj - R0.transpose() * P0).dot(k);
  }
}

/// The poses' size: the largest distance of a reference point from their centroid (at least 1e-12).
inline double Scale(const std::vector<Pose>& poses) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Pose& p : poses) mean += P(p);
  mean /= static_cast<double>(poses.size());
  double s = 0;
  for (const Pose& p : poses) s = std::max(s, (P(p) - mean).norm());
  return std::max(s, 1e-12);
}

}  // namespace burmester_internal

/// The circle point's position in pose j (world).
inline Eigen::Vector2d CirclePointAt(const Pose& pose, const Eigen::Vector2d& k) {
  return burmester_internal::P(pose) + burmester_internal::Rot(pose.angle) * k;
}

/// max_j | |K_j - M| - |K_0 - M| | over the poses (the distance form: the check).
inline double DyadResidual(const std::vector<Pose>& poses, const Eigen::Vector2d& M, const Eigen::Vector2d& k) {
  const double r0 = (CirclePointAt(poses[0], k) - M).norm();
  double worst = 0;
  for (const Pose& p : poses) worst = std::max(worst, std::abs((CirclePointAt(p, k) - M).norm() - r0));
  return worst;
}

/// Three poses: the centre point of the circle point k (false if K_0, K_1, K_2 are collinear).
inline bool CentreOfCirclePoint(const std::vector<Pose>& poses, const Eigen::Vector2d& k, Dyad* out) {
  Eigen::MatrixXd A;
  Eigen::VectorXd c;
  burmester_internal::System(poses, 2, k, &A, &c);
  const Eigen::Matrix2d A2 = A;
  if (!(std::abs(A2.determinant()) > 1e-14 * A2.squaredNorm())) return false;
  out->M = A2.partialPivLu().solve(Eigen::Vector2d(c));
  out->k = k;
  out->radius = (CirclePointAt(poses[0], k) - out->M).norm();
  out->residual = DyadResidual(std::vector<Pose>(poses.begin(), poses.begin() + 3), out->M, k);
  return true;
}

/// A point of the four-pose curves, with the ray it was found on.
struct CurvePoint {
  Dyad dyad;
  int ray = 0;
  double s = 0;
};

/// Four poses (the first four of `poses`): the circle-point curve and its centre points along
/// `rays` rays from `base` (a point off the curve; s > 0). Points whose centre does not solve
/// the three equations (the curve's points at infinity) are left out.
inline std::vector<CurvePoint> FourPoseCurve(const std::vector<Pose>& poses, const Eigen::Vector2d& base, int rays) {
  using namespace burmester_internal;
  const double L = Scale(std::vector<Pose>(poses.begin(), poses.begin() + 4));
  std::vector<CurvePoint> out;
  auto det = [&](const Eigen::Vector2d& k) {
    Eigen::MatrixXd A;
    Eigen::VectorXd c;
    System(poses, 3, k, &A, &c);
    Eigen::Matrix3d B;
    B << A, c;
    return B.determinant();
  };
  for (int r = 0; r < rays; ++r) {
    const double phi = 2 * M_PI * r / rays;
    const Eigen::Vector2d u(std::cos(phi), std::sin(phi));
    // The cubic through s = 0, L, 2L, 3L (Newton's divided differences, then the monomials).
    double f[4];
    for (int i = 0; i < 4; ++i) f[i] = det(base + (i * L) * u);
    // In t = s / L: f(t) = f0 + d1 t + d2 t (t-1) + d3 t (t-1)(t-2).
    const double d1 = f[1] - f[0];
    const double d2 = (f[2] - 2 * f[1] + f[0]) / 2;
    const double d3 = (f[3] - 3 * f[2] + 3 * f[1] - f[0]) / 6;
    const double c3 = d3, c2 = d2 - 3 * d3, c1 = d1 - d2 + 2 * d3, c0 = f[0];
    const double big = std::max({std::abs(c0), std::abs(c1), std::abs(c2), std::abs(c3)});
    std::vector<double> roots;
    auto cubic = [&](double t) { return ((c3 * t + c2) * t + c1) * t + c0; };
    auto dcubic = [&](double t) { return (3 * c3 * t + 2 * c2) * t + c1; };
    if (std::abs(c3) > 1e-12 * big) {
      Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
      C(0, 0) = -c2 / c3, C(0, 1) = -c1 / c3, C(0, 2) = -c0 / c3;
      C(1, 0) = 1, C(2, 1) = 1;
      const Eigen::EigenSolver<Eigen::Matrix3d> es(C, false);
      for (int i = 0; i < 3; ++i) {
        const std::complex<double> z = es.eigenvalues()(i);
        if (std::abs(z.imag()) <= 1e-7 * std::max(1.0, std::abs(z))) roots.push_back(z.real());
      }
    } else if (std::abs(c2) > 1e-12 * big) {
      const double disc = c1 * c1 - 4 * c2 * c0;
      if (disc >= 0) {
        roots.push_back((-c1 + std::sqrt(disc)) / (2 * c2));
        roots.push_back((-c1 - std::sqrt(disc)) / (2 * c2));
      }
    }
    for (double t : roots) {
      for (int it = 0; it < 20; ++it) {  // Newton on the cubic
        const double d = dcubic(t);
        if (d == 0) break;
        const double step = cubic(t) / d;
        t -= step;
        if (std::abs(step) <= 1e-15 * std::max(1.0, std::abs(t))) break;
      }
      if (!(t > 0) || !std::isfinite(t) || t > 1e6) continue;
      const Eigen::Vector2d k = base + (t * L) * u;
      Eigen::MatrixXd A;
      Eigen::VectorXd c;
      System(poses, 3, k, &A, &c);
      const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
      if (!(svd.singularValues()(1) > 1e-10 * svd.singularValues()(0))) continue;
      CurvePoint cp;
      cp.dyad.M = svd.solve(c);
      cp.dyad.k = k;
      cp.dyad.radius = (CirclePointAt(poses[0], k) - cp.dyad.M).norm();
      cp.dyad.residual = DyadResidual(std::vector<Pose>(poses.begin(), poses.begin() + 4), cp.dyad.M, k);
      cp.ray = r;
      cp.s = t * L;
      out.push_back(cp);
    }
  }
  return out;
}

/// Newton on the four equations e_1..e_4 of five poses in z = (M, k), from z (at most 60
/// steps; false if it left the finite numbers: the caller checks the residuals).
inline bool PolishBurmester(const std::vector<Pose>& poses, Eigen::Vector2d* M, Eigen::Vector2d* k) {
  using namespace burmester_internal;
  const double L = Scale(poses);
  const Eigen::Vector2d P0 = P(poses[0]);
  const Eigen::Matrix2d R0 = Rot(poses[0].angle);
  for (int it = 0; it < 60; ++it) {
    Eigen::MatrixXd A;
    Eigen::VectorXd c;
    System(poses, 4, *k, &A, &c);
    const Eigen::Vector4d F = c - A * (*M);
    Eigen::Matrix4d J;
    for (int j = 1; j <= 4; ++j) {
      const Eigen::Vector2d Pj = P(poses[static_cast<size_t>(j)]);
      const Eigen::Matrix2d Rj = Rot(poses[static_cast<size_t>(j)].angle);
      J.block<1, 2>(j - 1, 0) = -A.row(j - 1);
      J.block<1, 2>(j - 1, 2) = (Rj.transpose() * Pj - R0.transpose() * P0 - (Rj - R0).transpose() * (*M)).transpose();
    }
    const Eigen::Vector4d dz = J.fullPivLu().solve(-F);
    if (!dz.allFinite()) return false;
    M->noalias() += dz.head<2>();
    k->noalias() += dz.tail<2>();
    if (dz.norm() <= 1e-14 * std::max(L, M->norm() + k->norm())) break;
  }
  return M->allFinite() && k->allFinite();  // the caller checks the residuals
}

/// Five poses: the Burmester points (real; at most four), each a dyad checked in the distance
/// form. `rays` sets the density of the curve's tracing (the points found are exact: polished).
inline std::vector<Dyad> BurmesterPoints(const std::vector<Pose>& poses, int rays = 3600) {
  using namespace burmester_internal;
  std::vector<Dyad> found;
  if (poses.size() != 5) return found;
  const double L = Scale(poses);
  Eigen::Vector2d base = Eigen::Vector2d::Zero();
  for (const Pose& p : poses) base += P(p);
  base = base / 5.0 + Eigen::Vector2d(0.1234567 * L, 0.0765432 * L);  // off the curve, generically
  const std::vector<CurvePoint> curve = FourPoseCurve(poses, base, rays);
  // e_4 at each curve point (pose 4 against pose 0).
  auto e4 = [&](const Dyad& d) {
    return 0.5 * ((CirclePointAt(poses[4], d.k) - d.M).squaredNorm() - (CirclePointAt(poses[0], d.k) - d.M).squaredNorm());
  };
  std::vector<std::vector<size_t>> by_ray(static_cast<size_t>(rays));
  for (size_t i = 0; i < curve.size(); ++i) by_ray[static_cast<size_t>(curve[i].ray)].push_back(i);
  auto add = [&](Eigen::Vector2d M, Eigen::Vector2d k) {
    if (!PolishBurmester(poses, &M, &k)) return;
    for (const Dyad& d : found)
      if ((d.M - M).norm() + (d.k - k).norm() <= 1e-7 * L) return;
    Dyad d;
    d.M = M, d.k = k;
    d.radius = (CirclePointAt(poses[0], k) - M).norm();
    d.residual = DyadResidual(poses, M, k);
    if (d.residual <= 1e-9 * std::max(L, d.radius)) found.push_back(d);
  };
  for (int r = 0; r < rays; ++r) {
    const auto& here = by_ray[static_cast<size_t>(r)];
    const auto& next = by_ray[static_cast<size_t>((r + 1) % rays)];
    for (size_t i : here) {
      // The nearest point on the next ray continues the branch (if it is near enough).
      size_t best = curve.size();
      double gap = 0.05 * (curve[i].s + L);
      for (size_t j : next) {
        const double g = (curve[j].dyad.k - curve[i].dyad.k).norm();
        if (g < gap) gap = g, best = j;
      }
      if (best == curve.size()) continue;
      const double g0 = e4(curve[i].dyad), g1 = e4(curve[best].dyad);
      if ((g0 <= 0) != (g1 <= 0)) {
        const double w = g0 / (g0 - g1);
        add(curve[i].dyad.M + w * (curve[best].dyad.M - curve[i].dyad.M),
            curve[i].dyad.k + w * (curve[best].dyad.k - curve[i].dyad.k));
      }
    }
  }
  return found;
}

/// The four-bar of two dyads, as the parameters of tests/synthesis/models/synth_fourbar.yaml
/// (crank pivot A = M1 at (x0, y0), ground AD at theta0 to D = M2, crank a, coupler b (B to
/// C), rocker c, the body's reference point at (xi, eta) in the coupler frame: origin B, x
/// along BC), and the crank's absolute angle in each pose.
struct FourBarFromDyads {
  double a = 0, b = 0, c = 0, d = 0, xi = 0, eta = 0, x0 = 0, y0 = 0, theta0 = 0;
  std::vector<double> crank_angle;
};

inline FourBarFromDyads FourBarOfDyads(const std::vector<Pose>& poses, const Dyad& crank, const Dyad& rocker) {
  FourBarFromDyads f;
  const Eigen::Vector2d A = crank.M, D = rocker.M;
  const Eigen::Vector2d B = CirclePointAt(poses[0], crank.k), C = CirclePointAt(poses[0], rocker.k);
  f.a = (B - A).norm();
  f.b = (C - B).norm();
  f.c = (C - D).norm();
  f.d = (D - A).norm();
  f.x0 = A.x(), f.y0 = A.y();
  f.theta0 = std::atan2(D.y() - A.y(), D.x() - A.x());
  const Eigen::Vector2d u = (C - B) / f.b, n(-u.y(), u.x());
  const Eigen::Vector2d BP = burmester_internal::P(poses[0]) - B;
  f.xi = BP.dot(u), f.eta = BP.dot(n);
  for (const Pose& p : poses) {
    const Eigen::Vector2d Bj = CirclePointAt(p, crank.k);
    f.crank_angle.push_back(std::atan2(Bj.y() - A.y(), Bj.x() - A.x()));
  }
  return f;
}

}  // namespace mechgen::synthesis
