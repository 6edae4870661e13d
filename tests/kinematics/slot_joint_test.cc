// The slot joint (issue 13): a pin sliding in a slot of another link, one joint instead of a
// block link, a revolute and a prismatic joint. Two test models (tests/kinematics/models/):
//  - slot_oscillating_block: models/inverted_slider_crank.yaml written with the slot. Its
//    positions, K and L must be those of the shipped model (the old workaround) and of the
//    closed form theta_rocker = atan2(a sin q, a cos q - d), s = |DB|, to 1e-12; K also
//    against central differences of the closed-form positions.
//  - slot_whitworth: d < a (the rocker turns fully) with the slot given by two points of the
//    rocker (the line D -> H at 45 deg in its frame): theta_rocker = atan2(B - D) - 45 deg.
#include <gtest/gtest.h>

#include <cmath>

#include "inverted_slider_crank.h"
#include "slot_oscillating_block.h"
#include "slot_whitworth.h"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kSamples = 720;
constexpr double kTol = 1e-12;

double Wrap(double a) { return std::remainder(a, 2 * kPi); }

// The pin B = (a cos q, a sin q) seen from the pivot D = (dx, dy): the slot's line angle and
// the slide. Closed form, independent of the generator.
struct Pose {
  double line, s;
};
Pose ClosedForm(double a, double dx, double dy, double q) {
  const double x = a * std::cos(q) - dx, y = a * std::sin(q) - dy;
  return {std::atan2(y, x), std::hypot(x, y)};
}

template <class M, class Status>
Eigen::Vector2d Solved(const typename M::template ParamsT<double>& p, double q, const Eigen::Vector2d& guess,
                       Status converged) {
  Eigen::Vector2d phi = guess + Eigen::Vector2d(0.01, 0.01);
  const auto report = M::Solve(p, Eigen::Matrix<double, 1, 1>(q), &phi);
  EXPECT_EQ(report.status, converged) << "q = " << q;
  return phi;
}

TEST(SlotJoint, OscillatingBlockIsTheOldWorkaroundAndTheClosedForm) {
  using S = mech::slot_oscillating_block::Model;
  using O = mech::inverted_slider_crank::Model;
  ASSERT_STREQ(S::kPhiNames[0], O::kPhiNames[0]);
  ASSERT_STREQ(S::kPhiNames[1], O::kPhiNames[1]);
  const S::ParamsT<double> ps;
  const O::ParamsT<double> po;
  const double a = ps.a, d = ps.d;
  for (int k = 0; k < kSamples; ++k) {
    const double q = 2 * kPi * k / kSamples;
    const Pose c = ClosedForm(a, d, 0, q);
    const Eigen::Vector2d exact(c.line, c.s);
    const Eigen::Vector2d s = Solved<S>(ps, q, exact, mech::slot_oscillating_block::SolveStatus::kConverged);
    const Eigen::Vector2d o = Solved<O>(po, q, exact, mech::inverted_slider_crank::SolveStatus::kConverged);
    EXPECT_NEAR(Wrap(s(0) - c.line), 0, kTol) << q;
    EXPECT_NEAR(s(1), c.s, kTol) << q;
    EXPECT_NEAR(Wrap(s(0) - o(0)), 0, kTol) << q;
    EXPECT_NEAR(s(1) - o(1), 0, kTol) << q;
    const Eigen::Matrix<double, 1, 1> qv(q);
    S::CoefficientsT<double> cs;
    O::CoefficientsT<double> co;
    S::Coeffs(ps, qv, s, &cs);
    O::Coeffs(po, qv, o, &co);
    for (int i = 0; i < 2; ++i) {
      EXPECT_NEAR(cs.K(i, 0), co.K(i, 0), kTol) << q;
      EXPECT_NEAR(cs.L(i, 0), co.L(i, 0), kTol) << q;
      EXPECT_NEAR(cs.r_P(i, 0), co.r_P(i, 0), kTol) << q;
      EXPECT_NEAR(cs.K_P(i, 0), co.K_P(i, 0), kTol) << q;
      EXPECT_NEAR(cs.L_P(i, 0), co.L_P(i, 0), kTol) << q;
    }
    // K against central differences of the closed form (error ~ h^2 |phi'''| + eps/h).
    const double h = 1e-5;
    const Pose plus = ClosedForm(a, d, 0, q + h), minus = ClosedForm(a, d, 0, q - h);
    EXPECT_NEAR(cs.K(0, 0), Wrap(plus.line - minus.line) / (2 * h), 1e-8) << q;
    EXPECT_NEAR(cs.K(1, 0), (plus.s - minus.s) / (2 * h), 1e-8) << q;
  }
}

TEST(SlotJoint, WhitworthWithASlotThroughTwoPoints) {
  using W = mech::slot_whitworth::Model;
  const W::ParamsT<double> p;
  const double a = p.a, d = p.d;
  double prev = 0;
  for (int k = 0; k < kSamples; ++k) {
    const double q = 2 * kPi * k / kSamples;
    const Pose c = ClosedForm(a, 0, d, q);
    const double theta = c.line - kPi / 4;  // the slot is at 45 deg in the rocker's frame
    const Eigen::Vector2d phi =
        Solved<W>(p, q, Eigen::Vector2d(theta, c.s), mech::slot_whitworth::SolveStatus::kConverged);
    EXPECT_NEAR(Wrap(phi(0) - theta), 0, kTol) << q;
    EXPECT_NEAR(phi(1), c.s, kTol) << q;
    W::CoefficientsT<double> out;
    W::Coeffs(p, Eigen::Matrix<double, 1, 1>(q), phi, &out);
    const double h = 1e-5;
    const Pose plus = ClosedForm(a, 0, d, q + h), minus = ClosedForm(a, 0, d, q - h);
    EXPECT_NEAR(out.K(0, 0), Wrap(plus.line - minus.line) / (2 * h), 1e-8) << q;
    EXPECT_NEAR(out.K(1, 0), (plus.s - minus.s) / (2 * h), 1e-8) << q;
    // rocker.E = D + R(theta) (2, 0).
    EXPECT_NEAR(out.r_P(0, 0), 2 * std::cos(theta), kTol) << q;
    EXPECT_NEAR(out.r_P(1, 0), d + 2 * std::sin(theta), kTol) << q;
    // The rocker turns fully (quick return): its angle advances with the crank's.
    if (k > 0) {
      EXPECT_GT(Wrap(theta - prev), 0) << q;
    }
    prev = theta;
  }
}

}  // namespace
