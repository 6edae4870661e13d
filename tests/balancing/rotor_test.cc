// machines/balancing/rotor.h: the corrections cancel the unbalance's force and moment exactly (to
// rounding) for random rotors, a hand computation by the lever rule, static balancing, and
// the statuses of bad input.
#include "mechgen/machines/balancing/rotor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <vector>

namespace {

namespace bal = mechgen::balancing;
constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;

// Random rotors of 1 to 8 unbalances, random planes and radii: after the two corrections
// Σ m r e^{iθ} = 0 and Σ m r z e^{iθ} = 0 to rounding (relative to Σ m r and Σ m r |z|).
TEST(Rotor, TwoPlaneCorrectionsCancelForceAndMomentOfRandomRotors) {
  std::mt19937 gen(42);
  std::uniform_real_distribution<double> mass(0.01, 2), radius(0.01, 0.3), angle(-kPi, kPi), z(-0.5, 1.5);
  double worst_U = 0, worst_M = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + trial % 8;
    std::vector<bal::Unbalance> u(n);
    double scale_U = 0, scale_M = 0;
    for (bal::Unbalance& x : u) {
      x = {mass(gen), radius(gen), angle(gen), z(gen)};
      scale_U += x.m * x.r;
      scale_M += x.m * x.r * std::abs(x.z);
    }
    double z_L = z(gen), z_R = z(gen);
    if (std::abs(z_R - z_L) < 0.05) z_R = z_L + 0.3;
    const bal::RotorBalance b = bal::BalanceTwoPlanes(u.data(), n, z_L, z_R, radius(gen), radius(gen));
    ASSERT_TRUE(b.IsUsable());
    const bal::UnbalanceSums residual = bal::Residual(u.data(), n, b);
    // The corrections are of the size of the unbalance (times the lever ratios): rounding of a
    // few ulps of the largest term.
    const double lever = (std::abs(z_L) + std::abs(z_R) + 2) / std::abs(z_R - z_L);
    const double eps = 1e-15 * (scale_U + scale_M) * (1 + lever);
    EXPECT_LT(std::abs(residual.U), 4 * eps) << trial;
    EXPECT_LT(std::abs(residual.M), 4 * eps) << trial;
    worst_U = std::max(worst_U, std::abs(residual.U) / scale_U);
    worst_M = std::max(worst_M, std::abs(residual.M) / std::max(scale_M, 1e-300));
    EXPECT_GE(b.left.mass, 0);
    EXPECT_GE(b.right.mass, 0);
  }
  std::printf("worst relative residual: |U| %.2e, |M| %.2e\n", worst_U, worst_M);
}

// By hand (the lever rule: an unbalance m r at z splits between the planes as
// m r (z_R − z)/(z_R − z_L) at z_L and m r (z − z_L)/(z_R − z_L) at z_R):
//   2 kg at 0.1 m, 0°,  z = 0.1 m   (m r = 0.2 kg m)
//   1 kg at 0.2 m, 90°, z = 0.3 m   (m r = 0.2 kg m)
//   planes z_L = 0, z_R = 0.4 m, correction radius 0.1 m.
// Left plane: 0.2·0.3/0.4 = 0.15 at 0° and 0.2·0.1/0.4 = 0.05 at 90°: unbalance 0.15 + 0.05i,
// correction −0.15 − 0.05i: m r = √0.025 = 0.158114 kg m, 1.58114 kg at 180° + 18.435° =
// 198.435° (−161.565°). Right plane: 0.05 at 0° and 0.15 at 90°: correction −0.05 − 0.15i,
// 1.58114 kg at −108.435°. Static balancing in one plane: U = 0.2 + 0.2i, correction
// 0.282843 kg m at −135°, 2.82843 kg at 0.1 m.
TEST(Rotor, HandComputedTwoMassRotor) {
  const bal::Unbalance u[2] = {{2, 0.1, 0, 0.1}, {1, 0.2, 90 * kDeg, 0.3}};
  const bal::RotorBalance b = bal::BalanceTwoPlanes(u, 2, 0.0, 0.4, 0.1, 0.1);
  ASSERT_EQ(b.status, bal::RotorStatus::kOk);
  EXPECT_NEAR(b.left.mass, std::sqrt(0.025) / 0.1, 1e-13);
  EXPECT_NEAR(b.left.angle / kDeg, -180 + std::atan(1.0 / 3) / kDeg, 1e-11);  // −161.565°
  EXPECT_NEAR(b.right.mass, std::sqrt(0.025) / 0.1, 1e-13);
  EXPECT_NEAR(b.right.angle / kDeg, -90 - std::atan(1.0 / 3) / kDeg, 1e-11);  // −108.435°
  EXPECT_NEAR(b.left.mass, 1.58114, 5e-6);
  EXPECT_NEAR(b.right.angle / kDeg, -108.435, 5e-4);

  const bal::RotorBalance s = bal::BalanceStatic(u, 2, 0.1);
  ASSERT_EQ(s.status, bal::RotorStatus::kOk);
  EXPECT_NEAR(s.left.mass, 2 * std::sqrt(2.0), 1e-13);
  EXPECT_NEAR(s.left.angle / kDeg, -135, 1e-11);
  // Statically balanced: no force; but the couple remains (M of the unbalances plus the
  // correction's at z = 0: 0.02 + 0.06i kg m²).
  const bal::UnbalanceSums r = bal::Residual(u, 2, s, /*two_planes=*/false);
  EXPECT_LT(std::abs(r.U), 1e-16);
  EXPECT_NEAR(std::abs(r.M), std::abs(std::complex<double>(0.02, 0.06)), 1e-16);
}

// A balanced rotor needs no correction (mass 0, angle 0).
TEST(Rotor, BalancedRotorNeedsNoCorrection) {
  const bal::Unbalance u[2] = {{1, 0.1, 0.3, 0.2}, {1, 0.1, 0.3 + kPi, 0.2}};
  const bal::RotorBalance b = bal::BalanceTwoPlanes(u, 2, 0, 1, 0.1, 0.1);
  ASSERT_TRUE(b.IsUsable());
  EXPECT_LT(b.left.mass, 1e-15);
  EXPECT_LT(b.right.mass, 1e-15);
}

TEST(Rotor, BadInputNamesTheProblem) {
  bal::Unbalance u[3] = {{1, 0.1, 0, 0}, {1, 0.1, 1, 0.5}, {1, 0.1, 2, 1}};
  EXPECT_EQ(bal::BalanceTwoPlanes(u, 3, 0.2, 0.2, 0.1, 0.1).status, bal::RotorStatus::kCoincidentPlanes);
  EXPECT_EQ(bal::BalanceTwoPlanes(u, 3, 0.0, 1.0, 0.0, 0.1).status, bal::RotorStatus::kZeroRadius);
  EXPECT_EQ(bal::BalanceStatic(u, 3, -0.1).status, bal::RotorStatus::kZeroRadius);
  u[1].m = -1;
  bal::RotorBalance b = bal::BalanceTwoPlanes(u, 3, 0.0, 1.0, 0.1, 0.1);
  EXPECT_EQ(b.status, bal::RotorStatus::kBadUnbalance);
  EXPECT_EQ(b.index, 1);
  u[1].m = 1;
  u[2].angle = std::nan("");
  b = bal::BalanceStatic(u, 3, 0.1);
  EXPECT_EQ(b.status, bal::RotorStatus::kBadUnbalance);
  EXPECT_EQ(b.index, 2);
  // Finite data whose correction mass overflows (issue 45): m r = 1e300 kg m at r = 1e-300 m.
  const bal::Unbalance heavy[1] = {{1e300, 1, 0, 0}};
  EXPECT_EQ(bal::BalanceStatic(heavy, 1, 1e-300).status, bal::RotorStatus::kNotFinite);
  EXPECT_EQ(bal::BalanceTwoPlanes(heavy, 1, -1, 1, 1e-300, 1).status, bal::RotorStatus::kNotFinite);
  const bal::RotorBalance fine = bal::BalanceStatic(heavy, 1, 1.0);  // the same rotor, a usable radius
  EXPECT_EQ(fine.status, bal::RotorStatus::kOk);
  EXPECT_DOUBLE_EQ(fine.left.mass, 1e300);
  // Sums that overflow: two unbalances of 1e308 kg m in the same direction.
  const bal::Unbalance two[2] = {{1e308, 1, 0, 0}, {1e308, 1, 0, 0}};
  EXPECT_EQ(bal::BalanceStatic(two, 2, 1.0).status, bal::RotorStatus::kNotFinite);
}

}  // namespace
