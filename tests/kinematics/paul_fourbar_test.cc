// The generated four-bar kinematics (models fourbar and fourbar_crossed) against Paul's
// hand formulas, *Kinematics and Dynamics of Planar Machinery* §1.1 (PAUL_NOTES.md):
// positions by circle intersection, velocity coefficients by eq. (1.1-8) / Lamé's theorem,
// centripetal coefficients by eqs. (1.1-9, -10), and the coupler point by (1.1.1-2..4).
// None of these oracles calls generated code; the generated Phi is only *evaluated* at the
// closed-form positions to check that they close the loop.
//
// ---- Mapping Paul's four-bar onto ours ------------------------------------------------
// Ours (models/fourbar.yaml):  a e^{iq} + b e^{i th_c} - c e^{i th_r} - d = 0,
//   q = theta_crank (input), th_c = theta_coupler, th_r = theta_rocker measured at D.
// Paul (1.1-2):  a1 e^{i th1} + a2 e^{i th2} + a3 e^{i th3} - f = 0, input th3.
// Vector addition commutes, so our loop *is* Paul's with
//   a3 = a, th3 = q           (the input link)
//   a2 = b, th2 = th_c        (the coupler)
//   a1 = c, th1 = th_r + pi   (-c e^{i th_r} = c e^{i (th_r + pi)})
//   f  = d.
// Paul's K = (k1, k2) = (d th1/d th3, d th2/d th3) = (K_rocker, K_coupler), and the
// accelerations carry over the same way (th1 and th_r differ by a constant).
//
// ---- The same closed forms re-derived in our own sign convention ----------------------
// Write U_x = e^{i th_x} and cross a complex equation with U_y by taking Im(. conj(U_y)).
// Velocity (q' = 1):  i (a U_q + b U_c w_c - c U_r w_r) = 0.
//   x U_r:  a sin(q - th_r) + b w_c sin(th_c - th_r) = 0
//           => w_c = K_coupler = a sin(q - th_r) / (b sin(th_r - th_c))
//   x U_c:  a sin(q - th_c) - c w_r sin(th_r - th_c) = 0
//           => w_r = K_rocker  = a sin(q - th_c) / (c sin(th_r - th_c))
//   (Paul's k2 = a3 sin(th3 - th1) / (a2 sin(th1 - th2)): with th1 = th_r + pi both sines
//   change sign, giving the same w_c; likewise k1.)
// Acceleration (q' = 1, q'' = 0):  i (b U_c al_c - c U_r al_r) - W = 0,
//   W = a U_q + b U_c w_c^2 - c U_r w_r^2   (the centripetal terms).
//   So b U_c al_c - c U_r al_r = -i W, and Im(-i W conj U) = -Re(W conj U):
//   x U_r:  b al_c sin(th_c - th_r) = -Re(W conj U_r)
//           => L_coupler = [a cos(q - th_r) + b w_c^2 cos(th_c - th_r) - c w_r^2]
//                          / (b sin(th_r - th_c))
//   x U_c:  -c al_r sin(th_r - th_c) = -Re(W conj U_c)
//           => L_rocker  = [a cos(q - th_c) + b w_c^2 - c w_r^2 cos(th_r - th_c)]
//                          / (c sin(th_r - th_c))
// ---- Coupler point (1.1.1-2..4) -------------------------------------------------------
// Paul's partial loop runs from the fixed pivot A at the origin through the link pivoted
// there to the coupler's B, then to P at (xi, eta) in the coupler frame. In our model that
// link is the crank (a, angle q, q' = 1, q'' = 0):
//   x_P = a C_q + xi C_c - eta S_c,   y_P = a S_q + xi S_c + eta C_c
//   x_P' = -a S_q - (xi S_c + eta C_c) w_c,       y_P' = a C_q + (xi C_c - eta S_c) w_c
//   x_P'' = -a C_q - (xi S_c + eta C_c) al_c - (xi C_c - eta S_c) w_c^2
//   y_P'' = -a S_q + (xi C_c - eta S_c) al_c - (xi S_c + eta C_c) w_c^2
// with w_c, al_c from Paul's formulas above (not from generated code).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "fourbar.h"
#include "fourbar_crossed.h"
#include "kinematics_test_util.h"

namespace {

using mechtest::kPi;
using mechtest::kTwoPi;
using mechtest::WrapAngle;

// 720 configurations over a full crank turn (0.5 deg apart), for each assembly mode.
constexpr int kNumSamples = 720;

// Tolerances. Every oracle here is a closed form evaluated in double precision from the
// same data; the quantities are O(1) (over the turn |K| < 0.4, |L| < 0.52 for these link
// lengths, points within 6 of the origin), each formula has a few dozen flops and one
// division by sin(th_r - th_c), which stays above 0.81 in magnitude for this Grashof
// crank-rocker (a = 1, b = 3.5, c = 3, d = 4). Rounding is therefore ~1e-15; 1e-12
// (relative to max(1, |value|)) leaves three orders of margin while still catching any
// wrong term, sign or coefficient, which would show up at O(1e-3) or more.
constexpr double kPosTol = 1e-12;    // positions (rad, model units)
constexpr double kCoeffTol = 1e-12;  // K, L, K_P, L_P (relative to max(1, |value|))

// Closed-form positions and Paul's coefficients of one four-bar configuration.
struct PaulFourbar {
  double q, th_c, th_r;                 // our coordinates
  double K_c, K_r;                      // Paul (1.1-8) through the mapping
  double L_c, L_r;                      // Paul (1.1-9, -10) through the mapping
  double xP, yP, xPd, yPd, xPdd, yPdd;  // Paul (1.1.1-2..4)
};

// sigma = +1: C on the left of B->D (open mode of models/fourbar.yaml: C above the axis at
// q = 90 deg); sigma = -1: the crossed mode. Circle intersection of |C - B| = b, |C - D| = c.
PaulFourbar ClosedForm(
    double a, double b, double c, double d, double xi, double eta, double q, double sigma) {
  PaulFourbar r{};
  r.q = q;
  const double Bx = a * std::cos(q), By = a * std::sin(q);
  const double ux = d - Bx, uy = -By;  // B -> D
  const double rho = std::hypot(ux, uy);
  const double along = (b * b - c * c + rho * rho) / (2 * rho);  // from B along BD
  const double h = std::sqrt(b * b - along * along);             // off the line BD
  const double Cx = Bx + (along * ux - sigma * h * uy) / rho;
  const double Cy = By + (along * uy + sigma * h * ux) / rho;
  r.th_c = std::atan2(Cy - By, Cx - Bx);
  r.th_r = std::atan2(Cy, Cx - d);

  // Paul's variables (see the mapping in the file comment).
  const double a1 = c, a2 = b, a3 = a;
  const double th1 = r.th_r + kPi, th2 = r.th_c, th3 = q;
  const double S1 = std::sin(th1), C1 = std::cos(th1), S2 = std::sin(th2), C2 = std::cos(th2);
  const double S3 = std::sin(th3), C3 = std::cos(th3);
  // (1.1-8), with th3' = 1.
  const double k1 = a3 * std::sin(th2 - th3) / (a1 * std::sin(th1 - th2));
  const double k2 = a3 * std::sin(th3 - th1) / (a2 * std::sin(th1 - th2));
  // (1.1-9, -10) with th3' = 1, th3'' = 0: R1 = -a3 S3 th3'' - sum a_i C_i th_i'^2,
  // R2 = -a3 C3 th3'' + sum a_i S_i th_i'^2.
  const double w1 = k1, w2 = k2, w3 = 1.0, al3 = 0.0;
  const double R1 = -a3 * S3 * al3 - (a1 * C1 * w1 * w1 + a2 * C2 * w2 * w2 + a3 * C3 * w3 * w3);
  const double R2 = -a3 * C3 * al3 + (a1 * S1 * w1 * w1 + a2 * S2 * w2 * w2 + a3 * S3 * w3 * w3);
  const double al1 = (R1 * C2 - R2 * S2) / (a1 * std::sin(th1 - th2));
  const double al2 = (-R1 * C1 + R2 * S1) / (a2 * std::sin(th1 - th2));
  r.K_r = k1;
  r.K_c = k2;
  r.L_r = al1;
  r.L_c = al2;
  // (1.1.1-2..4): partial loop A -> B (our crank, q' = 1, q'' = 0) -> P on the coupler.
  const double Sq = S3, Cq = C3, Sc = S2, Cc = C2;
  r.xP = a * Cq + xi * Cc - eta * Sc;
  r.yP = a * Sq + xi * Sc + eta * Cc;
  r.xPd = -a * Sq - (xi * Sc + eta * Cc) * w2;
  r.yPd = a * Cq + (xi * Cc - eta * Sc) * w2;
  r.xPdd = -a * Cq - (xi * Sc + eta * Cc) * al2 - (xi * Cc - eta * Sc) * w2 * w2;
  r.yPdd = -a * Sq + (xi * Cc - eta * Sc) * al2 - (xi * Sc + eta * Cc) * w2 * w2;
  return r;
}

// Our-convention closed forms (derivation in the file comment), as a cross-check of the
// mapping onto Paul's variables: K = (K_c, K_r), L = (L_c, L_r).
void OwnConventionCoefficients(double a,
                               double b,
                               double c,
                               double q,
                               double th_c,
                               double th_r,
                               double* K_c,
                               double* K_r,
                               double* L_c,
                               double* L_r) {
  const double s = std::sin(th_r - th_c);
  *K_c = a * std::sin(q - th_r) / (b * s);
  *K_r = a * std::sin(q - th_c) / (c * s);
  const double wc2 = *K_c * *K_c, wr2 = *K_r * *K_r;
  *L_c = (a * std::cos(q - th_r) + b * wc2 * std::cos(th_c - th_r) - c * wr2) / (b * s);
  *L_r = (a * std::cos(q - th_c) + b * wc2 - c * wr2 * std::cos(th_r - th_c)) / (c * s);
}

double Rel(double value) { return std::max(1.0, std::abs(value)); }

// The two assembly modes of the same linkage: the model and the sign sigma of the circle
// intersection that its description names.
template <class ModelT, int kSigma>
struct Mode {
  using M = ModelT;
  static constexpr double sigma = kSigma;
};
using OpenMode = Mode<mech::fourbar::Model, +1>;
using CrossedMode = Mode<mech::fourbar_crossed::Model, -1>;

template <class T>
class PaulFourbarTest : public ::testing::Test {
 protected:
  using M = typename T::M;
  typename M::template ParamsT<double> p;

  PaulFourbar At(int k) const {
    const double q = kTwoPi * k / kNumSamples;
    return ClosedForm(p.a, p.b, p.c, p.d, p.xi, p.eta, q, T::sigma);
  }
  static Eigen::Matrix<double, 1, 1> Q(const PaulFourbar& r) {
    return Eigen::Matrix<double, 1, 1>(r.q);
  }
  static Eigen::Vector2d PhiOf(const PaulFourbar& r) { return {r.th_c, r.th_r}; }
};
using Modes = ::testing::Types<OpenMode, CrossedMode>;
class ModeNames {
 public:
  template <typename T>
  static std::string GetName(int) {
    return T::M::kName;
  }
};
TYPED_TEST_SUITE(PaulFourbarTest, Modes, ModeNames);

// The model's assembly guess selects the branch the description names (C above the ground
// line at q = 90 deg for the open mode, below for the crossed mode), and Newton from that
// guess lands on the circle-intersection root of that sign.
TYPED_TEST(PaulFourbarTest, AssemblyGuessSelectsTheDescribedMode) {
  using M = typename TestFixture::M;
  bool ok = false;
  const auto c = mechtest::SolvedAssembly<M>(this->p, &ok);
  ASSERT_TRUE(ok);
  const PaulFourbar r = ClosedForm(this->p.a, this->p.b, this->p.c, this->p.d, this->p.xi,
                                   this->p.eta, c.q(0), TypeParam::sigma);
  EXPECT_NEAR(WrapAngle(c.phi(0) - r.th_c), 0.0, kPosTol);
  EXPECT_NEAR(WrapAngle(c.phi(1) - r.th_r), 0.0, kPosTol);
  const double yC = this->p.c * std::sin(c.phi(1));
  EXPECT_GT(TypeParam::sigma * yC, 0.5)
      << "C should be " << (TypeParam::sigma > 0 ? "above" : "below")
      << " the ground line at q = 90 deg";
}

// The closed-form positions close the generated loop equations, and they are the branch
// that continuation from the assembly configuration follows over the whole turn.
TYPED_TEST(PaulFourbarTest, ClosedFormPositionsCloseGeneratedLoopOverFullTurn) {
  using M = typename TestFixture::M;
  const auto sweep = mechtest::SweepConfigs<M>(this->p, kNumSamples);
  ASSERT_EQ(sweep.size(), static_cast<size_t>(kNumSamples));
  for (int k = 0; k < kNumSamples; ++k) {
    const PaulFourbar r = this->At(k);
    Eigen::Vector2d res;
    mech::fourbar::Vec<double, 2> phi = this->PhiOf(r);
    M::Phi(this->p, this->Q(r), phi, &res);
    EXPECT_LT(res.template lpNorm<Eigen::Infinity>(), kPosTol) << "q = " << r.q;
    ASSERT_NEAR(sweep[k].q(0), r.q, 1e-15);
    EXPECT_NEAR(WrapAngle(sweep[k].phi(0) - r.th_c), 0.0, kPosTol) << "q = " << r.q;
    EXPECT_NEAR(WrapAngle(sweep[k].phi(1) - r.th_r), 0.0, kPosTol) << "q = " << r.q;
  }
}

// Our own-convention closed forms agree with Paul's through the mapping (guards the
// mapping itself, so that a sign slip there cannot hide a generator bug or fake one).
TYPED_TEST(PaulFourbarTest, PaulFormulasAgreeWithOwnConventionDerivation) {
  for (int k = 0; k < kNumSamples; ++k) {
    const PaulFourbar r = this->At(k);
    double K_c, K_r, L_c, L_r;
    OwnConventionCoefficients(this->p.a, this->p.b, this->p.c, r.q, r.th_c, r.th_r, &K_c, &K_r,
                              &L_c, &L_r);
    EXPECT_NEAR(K_c, r.K_c, kCoeffTol * Rel(r.K_c)) << "q = " << r.q;
    EXPECT_NEAR(K_r, r.K_r, kCoeffTol * Rel(r.K_r)) << "q = " << r.q;
    EXPECT_NEAR(L_c, r.L_c, kCoeffTol * Rel(r.L_c)) << "q = " << r.q;
    EXPECT_NEAR(L_r, r.L_r, kCoeffTol * Rel(r.L_r)) << "q = " << r.q;
  }
}

// Generated K against eq. (1.1-8).
TYPED_TEST(PaulFourbarTest, VelocityCoefficientsMatchPaulEq1_1_8) {
  using M = typename TestFixture::M;
  for (int k = 0; k < kNumSamples; ++k) {
    const PaulFourbar r = this->At(k);
    typename M::template CoefficientsT<double> out;
    M::Coeffs(this->p, this->Q(r), this->PhiOf(r), &out);
    EXPECT_NEAR(out.K(0, 0), r.K_c, kCoeffTol * Rel(r.K_c)) << "theta_coupler, q = " << r.q;
    EXPECT_NEAR(out.K(1, 0), r.K_r, kCoeffTol * Rel(r.K_r)) << "theta_rocker, q = " << r.q;
  }
}

// Generated L against eqs. (1.1-9, -10) at q' = 1, q'' = 0 (so phi'' = L).
TYPED_TEST(PaulFourbarTest, CentripetalCoefficientsMatchPaulEq1_1_9_10) {
  using M = typename TestFixture::M;
  for (int k = 0; k < kNumSamples; ++k) {
    const PaulFourbar r = this->At(k);
    typename M::template CoefficientsT<double> out;
    M::Coeffs(this->p, this->Q(r), this->PhiOf(r), &out);
    EXPECT_NEAR(out.L(0, 0), r.L_c, kCoeffTol * Rel(r.L_c)) << "theta_coupler, q = " << r.q;
    EXPECT_NEAR(out.L(1, 0), r.L_r, kCoeffTol * Rel(r.L_r)) << "theta_rocker, q = " << r.q;
  }
}

// The one-pass kinematics (Model::Kinematics = EvalKinematics: the closed form's direction
// cosines, K, L and Phi_phi, no angle) against the circle intersection's angles, eqs. (1.1-8)
// and (1.1-9, -10), and Phi_phi of the loop written out by hand,
//   Phi = (a cos q + b cos th_c - c cos th_r - d, a sin q + b sin th_c - c sin th_r),
//   Phi_phi = [-b sin th_c, c sin th_r; b cos th_c, -c cos th_r],
// over the full turn in this mode (the model's default assembly mode).
TYPED_TEST(PaulFourbarTest, OnePassKinematicsMatchPaulOverFullTurn) {
  using M = typename TestFixture::M;
  static_assert(M::kHasKinematics, "the four-bar's closed form gives EvalKinematics");
  for (int k = 0; k < kNumSamples; ++k) {
    const PaulFourbar r = this->At(k);
    typename M::template KinematicsT<double> kin;
    typename M::template TrigT<double> trig;
    const auto report = M::Kinematics(this->p, this->Q(r), M::kDefaultModes, &trig, &kin);
    ASSERT_EQ(static_cast<int>(report.status), 0) << "q = " << r.q;
    EXPECT_NEAR(trig.cos_phi(0), std::cos(r.th_c), kPosTol) << "q = " << r.q;
    EXPECT_NEAR(trig.sin_phi(0), std::sin(r.th_c), kPosTol) << "q = " << r.q;
    EXPECT_NEAR(trig.cos_phi(1), std::cos(r.th_r), kPosTol) << "q = " << r.q;
    EXPECT_NEAR(trig.sin_phi(1), std::sin(r.th_r), kPosTol) << "q = " << r.q;
    EXPECT_NEAR(kin.K(0, 0), r.K_c, kCoeffTol * Rel(r.K_c)) << "theta_coupler, q = " << r.q;
    EXPECT_NEAR(kin.K(1, 0), r.K_r, kCoeffTol * Rel(r.K_r)) << "theta_rocker, q = " << r.q;
    EXPECT_NEAR(kin.L(0, 0), r.L_c, kCoeffTol * Rel(r.L_c)) << "theta_coupler, q = " << r.q;
    EXPECT_NEAR(kin.L(1, 0), r.L_r, kCoeffTol * Rel(r.L_r)) << "theta_rocker, q = " << r.q;
    const double b = this->p.b, c = this->p.c;
    EXPECT_NEAR(kin.Phi_phi(0, 0), -b * std::sin(r.th_c), kCoeffTol * Rel(b)) << "q = " << r.q;
    EXPECT_NEAR(kin.Phi_phi(0, 1), c * std::sin(r.th_r), kCoeffTol * Rel(c)) << "q = " << r.q;
    EXPECT_NEAR(kin.Phi_phi(1, 0), b * std::cos(r.th_c), kCoeffTol * Rel(b)) << "q = " << r.q;
    EXPECT_NEAR(kin.Phi_phi(1, 1), -c * std::cos(r.th_r), kCoeffTol * Rel(c)) << "q = " << r.q;
  }
}

// Where the linkage cannot assemble, the one pass reports what SolveTrig reports: b = 1.5 makes
// the four-bar non-Grashof (a + d = 5 > b + c = 4.5), and C exists only while the circles of
// radius b about B and c about D meet, |b - c| <= |BD| <= b + c with |BD| = |D - B| (the oracle).
// Where they meet, K and L are Paul's again.
TYPED_TEST(PaulFourbarTest, OnePassKinematicsReportsWhereTheLinkageCannotAssemble) {
  using M = typename TestFixture::M;
  typename M::template ParamsT<double> p = this->p;
  p.b = 1.5;
  int refused = 0, solved = 0;
  for (int k = 0; k < kNumSamples; ++k) {
    const double q = kTwoPi * k / kNumSamples;
    const double BD = std::hypot(p.d - p.a * std::cos(q), p.a * std::sin(q));
    const double margin = std::min(BD - std::abs(p.b - p.c), p.b + p.c - BD);
    if (std::abs(margin) < 1e-9) continue;  // at a change point either answer is right
    typename M::template KinematicsT<double> kin;
    typename M::template TrigT<double> trig, trig_solve;
    const Eigen::Matrix<double, 1, 1> qv(q);
    const auto report = M::Kinematics(p, qv, M::kDefaultModes, &trig, &kin);
    const auto solve = M::SolveTrig(p, qv, M::kDefaultModes, &trig_solve);
    EXPECT_EQ(static_cast<int>(report.status), static_cast<int>(solve.status)) << "q = " << q;
    EXPECT_EQ(report.block, solve.block) << "q = " << q;
    if (margin < 0) {
      EXPECT_EQ(report.status, decltype(report.status)::kNotAssemblable) << "q = " << q;
      EXPECT_NEAR(report.measure, solve.measure, 1e-13 * std::max(1.0, std::abs(solve.measure))) << "q = " << q;
      ++refused;
      continue;
    }
    ASSERT_EQ(static_cast<int>(report.status), 0) << "q = " << q;
    ++solved;
    EXPECT_NEAR(report.branch_measure, solve.branch_measure, 1e-13) << "q = " << q;
    const PaulFourbar r = ClosedForm(p.a, p.b, p.c, p.d, p.xi, p.eta, q, TypeParam::sigma);
    EXPECT_NEAR(kin.K(0, 0), r.K_c, kCoeffTol * Rel(r.K_c)) << "theta_coupler, q = " << q;
    EXPECT_NEAR(kin.K(1, 0), r.K_r, kCoeffTol * Rel(r.K_r)) << "theta_rocker, q = " << q;
    EXPECT_NEAR(kin.L(0, 0), r.L_c, 1e-9 * Rel(r.L_c)) << "theta_coupler, q = " << q;
    EXPECT_NEAR(kin.L(1, 0), r.L_r, 1e-9 * Rel(r.L_r)) << "theta_rocker, q = " << q;
  }
  EXPECT_GT(refused, 10);
  EXPECT_GT(solved, 10);
}

// Generated coupler point r_P, K_P, L_P against (1.1.1-2..4).
TYPED_TEST(PaulFourbarTest, CouplerPointMatchesPaulEq1_1_1_2to4) {
  using M = typename TestFixture::M;
  ASSERT_EQ(std::string(M::kPointNames[0]), "coupler.P");
  for (int k = 0; k < kNumSamples; ++k) {
    const PaulFourbar r = this->At(k);
    typename M::template CoefficientsT<double> out;
    M::Coeffs(this->p, this->Q(r), this->PhiOf(r), &out);
    EXPECT_NEAR(out.r_P(0, 0), r.xP, kPosTol * Rel(r.xP)) << "q = " << r.q;
    EXPECT_NEAR(out.r_P(1, 0), r.yP, kPosTol * Rel(r.yP)) << "q = " << r.q;
    EXPECT_NEAR(out.K_P(0, 0), r.xPd, kCoeffTol * Rel(r.xPd)) << "q = " << r.q;
    EXPECT_NEAR(out.K_P(1, 0), r.yPd, kCoeffTol * Rel(r.yPd)) << "q = " << r.q;
    EXPECT_NEAR(out.L_P(0, 0), r.xPdd, kCoeffTol * Rel(r.xPdd)) << "q = " << r.q;
    EXPECT_NEAR(out.L_P(1, 0), r.yPdd, kCoeffTol * Rel(r.yPdd)) << "q = " << r.q;
  }
}

// The generated position solver (SolvePositions, a closed-form RRR dyad) returns the
// circle-intersection root of the model's mode with its default modes, and the other
// mode's root with the modes negated.
TYPED_TEST(PaulFourbarTest, GeneratedSolvePositionsMatchesCircleIntersection) {
  using M = typename TestFixture::M;
  std::array<int, M::kNumBlocks> other_modes = M::kDefaultModes;
  for (int& m : other_modes) m = -m;
  for (int k = 0; k < kNumSamples; ++k) {
    const PaulFourbar r = this->At(k);
    const PaulFourbar other = ClosedForm(this->p.a, this->p.b, this->p.c, this->p.d, this->p.xi,
                                         this->p.eta, r.q, -TypeParam::sigma);
    Eigen::Vector2d phi = this->PhiOf(r) + Eigen::Vector2d(0.01, -0.01);  // a predictor
    const auto report = M::Solve(this->p, this->Q(r), &phi);
    ASSERT_EQ(report.status, decltype(report.status)::kConverged) << "q = " << r.q;
    EXPECT_NEAR(WrapAngle(phi(0) - r.th_c), 0.0, kPosTol) << "q = " << r.q;
    EXPECT_NEAR(WrapAngle(phi(1) - r.th_r), 0.0, kPosTol) << "q = " << r.q;
    Eigen::Vector2d phi_other = this->PhiOf(other);
    ASSERT_EQ(M::Solve(this->p, this->Q(r), &phi_other, other_modes).status,
              decltype(report.status)::kConverged);
    EXPECT_NEAR(WrapAngle(phi_other(0) - other.th_c), 0.0, kPosTol) << "q = " << r.q;
    EXPECT_NEAR(WrapAngle(phi_other(1) - other.th_r), 0.0, kPosTol) << "q = " << r.q;
  }
}

// det Phi_phi = b c sin(th_c - th_r) (from the Phi_phi of our loop equations: rows
// (-b S_c, c S_r), (b C_c, -c C_r)); its sign is the assembly mode (Paul's sin(th1 - th2)
// in the denominators of (1.1-8) is -sin(th_r - th_c)), constant over the turn.
TYPED_TEST(PaulFourbarTest, DetPhiPhiIsPaulsDenominatorWithTheModesSign) {
  using M = typename TestFixture::M;
  for (int k = 0; k < kNumSamples; ++k) {
    const PaulFourbar r = this->At(k);
    double det = NAN;
    M::DetPhiPhi(this->p, this->Q(r), this->PhiOf(r), &det);
    const double ref = this->p.b * this->p.c * std::sin(r.th_c - r.th_r);
    EXPECT_NEAR(det, ref, kCoeffTol * Rel(ref)) << "q = " << r.q;
    EXPECT_GT(-TypeParam::sigma * det, 0.0) << "q = " << r.q;
  }
}

// The oracle is not vacuous: with a deliberately wrong phi (the other assembly mode) the
// generated coefficients differ from this mode's Paul values by far more than kCoeffTol.
TYPED_TEST(PaulFourbarTest, OracleDistinguishesTheOtherAssemblyMode) {
  using M = typename TestFixture::M;
  double max_diff = 0;
  for (int k = 0; k < kNumSamples; k += 10) {
    const PaulFourbar r = this->At(k);
    const PaulFourbar other = ClosedForm(this->p.a, this->p.b, this->p.c, this->p.d, this->p.xi,
                                         this->p.eta, r.q, -TypeParam::sigma);
    typename M::template CoefficientsT<double> out;
    M::Coeffs(this->p, this->Q(r), this->PhiOf(other), &out);
    max_diff = std::max(max_diff, std::abs(out.K(0, 0) - r.K_c) + std::abs(out.K(1, 0) - r.K_r));
  }
  EXPECT_GT(max_diff, 1e-2);
}

}  // namespace
