// The generated inverted slider-crank (models/inverted_slider_crank.yaml) against Paul's
// closed forms for the oscillating block, §1.2 (PAUL_NOTES.md), over a full crank turn.
//
// Paul (1.2-1, -2):  a cos(th) + r cos(ph) - d = 0,  a sin(th) - r sin(ph) = 0,
// input th = theta_crank, r = |DB|, ph measured at D from the -x direction.
// Mapping (model description): theta_rocker = pi - ph, s_slot = r. Our generated loop is
// -a cos(q) + s cos(th_r) + d = 0, -a sin(q) + s sin(th_r) = 0: the same equations with the
// sign of both rows flipped, since cos(th_r) = -cos(ph) and sin(th_r) = sin(ph).
//
// Positions (1.2-3, -4):  ph = atan2(a sin th, d - a cos th),  r = a sin th / sin ph.
//   (1.2-4) is 0/0 where sin ph = 0 (th = 0, pi); there we use the x row (1.2-1) instead,
//   r = (d - a cos th) / cos ph: whichever of |sin ph|, |cos ph| is larger.
// Velocities (1.2-8, -9) with th' = 1:  r' = a sin(th + ph),  r ph' = a cos(th + ph).
// Accelerations: differentiate (1.2-8, -9) once more with th' = 1, th'' = 0:
//   r''  = a cos(th + ph) (1 + ph')
//   r' ph' + r ph'' = -a sin(th + ph) (1 + ph')  =>  ph'' = [-a sin(th+ph)(1+ph') - r' ph'] / r
// Ours: K = (d th_r/dq, ds/dq) = (-ph', r'), L = (-ph'', r'').
// The point of interest rocker.E at 3 along the rocker from D = (d, 0):
//   r_E = D + 3 (cos th_r, sin th_r),  r_E' = 3 (-sin th_r, cos th_r) th_r',
//   r_E'' = 3 (-sin th_r, cos th_r) th_r'' - 3 (cos th_r, sin th_r) th_r'^2.
#include <gtest/gtest.h>

#include <cmath>

#include "inverted_slider_crank.h"
#include "kinematics_test_util.h"

namespace {

using M = mech::inverted_slider_crank::Model;
using mechtest::kPi;
using mechtest::kTwoPi;
using mechtest::WrapAngle;

constexpr int kNumSamples = 720;  // full crank turn, 0.5 deg apart
constexpr double kEOffset = 3.0;  // rocker.E body coordinate (models/inverted_slider_crank.yaml)

// Closed forms of a few dozen flops with one division by r >= d - a = 1.5; all values are
// O(1) (s in [1.5, 3.5]; over the turn |K| <= 1, |L| <= 5/3). Rounding is ~1e-15;
// 1e-12 relative to max(1, |value|) is three orders above that and far below any error of
// a wrong term.
constexpr double kTol = 1e-12;

struct PaulOscillatingBlock {
  double q, th_r, s;  // our coordinates
  double K_th, K_s;   // d th_r/dq, ds/dq
  double L_th, L_s;   // d^2 th_r/dq^2, d^2 s/dq^2
  double xE, yE, xEd, yEd, xEdd, yEdd;
};

PaulOscillatingBlock ClosedForm(double a, double d, double th) {
  PaulOscillatingBlock o{};
  o.q = th;
  const double ph = std::atan2(a * std::sin(th), d - a * std::cos(th));  // (1.2-3)
  const double r = std::abs(std::sin(ph)) > std::abs(std::cos(ph))
                       ? a * std::sin(th) / std::sin(ph)         // (1.2-4)
                       : (d - a * std::cos(th)) / std::cos(ph);  // (1.2-1)
  const double rd = a * std::sin(th + ph);                       // (1.2-8)
  const double phd = a * std::cos(th + ph) / r;                  // (1.2-9)
  const double rdd = a * std::cos(th + ph) * (1 + phd);
  const double phdd = (-a * std::sin(th + ph) * (1 + phd) - rd * phd) / r;
  o.th_r = kPi - ph;
  o.s = r;
  o.K_th = -phd;
  o.K_s = rd;
  o.L_th = -phdd;
  o.L_s = rdd;
  const double Cr = std::cos(o.th_r), Sr = std::sin(o.th_r);
  o.xE = d + kEOffset * Cr;
  o.yE = kEOffset * Sr;
  o.xEd = -kEOffset * Sr * o.K_th;
  o.yEd = kEOffset * Cr * o.K_th;
  o.xEdd = -kEOffset * Sr * o.L_th - kEOffset * Cr * o.K_th * o.K_th;
  o.yEdd = kEOffset * Cr * o.L_th - kEOffset * Sr * o.K_th * o.K_th;
  return o;
}

double Rel(double v) { return std::max(1.0, std::abs(v)); }

class PaulInvertedSliderCrankTest : public ::testing::Test {
 protected:
  M::ParamsT<double> p;
  PaulOscillatingBlock At(int k) const { return ClosedForm(p.a, p.d, kTwoPi * k / kNumSamples); }
  static Eigen::Matrix<double, 1, 1> Q(const PaulOscillatingBlock& o) {
    return Eigen::Matrix<double, 1, 1>(o.q);
  }
  static Eigen::Vector2d PhiOf(const PaulOscillatingBlock& o) { return {o.th_r, o.s}; }
};

TEST_F(PaulInvertedSliderCrankTest, ModelDeclaresTheExpectedCoordinates) {
  ASSERT_STREQ(M::kPhiNames[0], "theta_rocker");
  ASSERT_STREQ(M::kPhiNames[1], "s_slot");
  ASSERT_STREQ(M::kPointNames[0], "rocker.E");
}

// (1.2-3, -4) close the generated loop and are the branch continuation follows.
TEST_F(PaulInvertedSliderCrankTest, PaulPositionsEq1_2_3_4CloseGeneratedLoop) {
  const auto sweep = mechtest::SweepConfigs<M>(p, kNumSamples);
  ASSERT_EQ(sweep.size(), static_cast<size_t>(kNumSamples));
  for (int k = 0; k < kNumSamples; ++k) {
    const auto o = At(k);
    Eigen::Vector2d res;
    M::Phi(p, Q(o), PhiOf(o), &res);
    EXPECT_LT(res.lpNorm<Eigen::Infinity>(), kTol) << "q = " << o.q;
    EXPECT_NEAR(WrapAngle(sweep[k].phi(0) - o.th_r), 0.0, kTol) << "q = " << o.q;
    EXPECT_NEAR(sweep[k].phi(1), o.s, kTol * Rel(o.s)) << "q = " << o.q;
  }
}

// Generated K against (1.2-8, -9).
TEST_F(PaulInvertedSliderCrankTest, VelocityCoefficientsMatchPaulEq1_2_8_9) {
  for (int k = 0; k < kNumSamples; ++k) {
    const auto o = At(k);
    M::CoefficientsT<double> out;
    M::Coeffs(p, Q(o), PhiOf(o), &out);
    EXPECT_NEAR(out.K(0, 0), o.K_th, kTol * Rel(o.K_th)) << "theta_rocker, q = " << o.q;
    EXPECT_NEAR(out.K(1, 0), o.K_s, kTol * Rel(o.K_s)) << "s_slot, q = " << o.q;
  }
}

// Generated L against the derivatives of (1.2-8, -9).
TEST_F(PaulInvertedSliderCrankTest, CentripetalCoefficientsMatchDerivativeOfPaulEq1_2_8_9) {
  for (int k = 0; k < kNumSamples; ++k) {
    const auto o = At(k);
    M::CoefficientsT<double> out;
    M::Coeffs(p, Q(o), PhiOf(o), &out);
    EXPECT_NEAR(out.L(0, 0), o.L_th, kTol * Rel(o.L_th)) << "theta_rocker, q = " << o.q;
    EXPECT_NEAR(out.L(1, 0), o.L_s, kTol * Rel(o.L_s)) << "s_slot, q = " << o.q;
  }
}

// Generated rocker.E position, K_P and L_P against the rigid-body formulas driven by Paul's
// rocker angle and its derivatives.
TEST_F(PaulInvertedSliderCrankTest, RockerPointMatchesPaulDrivenRigidBodyFormulas) {
  for (int k = 0; k < kNumSamples; ++k) {
    const auto o = At(k);
    M::CoefficientsT<double> out;
    M::Coeffs(p, Q(o), PhiOf(o), &out);
    EXPECT_NEAR(out.r_P(0, 0), o.xE, kTol * Rel(o.xE)) << "q = " << o.q;
    EXPECT_NEAR(out.r_P(1, 0), o.yE, kTol * Rel(o.yE)) << "q = " << o.q;
    EXPECT_NEAR(out.K_P(0, 0), o.xEd, kTol * Rel(o.xEd)) << "q = " << o.q;
    EXPECT_NEAR(out.K_P(1, 0), o.yEd, kTol * Rel(o.yEd)) << "q = " << o.q;
    EXPECT_NEAR(out.L_P(0, 0), o.xEdd, kTol * Rel(o.xEdd)) << "q = " << o.q;
    EXPECT_NEAR(out.L_P(1, 0), o.yEdd, kTol * Rel(o.yEdd)) << "q = " << o.q;
  }
}

// The generated position solver (closed-form RRP dyad) returns Paul's (1.2-3, -4).
TEST_F(PaulInvertedSliderCrankTest, GeneratedSolvePositionsMatchesPaulEq1_2_3_4) {
  for (int k = 0; k < kNumSamples; ++k) {
    const auto o = At(k);
    Eigen::Vector2d phi = PhiOf(o) + Eigen::Vector2d(0.01, 0.01);  // a predictor
    const auto report = M::Solve(p, Q(o), &phi);
    ASSERT_EQ(report.status, mech::inverted_slider_crank::SolveStatus::kConverged) << "q = " << o.q;
    EXPECT_NEAR(WrapAngle(phi(0) - o.th_r), 0.0, kTol) << "q = " << o.q;
    EXPECT_NEAR(phi(1), o.s, kTol * Rel(o.s)) << "q = " << o.q;
  }
}

// Paul's phi of the model's assembly configuration is close to the model's guess
// (theta_crank = 90 deg: ph = atan2(1, 2.5) = 21.8 deg, so theta_rocker = 158.2 deg and
// s = sqrt(7.25) = 2.693), i.e. the mapping theta_rocker = pi - ph is the model's.
TEST_F(PaulInvertedSliderCrankTest, MappingMatchesModelAssemblyGuess) {
  const auto o = ClosedForm(p.a, p.d, M::kAssemblyQ[0]);
  EXPECT_NEAR(o.th_r, M::kAssemblyPhi[0], 0.5 * kPi / 180);
  EXPECT_NEAR(o.s, M::kAssemblyPhi[1], 0.01);
  EXPECT_NEAR(o.s, std::sqrt(7.25), kTol);
}

}  // namespace
