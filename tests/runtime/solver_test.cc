// PositionSolver on the hand-written four-bar (closed-form oracle) and on the same four-bar
// driven by its rocker (inputs beyond the toggle positions, order-1 model).
//
// Tolerances: the solver converges to ||Phi||_inf <= Options::tolerance = 1e-10 (lengths ~ 1);
// with cond(Phi_phi) <= ~10 along these sweeps and |Phi_phi| ~ b, c ~ 3, phi is then within
// ~ 1e-10 of the exact solution, so positions are compared at 1e-9. Finite differences are
// bounded by truncation h^2 |f'''| / 6 plus rounding (position error) / h; each check states
// its h.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "handwritten_fourbar.h"
#include "handwritten_rocker_driven.h"
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/position/motion.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/sweep.h"
#include "test_util.h"

namespace mechgen::position {
namespace {

using FourBar = mech::handwritten_fourbar::Model;
using Rocker = mech::handwritten_rocker_driven::Model;
using Vec1 = Eigen::Matrix<double, 1, 1>;
using Vec2 = Eigen::Vector2d;
constexpr double kPi = 3.14159265358979323846;

Vec1 Q(double q) { return Vec1::Constant(q); }

// Angles equal modulo 2 pi.
double AngleDistance(double a, double b) { return std::abs(std::remainder(a - b, 2 * kPi)); }

TEST(CeresAdapter, JacobianIsRowMajor) {
  // Phi_phi = [-b S2, c S3; b C2, -c C3] has four distinct entries at this point, so a
  // transposed layout would fail.
  const FourBar::ParamsT<double> p;
  const Vec1 q = Q(0.3);
  const Vec2 phi(0.4, 1.9);
  PhiCostFunction<FourBar> cost(&p, &q);
  double residuals[2];
  double jacobian[4];
  double* jacobians[1] = {jacobian};
  const double* parameters[1] = {phi.data()};
  ASSERT_TRUE(cost.Evaluate(parameters, residuals, jacobians));
  Eigen::Matrix2d Phi_phi;
  Vec2 Phi;
  FourBar::Phi<double>(p, q, phi, &Phi, &Phi_phi, nullptr);
  for (int r = 0; r < 2; ++r) {
    EXPECT_EQ(residuals[r], Phi(r));
    for (int c = 0; c < 2; ++c) EXPECT_EQ(jacobian[r * 2 + c], Phi_phi(r, c)) << r << "," << c;
  }
  // Also without a Jacobian.
  ASSERT_TRUE(cost.Evaluate(parameters, residuals, nullptr));
}

TEST(HandwrittenFourBar, CoefficientsMatchFiniteDifferencesOfClosedForm) {
  // h = 1e-4 on exact closed forms (rounding ~1e-16 / h = 1e-12): the central difference
  // errs by h^2 |phi'''| / 6 < 1e-8 * |phi'''| with |phi'''| < 10 on this linkage.
  const FourBar::ParamsT<double> p;
  const double h = 1e-4;
  for (double q = 0; q < 2 * kPi; q += 0.37) {
    Vec2 phi, plus, minus;
    ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(p, q, +1, &phi));
    ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(p, q + h, +1, &plus));
    ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(p, q - h, +1, &minus));
    FourBar::CoefficientsT<double> c, c_plus, c_minus;
    FourBar::Coeffs<double>(p, Q(q), phi, &c);
    FourBar::Coeffs<double>(p, Q(q + h), plus, &c_plus);
    FourBar::Coeffs<double>(p, Q(q - h), minus, &c_minus);
    EXPECT_LT((c.K - (plus - minus) / (2 * h)).cwiseAbs().maxCoeff(), 1e-7) << q;
    EXPECT_LT((c.L - (c_plus.K - c_minus.K) / (2 * h)).cwiseAbs().maxCoeff(), 1e-7) << q;
    EXPECT_LT((c.K_P - (c_plus.r_P - c_minus.r_P) / (2 * h)).cwiseAbs().maxCoeff(), 1e-7);
    EXPECT_LT((c.L_P - (c_plus.K_P - c_minus.K_P) / (2 * h)).cwiseAbs().maxCoeff(), 1e-7);
  }
}

TEST(PositionSolver, AssemblesAtModelConfiguration) {
  CeresPositionSolver<FourBar> solver;
  Summary summary;
  ASSERT_EQ(solver.AssembleDefault(&summary), Status::kConverged) << FormatSummary(summary);
  EXPECT_TRUE(summary.used_assembler);
  EXPECT_LE(summary.residual_norm, solver.options().tolerance);
  Vec2 expected;
  ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(solver.params(), kPi / 2, +1,
                                                            &expected));
  EXPECT_LT((solver.state().phi - expected).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(summary.branch, -1);  // open mode: det Phi_phi = b c sin(th2 - th3) < 0
}

TEST(PositionSolver, SweepFollowsClosedFormAndKeepsBranch) {
  for (int branch : {+1, -1}) {  // open, then crossed
    CeresPositionSolver<FourBar> solver;
    Vec2 guess;
    ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(solver.params(), 1.0, branch,
                                                              &guess));
    ASSERT_EQ(solver.Assemble(Q(1.0), guess + Vec2(0.2, -0.2), 0, nullptr), Status::kConverged);
    std::vector<SweepRecord<FourBar>> records;
    // 0.5 deg steps over two full turns starting at 1 rad.
    ASSERT_EQ(Sweep(&solver, Q(1.0), Q(1.0 + 4 * kPi), 1440, Q(1.0), Q(0.0), &records), 0);
    const int start_branch = records.front().state.branch;
    for (const auto& r : records) {
      ASSERT_EQ(r.summary.status, Status::kConverged);
      EXPECT_EQ(r.state.branch, start_branch);
      EXPECT_LE(testing::ResidualNorm<FourBar>(solver.params(), r.state.q, r.state.phi), 1e-10);
      Vec2 exact;
      ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(solver.params(), r.q(0), branch,
                                                                &exact));
      EXPECT_LT(AngleDistance(r.state.phi(0), exact(0)), 1e-9) << r.q(0);
      EXPECT_LT(AngleDistance(r.state.phi(1), exact(1)), 1e-9) << r.q(0);
    }
    // Rigid links keep their lengths to the position accuracy.
    EXPECT_LT(testing::MaxLinkLengthChange<FourBar>(solver.params(), records), 1e-9);
    // One branch: the step is predicted to O(dq^3) = 6.6e-7 |phi'''| / 6 (|phi'''| < 10);
    // a jump to the other mode would be O(1).
    EXPECT_LT(testing::MaxTaylorDefect(records), 1e-5);
  }
}

TEST(PositionSolver, VelocitiesAndAccelerationsMatchFiniteDifferencesInTime) {
  // Crank motion q(t) = q0 + w t + 1/2 alpha t^2. Exact closed-form positions differenced
  // at h = 1e-4 s: velocity error h^2 |x'''| / 6 ~ 1e-8 |x'''|, acceleration error
  // h^2 |x''''| / 12 + 4 eps / h^2 ~ 1e-8 * 10 + 1e-8.
  const double w = 3.0, alpha = -2.0, h = 1e-4;
  CeresPositionSolver<FourBar> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  const FourBar::ParamsT<double>& p = solver.params();
  for (double q0 = 0.1; q0 < 2 * kPi; q0 += 0.5) {
    ASSERT_EQ(solver.MoveTo(Q(q0), nullptr), Status::kConverged);
    Motion<FourBar> motion;
    ComputeMotion(solver.state(), Q(w), Q(alpha), &motion);
    auto at = [&](double t, Vec2* phi, Vec2* r_P) {
      const double q = q0 + w * t + 0.5 * alpha * t * t;
      ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(p, q, +1, phi));
      FourBar::CoefficientsT<double> c;
      FourBar::Coeffs<double>(p, Q(q), *phi, &c);
      *r_P = c.r_P;
    };
    Vec2 phi_m = Vec2::Zero(), phi_0 = phi_m, phi_p = phi_m, r_m = phi_m, r_0 = phi_m,
         r_p = phi_m;
    at(-h, &phi_m, &r_m);
    at(0, &phi_0, &r_0);
    at(h, &phi_p, &r_p);
    EXPECT_LT((motion.phid - (phi_p - phi_m) / (2 * h)).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_LT((motion.phidd - (phi_p - 2 * phi_0 + phi_m) / (h * h)).cwiseAbs().maxCoeff(), 1e-5);
    EXPECT_LT((motion.v_P - (r_p - r_m) / (2 * h)).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_LT((motion.a_P - (r_p - 2 * r_0 + r_m) / (h * h)).cwiseAbs().maxCoeff(), 1e-5);
  }
}

TEST(PositionSolver, PoorGuessesLandOnRequestedBranchOrSayOtherwise) {
  std::mt19937 gen(42);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  const FourBar::ParamsT<double> p;
  int landed = 0, wrong_branch = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const double q = angle(gen);
    const int branch = trial % 2 ? +1 : -1;  // ClosedFormPosition's label
    const int det_sign = -branch;            // sign(det Phi_phi) of that mode
    Vec2 exact;
    ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(p, q, branch, &exact));
    CeresPositionSolver<FourBar> solver;
    Summary summary;
    const Status status = solver.Assemble(Q(q), Vec2(angle(gen), angle(gen)), det_sign, &summary);
    if (status == Status::kConverged) {
      ++landed;
      EXPECT_EQ(solver.state().branch, det_sign);
      EXPECT_LT(AngleDistance(solver.state().phi(0), exact(0)), 1e-9);
      EXPECT_LT(AngleDistance(solver.state().phi(1), exact(1)), 1e-9);
    } else {
      // The only other outcome from a random guess: the other mode, reported, not adopted.
      EXPECT_EQ(status, Status::kWrongBranch) << FormatSummary(summary);
      EXPECT_EQ(summary.branch, -det_sign);
      EXPECT_FALSE(solver.state().valid);
      ++wrong_branch;
    }
  }
  EXPECT_EQ(landed + wrong_branch, 200);
  EXPECT_GT(landed, 50);  // random guesses fall on either side about equally often
}

TEST(PositionSolver, RockerDrivenPastToggleStopsSingularAtLastValidConfiguration) {
  // The rocker of this crank-rocker swings over th3 in [101.42, 141.38] deg (upper mode):
  // cos th3 = (c^2 + d^2 - (b -+ a)^2) / (2 c d). Driving it beyond reaches a dead point.
  const double th_min = std::acos(-0.197916666666667), th_max = std::acos(-0.78125);
  for (double target : {th_max + 0.05, th_min - 0.05, th_max + 1.0, 3.5}) {
    CeresPositionSolver<Rocker> solver;
    ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
    const int branch = solver.state().branch;
    Summary summary;
    EXPECT_EQ(solver.MoveTo(Q(target), &summary), Status::kSingular)
        << target << ": " << FormatSummary(summary);
    // state() is the last valid configuration, next to the toggle on the way to target:
    // within 1e-3 rad of it (bisection to 2^-16 of the step, then rejection once
    // 1/cond < min_rcond), on the same branch, closed, with a small sigma_min.
    const State<Rocker>& s = solver.state();
    EXPECT_TRUE(s.valid);
    const double toggle = target > th_max ? th_max : th_min;
    EXPECT_LT(std::abs(s.q(0) - toggle), 1e-3) << target;
    EXPECT_TRUE(target > th_max ? s.q(0) <= th_max : s.q(0) >= th_min) << s.q(0);
    EXPECT_EQ(s.branch, branch);
    EXPECT_LE(testing::ResidualNorm<Rocker>(solver.params(), s.q, s.phi), 1e-10);
    EXPECT_LT(s.sigma_min, 0.05 * s.sigma_max);
    EXPECT_EQ(summary.sigma_min, s.sigma_min);
  }
  // Assembly beyond the limit is refused.
  CeresPositionSolver<Rocker> solver;
  Summary summary;
  EXPECT_EQ(solver.Assemble(Q(th_max + 0.2), Vec2(-0.5, 1.1), 0, &summary),
            Status::kNotAssemblable)
      << FormatSummary(summary);
  // Right up to the toggle, the solver still follows (sub-stepping as K grows).
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  EXPECT_EQ(solver.MoveTo(Q(th_max - 1e-4), nullptr), Status::kConverged);
  EXPECT_EQ(solver.MoveTo(Q(th_min + 1e-4), nullptr), Status::kConverged);
}

// The hand-written four-bar with its coefficients cut down to K: the solver forms L itself
// (from one evaluation of Phi in dual numbers, position/internal/dual.h).
struct FourBarKOnly : FourBar {
  static constexpr bool kHasL = false;  // its flags say so (core/model_traits.h reads them)
  static constexpr bool kHasPoints = false;
  static constexpr bool kHasPointVelocities = false;
  static constexpr bool kHasPointAccelerations = false;
  template <typename Scalar>
  struct CoefficientsT {
    Eigen::Matrix<Scalar, kNphi, kNq> K;
  };
  template <typename Scalar>
  static void Coeffs(const mech::handwritten_fourbar::Params<Scalar>& p,
                     const Eigen::Matrix<Scalar, kNq, 1>& q,
                     const Eigen::Matrix<Scalar, kNphi, 1>& phi, CoefficientsT<Scalar>* out) {
    mech::handwritten_fourbar::Coefficients<Scalar> c;
    FourBar::Coeffs(p, q, phi, &c);
    out->K = c.K;
  }
};

TEST(PositionSolver, LOfModelWithoutItEqualsPaulsClosedForm) {
  // Over a whole turn of the crank-rocker, the L the solver forms for the model without it
  // agrees with Paul's closed-form L of the hand-written model (EvalCoefficients) to
  // rounding: 1e-13 relative, where central differences (h = cbrt(eps)) were ~1e-11 off.
  static_assert(!ModelFeatures<FourBarKOnly>::kHasL && ModelFeatures<FourBarKOnly>::kHasK);
  CeresPositionSolver<FourBar> exact;
  CeresPositionSolver<FourBarKOnly> formed;
  ASSERT_EQ(exact.AssembleDefault(nullptr), Status::kConverged);
  ASSERT_EQ(formed.AssembleDefault(nullptr), Status::kConverged);
  double worst = 0;
  for (int k = 1; k <= 720; ++k) {
    const double q = M_PI / 2 + k * M_PI / 360;
    ASSERT_EQ(exact.MoveTo(Q(q), nullptr), Status::kConverged) << q;
    ASSERT_EQ(formed.MoveTo(Q(q), nullptr), Status::kConverged) << q;
    ASSERT_LE((formed.state().phi - exact.state().phi).cwiseAbs().maxCoeff(), 1e-14) << q;
    const auto& L = exact.state().L;
    const double error = (formed.state().L - L).cwiseAbs().maxCoeff() /
                         (1 + L.cwiseAbs().maxCoeff());
    worst = std::max(worst, error);
    EXPECT_LE(error, 1e-13) << q;
  }
  EXPECT_GT(worst, 0.0);  // two computations, not one copied
}

// HyperDual<2> (position/internal/dual.h) at (x, y) = (0.3, 0.7), x along t_0 and y along
// t_1: each function of a = x y + x (a_x = y + 1, a_y = x, a_xy = 1, a_xx = a_yy = 0) against
// its first and second derivatives written out here, f(a)_ij = f'(a) a_ij + f''(a) a_i a_j;
// the two-argument ones against their partial derivatives; a composite expression against
// central differences (h = 1e-4: truncation ~ h^2, rounding ~ eps / h^2, both < 1e-7).
TEST(HyperDual, SecondDerivativesMatchClosedForms) {
  using H = internal::HyperDual<2>;
  const double x0 = 0.3, y0 = 0.7;
  H x(x0), y(y0);
  x.d[0] = 1;
  y.d[1] = 1;
  const H a = x * y + x;
  const double av = x0 * y0 + x0, ad[2] = {y0 + 1, x0}, add[2][2] = {{0, 1}, {1, 0}};
  ASSERT_EQ(a.v, av);
  // r's derivatives: value, gradient [2] and Hessian [2][2] (row-major).
  const auto expect = [](const H& r, double v, const double (&g)[2], const double (&hess)[2][2],
                         const char* what) {
    EXPECT_NEAR(r.v, v, 1e-15 * (1 + std::abs(v))) << what;
    for (int i = 0; i < 2; ++i) {
      EXPECT_NEAR(r.d[i], g[i], 1e-14 * (1 + std::abs(g[i]))) << what << " d" << i;
      for (int j = 0; j < 2; ++j) {
        EXPECT_NEAR(r.dd[i][j], hess[i][j], 1e-13 * (1 + std::abs(hess[i][j])))
            << what << " dd" << i << j;
      }
    }
  };
  const auto chain = [&](const H& r, double f, double f1, double f2, const char* what) {
    const double g[2] = {f1 * ad[0], f1 * ad[1]};
    double hess[2][2];
    for (int i = 0; i < 2; ++i) {
      for (int j = 0; j < 2; ++j) hess[i][j] = f1 * add[i][j] + f2 * ad[i] * ad[j];
    }
    expect(r, f, g, hess, what);
  };
  chain(sin(a), std::sin(av), std::cos(av), -std::sin(av), "sin");
  chain(cos(a), std::cos(av), -std::sin(av), -std::cos(av), "cos");
  const double c = std::cos(av);
  chain(tan(a), std::tan(av), 1 / (c * c), 2 * std::sin(av) / (c * c * c), "tan");
  chain(sqrt(a), std::sqrt(av), 0.5 / std::sqrt(av), -0.25 / (av * std::sqrt(av)), "sqrt");
  chain(exp(a), std::exp(av), std::exp(av), std::exp(av), "exp");
  chain(log(a), std::log(av), 1 / av, -1 / (av * av), "log");
  chain(pow(a, 3.5), std::pow(av, 3.5), 3.5 * std::pow(av, 2.5), 8.75 * std::pow(av, 1.5), "pow");
  chain(pow(a, 2), av * av, 2 * av, 2, "pow int");
  const double w = 1 - av * av;
  chain(asin(a), std::asin(av), 1 / std::sqrt(w), av / (w * std::sqrt(w)), "asin");
  chain(acos(a), std::acos(av), -1 / std::sqrt(w), -av / (w * std::sqrt(w)), "acos");
  chain(atan(a), std::atan(av), 1 / (1 + av * av), -2 * av / ((1 + av * av) * (1 + av * av)),
        "atan");
  chain(abs(-a), av, 1, 0, "abs");  // -a < 0: |-a| = a
  chain(2.0 / a, 2 / av, -2 / (av * av), 4 / (av * av * av), "2 / a");
  chain(a * 3.0 - 1.0, 3 * av - 1, 3, 0, "3 a - 1");
  {  // x / y
    const double g[2] = {1 / y0, -x0 / (y0 * y0)};
    const double hess[2][2] = {{0, -1 / (y0 * y0)}, {-1 / (y0 * y0), 2 * x0 / (y0 * y0 * y0)}};
    expect(x / y, x0 / y0, g, hess, "x / y");
  }
  {  // atan2(y, x), r2 = x^2 + y^2
    const double r2 = x0 * x0 + y0 * y0, r4 = r2 * r2;
    const double g[2] = {-y0 / r2, x0 / r2};
    const double hess[2][2] = {{2 * x0 * y0 / r4, (y0 * y0 - x0 * x0) / r4},
                               {(y0 * y0 - x0 * x0) / r4, -2 * x0 * y0 / r4}};
    expect(atan2(y, x), std::atan2(y0, x0), g, hess, "atan2");
  }
  {  // hypot(x, y) = h
    const double h = std::hypot(x0, y0), h3 = h * h * h;
    const double g[2] = {x0 / h, y0 / h};
    const double hess[2][2] = {{y0 * y0 / h3, -x0 * y0 / h3}, {-x0 * y0 / h3, x0 * x0 / h3}};
    expect(hypot(x, y), h, g, hess, "hypot");
  }
  {  // x^y
    const double p = std::pow(x0, y0), l = std::log(x0);
    const double g[2] = {y0 * p / x0, p * l};
    const double mixed = p / x0 * (1 + y0 * l);
    const double hess[2][2] = {{y0 * (y0 - 1) * p / (x0 * x0), mixed}, {mixed, p * l * l}};
    expect(pow(x, y), p, g, hess, "pow(x, y)");
  }
  // A composite: every operator on the way, against central differences.
  const auto g = [](auto u, auto v) {
    using std::atan2;
    using std::cos;
    using std::sqrt;
    return (cos(u) * v - 2.0) / (u + v * v) + 3.0 * sqrt(u) - u / 4.0 - atan2(v, 1.0 + u) * u;
  };
  const H r = g(x, y);
  const double h = 1e-4;
  const auto f = [&](double u, double v) { return g(u, v); };
  EXPECT_NEAR(r.v, f(x0, y0), 1e-15);
  EXPECT_NEAR(r.d[0], (f(x0 + h, y0) - f(x0 - h, y0)) / (2 * h), 1e-7);
  EXPECT_NEAR(r.d[1], (f(x0, y0 + h) - f(x0, y0 - h)) / (2 * h), 1e-7);
  EXPECT_NEAR(r.dd[0][0], (f(x0 + h, y0) - 2 * f(x0, y0) + f(x0 - h, y0)) / (h * h), 1e-6);
  EXPECT_NEAR(r.dd[1][1], (f(x0, y0 + h) - 2 * f(x0, y0) + f(x0, y0 - h)) / (h * h), 1e-6);
  const double mixed = (f(x0 + h, y0 + h) - f(x0 + h, y0 - h) - f(x0 - h, y0 + h) +
                        f(x0 - h, y0 - h)) / (4 * h * h);
  EXPECT_NEAR(r.dd[0][1], mixed, 1e-6);
  EXPECT_NEAR(r.dd[0][1], r.dd[1][0], 1e-15);  // symmetric to rounding
}

TEST(PositionSolver, NumericalCentripetalCoefficientsOfOrderOneModel) {
  // Rocker has K only; the solver forms L (dual numbers, exact to rounding). Compare
  // with differences of K between solved positions at h = 1e-5 (error ~ h^2 |K''| + 1e-10/h).
  CeresPositionSolver<Rocker> solver, probe;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  ASSERT_EQ(probe.AssembleDefault(nullptr), Status::kConverged);
  const double h = 1e-5;
  for (double q = 1.85; q < 2.4; q += 0.1) {
    ASSERT_EQ(solver.MoveTo(Q(q), nullptr), Status::kConverged);
    ASSERT_EQ(probe.MoveTo(Q(q + h), nullptr), Status::kConverged);
    const Vec2 K_plus = probe.state().K;
    ASSERT_EQ(probe.MoveTo(Q(q - h), nullptr), Status::kConverged);
    const Vec2 K_minus = probe.state().K;
    EXPECT_LT((solver.state().L - (K_plus - K_minus) / (2 * h)).cwiseAbs().maxCoeff(), 1e-4)
        << q;
  }
}

TEST(PositionSolver, NonFiniteInputIsRejectedAndNextCallWorks) {
  CeresPositionSolver<FourBar> solver;
  Summary summary;
  EXPECT_EQ(solver.MoveTo(Q(0.1), &summary), Status::kInvalidInput);  // not assembled yet
  EXPECT_EQ(solver.Assemble(Q(NAN), Vec2(0.5, 1.9), 0, &summary), Status::kInvalidInput);
  EXPECT_EQ(solver.Assemble(Q(1.0), Vec2(INFINITY, 1.9), 0, &summary), Status::kInvalidInput);
  ASSERT_EQ(solver.AssembleDefault(&summary), Status::kConverged);
  const Vec2 phi = solver.state().phi;
  EXPECT_EQ(solver.MoveTo(Q(NAN), &summary), Status::kInvalidInput);
  EXPECT_FALSE(summary.IsSolutionUsable());
  EXPECT_EQ(solver.state().phi, phi);
  ASSERT_EQ(solver.MoveTo(Q(0.2), &summary), Status::kConverged);
  EXPECT_TRUE(solver.state().phi.allFinite());
  // Parameters that are not finite.
  FourBar::ParamsT<double> bad;
  bad.b = NAN;
  solver.set_params(bad);
  EXPECT_EQ(solver.AssembleDefault(&summary), Status::kInvalidInput);
}

TEST(PositionSolver, CeresFallbackWhenNewtonCannotConverge) {
  Options options;
  options.max_newton_iterations = 1;  // too few for a 60 deg step
  options.max_bisections = 0;         // and no splitting: Newton fails, Ceres must step in
  CeresPositionSolver<FourBar> solver(options);
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  Summary summary;
  ASSERT_EQ(solver.MoveTo(Q(kPi / 2 + kPi / 3), &summary), Status::kConverged)
      << FormatSummary(summary);
  EXPECT_TRUE(summary.used_assembler);
  Vec2 exact;
  ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(solver.params(), kPi / 2 + kPi / 3,
                                                            +1, &exact));
  EXPECT_LT((solver.state().phi - exact).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(PositionSolver, NeverNaNWithSuccess) {
  // Large random jumps (including beyond a turn) must end converged with finite values, or
  // fail with the configuration unchanged.
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> angle(-10, 10);
  CeresPositionSolver<Rocker> rocker;
  ASSERT_EQ(rocker.AssembleDefault(nullptr), Status::kConverged);
  for (int i = 0; i < 100; ++i) {
    Summary summary;
    const Status status = rocker.MoveTo(Q(angle(gen)), &summary);
    if (status == Status::kConverged) {
      EXPECT_TRUE(rocker.state().phi.allFinite() && rocker.state().K.allFinite() &&
                  rocker.state().L.allFinite());
      EXPECT_LE(summary.residual_norm, rocker.options().tolerance);
    }
    EXPECT_TRUE(rocker.state().valid);
    EXPECT_LE(testing::ResidualNorm<Rocker>(rocker.params(), rocker.state().q,
                                            rocker.state().phi),
              1e-10);
  }
}

TEST(Options, IsValidNamesTheField) {
  Options options;
  std::string error;
  EXPECT_TRUE(options.IsValid(&error));
  options.tolerance = -1;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("Options::tolerance"), std::string::npos) << error;
  options = Options();
  options.max_newton_iterations = 0;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("max_newton_iterations"), std::string::npos) << error;
  // An invalid Options makes every solve return kInvalidInput.
  CeresPositionSolver<FourBar> solver(options);
  EXPECT_EQ(solver.AssembleDefault(nullptr), Status::kInvalidInput);
}

TEST(Status, EveryValueHasAName) {
  for (Status s : {Status::kConverged, Status::kNotAssemblable, Status::kSingular,
                   Status::kDidNotConverge, Status::kInvalidInput, Status::kWrongBranch,
                   Status::kNotRun}) {
    EXPECT_STRNE(ToString(s), "unknown");
    Summary summary;
    summary.status = s;
    EXPECT_EQ(FormatSummary(summary).rfind(ToString(s), 0), 0u);
  }
}

}  // namespace
}  // namespace mechgen::position
