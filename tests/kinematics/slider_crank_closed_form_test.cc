// The generated offset slider-crank (models/slider_crank.yaml) against its own closed form,
// over a full crank turn.
//
// Crank OB = a at angle q about O; rod BC = b; C runs on the line y = e; s = x_C.
// With u = e - a sin q (the rise from B to C) and w = sqrt(b^2 - u^2) (the rod's x
// projection, > 0 on the model's branch: C to the right of B):
//   s = a cos q + w,            th_rod = asin(u / b) = atan2(u, w)
// Derivatives (u' = -a cos q, u'' = a sin q):
//   w'  = -u u' / w,            w'' = -(u'^2 + u u'') / w - u^2 u'^2 / w^3
//   s'  = -a sin q + w',        s'' = -a cos q + w''
//   th' = u' / w,               th'' = u'' / w - u' w' / w^2
// (th = asin(u/b) so th' = u' / sqrt(b^2 - u^2) = u' / w.) The point slider.C = (s, e):
// K_P = (s', 0), L_P = (s'', 0).
#include <gtest/gtest.h>

#include <cmath>

#include "kinematics_test_util.h"
#include "slider_crank.h"

namespace {

using M = mech::slider_crank::Model;
using mechtest::kTwoPi;
using mechtest::WrapAngle;

constexpr int kNumSamples = 720;  // full crank turn, 0.5 deg apart

// The closed form has a few dozen flops and divides by w >= sqrt(b^2 - (a + e)^2) = 2.97,
// all values are O(1): rounding ~1e-15. 1e-12 relative to max(1, |value|) is three orders
// above that and far below the effect of any wrong term.
constexpr double kTol = 1e-12;

struct SliderCrank {
  double q, th, s, K_th, K_s, L_th, L_s;
};

SliderCrank ClosedForm(double a, double b, double e, double q) {
  SliderCrank r{};
  r.q = q;
  const double u = e - a * std::sin(q), ud = -a * std::cos(q), udd = a * std::sin(q);
  const double w = std::sqrt(b * b - u * u);
  const double wd = -u * ud / w;
  const double wdd = -(ud * ud + u * udd) / w - u * u * ud * ud / (w * w * w);
  r.s = a * std::cos(q) + w;
  r.th = std::atan2(u, w);
  r.K_s = -a * std::sin(q) + wd;
  r.L_s = -a * std::cos(q) + wdd;
  r.K_th = ud / w;
  r.L_th = udd / w - ud * wd / (w * w);
  return r;
}

double Rel(double v) { return std::max(1.0, std::abs(v)); }

class SliderCrankClosedFormTest : public ::testing::Test {
 protected:
  M::ParamsT<double> p;
  SliderCrank At(int k) const { return ClosedForm(p.a, p.b, p.e, kTwoPi * k / kNumSamples); }
  static Eigen::Matrix<double, 1, 1> Q(const SliderCrank& r) {
    return Eigen::Matrix<double, 1, 1>(r.q);
  }
  static Eigen::Vector2d PhiOf(const SliderCrank& r) { return {r.th, r.s}; }
};

TEST_F(SliderCrankClosedFormTest, ModelDeclaresTheExpectedCoordinates) {
  ASSERT_STREQ(M::kPhiNames[0], "theta_rod");
  ASSERT_STREQ(M::kPhiNames[1], "s_slide");
  ASSERT_STREQ(M::kPointNames[0], "slider.C");
}

TEST_F(SliderCrankClosedFormTest, ClosedFormPositionsCloseGeneratedLoopOverFullTurn) {
  const auto sweep = mechtest::SweepConfigs<M>(p, kNumSamples);
  ASSERT_EQ(sweep.size(), static_cast<size_t>(kNumSamples));
  for (int k = 0; k < kNumSamples; ++k) {
    const auto r = At(k);
    Eigen::Vector2d res;
    M::Phi(p, Q(r), PhiOf(r), &res);
    EXPECT_LT(res.lpNorm<Eigen::Infinity>(), kTol) << "q = " << r.q;
    EXPECT_NEAR(WrapAngle(sweep[k].phi(0) - r.th), 0.0, kTol) << "q = " << r.q;
    EXPECT_NEAR(sweep[k].phi(1), r.s, kTol * Rel(r.s)) << "q = " << r.q;
  }
}

TEST_F(SliderCrankClosedFormTest, VelocityCoefficientsMatchClosedForm) {
  for (int k = 0; k < kNumSamples; ++k) {
    const auto r = At(k);
    M::CoefficientsT<double> out;
    M::Coeffs(p, Q(r), PhiOf(r), &out);
    EXPECT_NEAR(out.K(0, 0), r.K_th, kTol * Rel(r.K_th)) << "theta_rod, q = " << r.q;
    EXPECT_NEAR(out.K(1, 0), r.K_s, kTol * Rel(r.K_s)) << "s_slide, q = " << r.q;
  }
}

TEST_F(SliderCrankClosedFormTest, CentripetalCoefficientsMatchClosedForm) {
  for (int k = 0; k < kNumSamples; ++k) {
    const auto r = At(k);
    M::CoefficientsT<double> out;
    M::Coeffs(p, Q(r), PhiOf(r), &out);
    EXPECT_NEAR(out.L(0, 0), r.L_th, kTol * Rel(r.L_th)) << "theta_rod, q = " << r.q;
    EXPECT_NEAR(out.L(1, 0), r.L_s, kTol * Rel(r.L_s)) << "s_slide, q = " << r.q;
  }
}

TEST_F(SliderCrankClosedFormTest, SliderPointMatchesClosedForm) {
  for (int k = 0; k < kNumSamples; ++k) {
    const auto r = At(k);
    M::CoefficientsT<double> out;
    M::Coeffs(p, Q(r), PhiOf(r), &out);
    EXPECT_NEAR(out.r_P(0, 0), r.s, kTol * Rel(r.s)) << "q = " << r.q;
    EXPECT_NEAR(out.r_P(1, 0), p.e, kTol) << "q = " << r.q;
    EXPECT_NEAR(out.K_P(0, 0), r.K_s, kTol * Rel(r.K_s)) << "q = " << r.q;
    EXPECT_NEAR(out.K_P(1, 0), 0.0, kTol) << "q = " << r.q;
    EXPECT_NEAR(out.L_P(0, 0), r.L_s, kTol * Rel(r.L_s)) << "q = " << r.q;
    EXPECT_NEAR(out.L_P(1, 0), 0.0, kTol) << "q = " << r.q;
  }
}

// The generated position solver (one-angle acos block, then a linear block) returns the
// closed form.
TEST_F(SliderCrankClosedFormTest, GeneratedSolvePositionsMatchesClosedForm) {
  for (int k = 0; k < kNumSamples; ++k) {
    const auto r = At(k);
    Eigen::Vector2d phi = PhiOf(r) + Eigen::Vector2d(0.01, 0.01);  // a predictor
    const auto report = M::Solve(p, Q(r), &phi);
    ASSERT_EQ(report.status, mech::slider_crank::SolveStatus::kConverged) << "q = " << r.q;
    EXPECT_NEAR(WrapAngle(phi(0) - r.th), 0.0, kTol) << "q = " << r.q;
    EXPECT_NEAR(phi(1), r.s, kTol * Rel(r.s)) << "q = " << r.q;
  }
}

// Top and bottom dead centres: s' = 0 where crank and rod are collinear,
// i.e. at q0 = asin(e / (a + b)) (outer) with s = sqrt((a + b)^2 - e^2).
TEST_F(SliderCrankClosedFormTest, OuterDeadCentreHasZeroSliderVelocity) {
  const double q0 = std::asin(p.e / (p.a + p.b));
  const auto r = ClosedForm(p.a, p.b, p.e, q0);
  EXPECT_NEAR(r.s, std::sqrt((p.a + p.b) * (p.a + p.b) - p.e * p.e), kTol);
  M::CoefficientsT<double> out;
  M::Coeffs(p, Q(r), PhiOf(r), &out);
  EXPECT_NEAR(out.K(1, 0), 0.0, kTol);
  EXPECT_LT(out.L(1, 0), -0.1);  // s is at its maximum
}

}  // namespace
