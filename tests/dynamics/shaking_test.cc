// The generated shaking force and moment (EvalShaking, the `shaking` quantity; issue 16, Paul
// ch. 7) against oracles independent of the generated code:
//  - models/slider_crank_motor.yaml: the centres of mass written here in closed form from the
//    model's text (crank at O, rod's G midway between B and C, the piston at C with
//    x_C = a cos q + sqrt(b^2 - a^2 sin^2 q)), along q(t) = q0 + qd t + qdd t^2 / 2; the linear
//    momentum's rate sum m a_G by a fourth-order second difference of sum m r_G(t), the angular
//    momentum about O, H = sum (r_G x m v_G + J omega), by fourth-order differences of the
//    positions and the rod's angle, and its rate by a difference of H;
//  - models/fourbar_massive.yaml: the same differences of the solved positions' centres of mass
//    (midpoints of the bars' scene points);
//  - F is the sum of the per-link columns, M the sum of M_link, mass and r_C the masses' sum and
//    their weighted mean;
//  - the four-bar without gravity: F and M equal what the kinetostatics' ground reactions and the
//    driving torque's reaction load the frame with (-R_A + R_D, d R_D,y - drive about A = O);
//  - models/fourbar_balanced.yaml (Berkof-Lowen counterweights): F = 0 to rounding against the
//    scale sum m |a_G| at 360 crank angles at constant speed and with a crank acceleration, r_C
//    still and at the point the derivation in the model's description predicts,
//    (m4 d + m3 z3 d / b) / m with the rocker's and crank's totals written out here; with the
//    counterweights removed (balance = 0) F is of the order of that scale.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <vector>

#include "fourbar_balanced.h"
#include "fourbar_massive.h"
#include "slider_crank_motor.h"

namespace {

// Every shipped model says whether it has EvalShaking.
static_assert(mech::slider_crank_motor::Model::kHasShaking);
static_assert(mech::fourbar_massive::Model::kHasShaking);
static_assert(mech::fourbar_balanced::Model::kHasShaking);

// A mechanism's mass data as the oracle sees it: per link (by index), the centre of mass and
// the angle at time t along the motion.
struct Oracle {
  struct Body {
    int link;
    double m, J;
  };
  std::array<Body, 3> bodies;  // both models have three moving links
  // r_G and theta of every body at time t.
  std::function<void(double t, std::vector<Eigen::Vector2d>* rG, std::vector<double>* th)> at;

  // The linear momentum's rate d/dt sum m v_G = sum m a_G at t = 0 (fourth-order second difference).
  Eigen::Vector2d MomentumRate(double h) const {
    Eigen::Vector2d s[5];
    for (int i = 0; i < 5; ++i) {
      std::vector<Eigen::Vector2d> r;
      std::vector<double> th;
      at((i - 2) * h, &r, &th);
      s[i].setZero();
      for (size_t b = 0; b < bodies.size(); ++b) s[i] += bodies[b].m * r[b];
    }
    return (-s[0] + 16 * s[1] - 30 * s[2] + 16 * s[3] - s[4]) / (12 * h * h);
  }
  // The angular momentum about O at time t: velocities by a fourth-order difference.
  double AngularMomentum(double t, double h) const {
    std::vector<Eigen::Vector2d> r[5];
    std::vector<double> th[5];
    for (int i = 0; i < 5; ++i) at(t + (i - 2) * h, &r[i], &th[i]);
    double H = 0;
    for (size_t b = 0; b < bodies.size(); ++b) {
      const Eigen::Vector2d v = (r[0][b] - 8 * r[1][b] + 8 * r[3][b] - r[4][b]) / (12 * h);
      // The angles relative to the middle one, so that a jump of 2 pi between atan2 values is none.
      auto d = [&](int i) { return std::remainder(th[i][b] - th[2][b], 2 * M_PI); };
      const double w = (d(0) - 8 * d(1) + 8 * d(3) - d(4)) / (12 * h);
      const Eigen::Vector2d& g = r[2][b];
      H += bodies[b].m * (g.x() * v.y() - g.y() * v.x()) + bodies[b].J * w;
    }
    return H;
  }
  double AngularMomentumRate(double h) const {
    return (AngularMomentum(-2 * h, h) - 8 * AngularMomentum(-h, h) + 8 * AngularMomentum(h, h) -
            AngularMomentum(2 * h, h)) /
           (12 * h);
  }
};

// EvalShaking of model M at (q, qd, qdd), the positions solved from the assembly guess.
template <class M>
typename M::template ShakingT<double> Shake(const typename M::template ParamsT<double>& p, double q0, double qd0,
                                            double qdd0) {
  Eigen::Matrix<double, M::kNq, 1> q, qd, qdd;
  q(0) = q0;
  qd(0) = qd0;
  qdd(0) = qdd0;
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  const auto report = M::Solve(p, q, &phi);
  EXPECT_EQ(report.status, decltype(report.status)::kConverged);
  typename M::template CoefficientsT<double> c;
  M::Coeffs(p, q, phi, &c);
  typename M::template ShakingT<double> s;
  M::Shaking(p, q, phi, qd, qdd, c, &s);
  return s;
}

// F against -d/dt of the linear momentum, M against -d/dt of the angular momentum about O, the
// per-link columns against the totals, r_G against the oracle's centres at t = 0.
template <class M>
void CheckAgainstMomenta(const typename M::template ShakingT<double>& s, const Oracle& o) {
  const Eigen::Vector2d dP = o.MomentumRate(1e-3);
  const double dH = o.AngularMomentumRate(1e-3);
  std::vector<Eigen::Vector2d> r;
  std::vector<double> th;
  o.at(0.0, &r, &th);
  double scale = 0, mass = 0;
  Eigen::Vector2d first_moment = Eigen::Vector2d::Zero();
  for (size_t b = 0; b < o.bodies.size(); ++b) {
    scale += s.F_link.col(o.bodies[b].link).norm() * (1 + r[b].norm()) + std::abs(s.M_link(o.bodies[b].link));
    mass += o.bodies[b].m;
    first_moment += o.bodies[b].m * r[b];
    EXPECT_NEAR((s.r_G.col(o.bodies[b].link) - r[b]).norm(), 0.0, 1e-12 * (1 + r[b].norm()));
  }
  ASSERT_GT(scale, 1.0);  // the motion does accelerate the masses: the test can fail
  EXPECT_NEAR(s.F(0), -dP.x(), 1e-7 * scale);
  EXPECT_NEAR(s.F(1), -dP.y(), 1e-7 * scale);
  EXPECT_NEAR(s.M, -dH, 1e-7 * scale);
  EXPECT_NEAR((s.F - s.F_link.rowwise().sum()).norm(), 0.0, 1e-12 * scale);
  EXPECT_NEAR(s.M - s.M_link.sum(), 0.0, 1e-12 * scale);
  EXPECT_NEAR(s.mass, mass, 1e-12 * mass);
  EXPECT_NEAR((s.r_C - first_moment / mass).norm(), 0.0, 1e-12);
  // The ground has no centre of mass; its columns are zero.
  EXPECT_TRUE(std::isnan(s.r_G(0, M::kGroundLink)));
  EXPECT_EQ(s.F_link.col(M::kGroundLink).norm(), 0.0);
  EXPECT_EQ(s.M_link(M::kGroundLink), 0.0);
}

TEST(GeneratedShaking, SliderCrankAgainstClosedFormMomenta) {
  using M = mech::slider_crank_motor::Model;
  const M::ParamsT<double> p;
  const double a = p.a, b = p.b;
  static_assert(M::kNumLinks == 4, "ground, crank, rod, piston");
  for (const auto& [q0, qd0, qdd0] : {std::array<double, 3>{0.3, 2.0, 3.0}, std::array<double, 3>{2.2, -1.5, 0.7},
                                      std::array<double, 3>{4.0, 3.0, -2.5}, std::array<double, 3>{5.5, 0.0, 4.0}}) {
    SCOPED_TRACE("q = " + std::to_string(q0));
    Oracle o;
    // The model's mass data: crank m1 with J_fly about O; rod m2, J = m2 b^2 / 12 at mid-length;
    // piston m3 at C, J = 0.001 (it does not turn).
    o.bodies = {{{1, p.m1, p.J_fly}, {2, p.m2, p.m2 * b * b / 12}, {3, p.m3, 0.001}}};
    const double q0_ = q0, qd0_ = qd0, qdd0_ = qdd0;
    o.at = [=](double t, std::vector<Eigen::Vector2d>* r, std::vector<double>* th) {
      const double q = q0_ + qd0_ * t + qdd0_ * t * t / 2;
      const Eigen::Vector2d B(a * std::cos(q), a * std::sin(q));
      const double root = std::sqrt(b * b - a * a * std::sin(q) * std::sin(q));
      const Eigen::Vector2d C(a * std::cos(q) + root, 0);
      *r = {Eigen::Vector2d::Zero(), (B + C) / 2, C};
      *th = {q, std::atan2(-a * std::sin(q), root), 0.0};
    };
    CheckAgainstMomenta<M>(Shake<M>(p, q0, qd0, qdd0), o);
  }
}

TEST(GeneratedShaking, FourBarAgainstMomentaOfTheSolvedPositions) {
  using M = mech::fourbar_massive::Model;
  const M::ParamsT<double> p;
  const double rho = p.rho;
  auto mid = [](const char* a, const char* b) {
    int ia = -1, ib = -1;
    for (int i = 0; i < M::kNumScenePoints; ++i) {
      if (std::strcmp(M::kScenePointNames[i], a) == 0) ia = i;
      if (std::strcmp(M::kScenePointNames[i], b) == 0) ib = i;
    }
    EXPECT_GE(ia, 0);
    EXPECT_GE(ib, 0);
    return std::array<int, 2>{ia, ib};
  };
  const std::array<int, 2> bars[3] = {mid("crank.A", "crank.B"), mid("coupler.B", "coupler.C"),
                                      mid("rocker.D", "rocker.C")};
  for (const auto& [q0, qd0, qdd0] : {std::array<double, 3>{0.4, 2.0, 3.0}, std::array<double, 3>{2.5, -1.2, 0.5},
                                      std::array<double, 3>{4.4, 1.5, -2.0}}) {
    SCOPED_TRACE("q = " + std::to_string(q0));
    Oracle o;
    o.bodies = {{{1, rho * p.a, rho * p.a * p.a * p.a / 12},
                 {2, rho * p.b, rho * p.b * p.b * p.b / 12},
                 {3, rho * p.c, rho * p.c * p.c * p.c / 12}}};
    o.at = [&, q0 = q0, qd0 = qd0, qdd0 = qdd0](double t, std::vector<Eigen::Vector2d>* r, std::vector<double>* th) {
      Eigen::Matrix<double, 1, 1> q;
      q(0) = q0 + qd0 * t + qdd0 * t * t / 2;
      Eigen::Matrix<double, M::kNphi, 1> phi;
      for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
      EXPECT_EQ(M::Solve(p, q, &phi).status, mech::fourbar_massive::SolveStatus::kConverged);
      Eigen::Matrix<double, 2, M::kNumScenePoints> scene;
      M::Scene(p, q, phi, &scene);
      r->clear();
      th->clear();
      for (const auto& bar : bars) {
        const Eigen::Vector2d A = scene.col(bar[0]), B = scene.col(bar[1]);
        r->push_back((A + B) / 2);
        th->push_back(std::atan2(B.y() - A.y(), B.x() - A.x()));
      }
    };
    CheckAgainstMomenta<M>(Shake<M>(p, q0, qd0, qdd0), o);
  }
}

// Without gravity the frame feels only the ground joints' reactions and the driver's reaction:
// the kinetostatics' R_A (ground on crank, at A = O), R_D (rocker on ground, at D = (d, 0)) and
// drive (the torque on the crank, reacting on the ground).
TEST(GeneratedShaking, FourBarEqualsTheFramesLoadFromTheKinetostatics) {
  using M = mech::fourbar_massive::Model;
  M::ParamsT<double> p;
  p.g = 0;
  for (int i = 0; i < 8; ++i) {
    const double q0 = 0.3 + 0.8 * i, qd0 = 2.5 - 0.6 * i, qdd0 = 1.5 - 0.4 * i;
    SCOPED_TRACE("q = " + std::to_string(q0));
    Eigen::Matrix<double, 1, 1> q, qd, qdd;
    q(0) = q0;
    qd(0) = qd0;
    qdd(0) = qdd0;
    Eigen::Matrix<double, M::kNphi, 1> phi;
    for (int k = 0; k < M::kNphi; ++k) phi(k) = M::kAssemblyPhi[k];
    ASSERT_EQ(M::Solve(p, q, &phi).status, mech::fourbar_massive::SolveStatus::kConverged);
    M::CoefficientsT<double> c;
    M::Coeffs(p, q, phi, &c);
    M::StaticsT<double> st;
    M::Kinetostatics(p, q, phi, qd, qdd, 0.0, c, &st);
    M::ShakingT<double> s;
    M::Shaking(p, q, phi, qd, qdd, c, &s);
    ASSERT_STREQ(M::kReactionNames[0], "F_A_x");
    ASSERT_STREQ(M::kReactionNames[6], "F_D_x");
    const Eigen::Vector2d R_A(st.R(0), st.R(1)), R_D(st.R(6), st.R(7));
    const Eigen::Vector2d on_frame = -R_A + R_D;
    const double moment_on_frame = p.d * R_D.y() - st.drive(0);
    const double scale = 1 + R_A.norm() + R_D.norm() + std::abs(st.drive(0));
    EXPECT_NEAR(s.F(0), on_frame.x(), 1e-10 * scale);
    EXPECT_NEAR(s.F(1), on_frame.y(), 1e-10 * scale);
    EXPECT_NEAR(s.M, moment_on_frame, 1e-10 * scale * (1 + p.d));
    EXPECT_GT(s.F.norm(), 1e-3 * scale);  // an unbalanced four-bar shakes its frame
  }
}

// The balanced four-bar over a turn at constant crank speed (and with a crank acceleration):
// the largest |F| / sum m |a_G|, the centre of mass' largest distance from its value at the
// first angle, and the sweep's largest scale.
struct BalanceSweep {
  double worst_ratio = 0, worst_drift = 0, max_force = 0, max_scale = 0;
  Eigen::Vector2d r_C0{0, 0};
};

BalanceSweep SweepBalanced(const mech::fourbar_balanced::Model::ParamsT<double>& p, double qdd0) {
  using M = mech::fourbar_balanced::Model;
  BalanceSweep out;
  Eigen::Matrix<double, M::kNphi, 1> phi;
  for (int k = 0; k < M::kNphi; ++k) phi(k) = M::kAssemblyPhi[k];
  for (int i = 0; i < 360; ++i) {
    Eigen::Matrix<double, 1, 1> q, qd, qdd;
    q(0) = i * M_PI / 180;
    qd(0) = 10.0;  // rad/s
    qdd(0) = qdd0;
    const auto report = M::Solve(p, q, &phi);  // continued from the last angle: one branch
    EXPECT_EQ(report.status, mech::fourbar_balanced::SolveStatus::kConverged) << i;
    M::CoefficientsT<double> c;
    M::Coeffs(p, q, phi, &c);
    M::ShakingT<double> s;
    M::Shaking(p, q, phi, qd, qdd, c, &s);
    double scale = 0;  // sum m |a_G|
    for (int l = 0; l < M::kNumLinks; ++l) scale += s.F_link.col(l).norm();
    if (i == 0) out.r_C0 = s.r_C;
    out.worst_ratio = std::max(out.worst_ratio, s.F.norm() / scale);
    out.worst_drift = std::max(out.worst_drift, (s.r_C - out.r_C0).norm());
    out.max_force = std::max(out.max_force, s.F.norm());
    out.max_scale = std::max(out.max_scale, scale);
  }
  return out;
}

TEST(GeneratedShaking, BalancedFourBarHasNoShakingForce) {
  using M = mech::fourbar_balanced::Model;
  M::ParamsT<double> p;
  ASSERT_EQ(p.balance, 1.0);
  for (double qdd0 : {0.0, 40.0}) {
    SCOPED_TRACE("qdd = " + std::to_string(qdd0));
    const BalanceSweep b = SweepBalanced(p, qdd0);
    EXPECT_GT(b.max_scale, 1.0);  // N: the links do accelerate
    EXPECT_LT(b.worst_ratio, 1e-9);
    EXPECT_LT(b.worst_drift, 1e-12);  // m; the links are 0.05 to 0.2 m long
    // Where the derivation puts it: S = m4 d + m3 z3 d / b with the rocker's total mass m4
    // (bar and counterweight), over the total mass.
    const double m2 = p.m2b + p.mc2, m4 = p.m4b + p.mc4, m = m2 + p.m3 + m4;
    EXPECT_NEAR(b.r_C0.x(), (m4 * p.d + p.m3 * p.x3 * p.d / p.b) / m, 1e-14);
    EXPECT_NEAR(b.r_C0.y(), p.m3 * p.y3 * p.d / p.b / m, 1e-14);
  }
  // The unbalanced twin: the counterweights removed at run time.
  double* balance = p.Find("balance");
  ASSERT_NE(balance, nullptr);
  *balance = 0;
  const BalanceSweep u = SweepBalanced(p, 0.0);
  EXPECT_GT(u.worst_ratio, 0.3);
  EXPECT_GT(u.max_force, 1.0);  // N
  EXPECT_GT(u.worst_drift, 1e-3);  // m
}

}  // namespace
