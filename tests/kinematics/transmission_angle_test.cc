// The generated transmission angles (EvalTransmissionAngles) against hand formulas:
//  - four-bar (Paul §1.1 geometry): the coupler b, the rocker c and the diagonal from the
//    crank pin B to the rocker pivot D form a triangle, delta^2 = a^2 + d^2 - 2 a d cos q,
//    so cos mu = (b^2 + c^2 - delta^2) / (2 b c) (law of cosines), at every crank angle of
//    a full turn, open and crossed assembly;
//  - Watt six-bar: each loop's angle between its coupler and output link directions,
//    cos mu = cos(theta_coupler - theta_output) from the solved angles;
//  - the toggle: |det Phi_phi| = b c |sin mu| for the four-bar (det Phi_phi = 0 exactly
//    where mu = 0 or pi), and the product over both loops for the Watt six-bar.
// Positions come from the test's own Newton solve (kinematics_test_util.h), not from the
// generated solver.
#include <gtest/gtest.h>

#include <cmath>

#include "fourbar.h"
#include "fourbar_crossed.h"
#include "kinematics_test_util.h"
#include "watt_sixbar.h"

namespace {

using mechtest::kPi;

// mu is an atan2 of O(10) products of O(4) values: ~1e-15 absolute; the hand formula's
// acos loses accuracy only where mu is near 0 or pi (not on these sweeps, mu in 38..140 deg).
constexpr double kTol = 1e-12;

template <class M>
void CheckFourBar() {
  const mechtest::ParamsD<M> p;
  const auto configs = mechtest::SweepConfigs<M>(p, 720);
  ASSERT_EQ(configs.size(), 720u);
  double mu_min = kPi, mu_max = 0;
  for (const auto& c : configs) {
    Eigen::Matrix<double, M::kNumTransmissionAngles, 1> mu;
    M::TransmissionAngles(p, c.q, c.phi, &mu);
    const double delta2 = p.a * p.a + p.d * p.d - 2 * p.a * p.d * std::cos(c.q(0));
    const double cos_mu = (p.b * p.b + p.c * p.c - delta2) / (2 * p.b * p.c);
    EXPECT_NEAR(std::cos(mu(0)), cos_mu, kTol) << "theta_crank = " << c.q(0);
    EXPECT_GE(mu(0), 0.0);
    EXPECT_LE(mu(0), kPi);
    mu_min = std::min(mu_min, mu(0));
    mu_max = std::max(mu_max, mu(0));
    double det = 0;
    M::DetPhiPhi(p, c.q, c.phi, &det);
    EXPECT_NEAR(std::abs(det), p.b * p.c * std::sin(mu(0)), 1e-12 * p.b * p.c);
  }
  // Crank-rocker extremes at q = 0 and pi (delta = d - a and d + a): 54.3 and 100.3 deg.
  EXPECT_NEAR(mu_min, std::acos((p.b * p.b + p.c * p.c - (p.d - p.a) * (p.d - p.a)) / (2 * p.b * p.c)), 1e-4);
  EXPECT_NEAR(mu_max, std::acos((p.b * p.b + p.c * p.c - (p.d + p.a) * (p.d + p.a)) / (2 * p.b * p.c)), 1e-4);
}

TEST(TransmissionAngle, FourBarOpenMatchesLawOfCosines) {
  static_assert(mech::fourbar::Model::kNumTransmissionAngles == 1);
  EXPECT_STREQ(mech::fourbar::Model::kTransmissionJoints[0], "C");
  CheckFourBar<mech::fourbar::Model>();
}

TEST(TransmissionAngle, FourBarCrossedMatchesLawOfCosines) { CheckFourBar<mech::fourbar_crossed::Model>(); }

TEST(TransmissionAngle, WattSixBarBothLoops) {
  using M = mech::watt_sixbar::Model;
  static_assert(M::kNumTransmissionAngles == 2);
  EXPECT_STREQ(M::kTransmissionJoints[0], "C");
  EXPECT_STREQ(M::kTransmissionJoints[1], "F");
  const mechtest::ParamsD<M> p;
  const auto configs = mechtest::SweepConfigs<M>(p, 360);
  ASSERT_EQ(configs.size(), 360u);
  auto index = [](const char* name) {
    for (int i = 0; i < M::kNphi; ++i)
      if (std::string(M::kPhiNames[i]) == name) return i;
    return -1;
  };
  const int coupler = index("theta_coupler"), rocker = index("theta_rocker");
  const int link5 = index("theta_link5"), output = index("theta_output");
  ASSERT_GE(std::min({coupler, rocker, link5, output}), 0);
  for (const auto& c : configs) {
    Eigen::Matrix<double, 2, 1> mu;
    M::TransmissionAngles(p, c.q, c.phi, &mu);
    EXPECT_NEAR(std::cos(mu(0)), std::cos(c.phi(coupler) - c.phi(rocker)), kTol);
    EXPECT_NEAR(std::cos(mu(1)), std::cos(c.phi(link5) - c.phi(output)), kTol);
    double det = 0;
    M::DetPhiPhi(p, c.q, c.phi, &det);
    const double scale = p.b * p.c * p.f * p.o;
    EXPECT_NEAR(std::abs(det), scale * std::sin(mu(0)) * std::sin(mu(1)), 1e-12 * scale);
  }
}

}  // namespace
