// The runtime driving every model: the hand-written four-bar always, and each generated
// model whose target exists in the build (MECHGEN_HAVE_<name>, set by CMakeLists.txt).
//
// Typed tests check what holds for any model over its default range (kQMin..kQMax, 720
// steps): every row converges with ||Phi||_inf <= 1e-10 (Options::tolerance); rigid links
// keep the distances between their scene points to 1e-9 (position accuracy ~ tolerance);
// the branch (sign det Phi_phi) never changes and each step is predicted by the
// second-order Taylor polynomial to 1e-4 (O(dq^3) = 1e-6 |phi'''|, a branch jump is O(1));
// generated Phi_phi and Phi_q equal Jet autodiff of the generated Phi (1e-12: the same
// arithmetic up to rounding); K and L equal central differences of solved positions.
// Model-specific tests compare with closed forms written here.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include "handwritten_fourbar.h"
#include "mechgen/position/motion.h"
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/position/solver.h"
#include "mechgen/sweep/sweep.h"
#include "test_util.h"

#ifdef MECHGEN_HAVE_fourbar
#include "fourbar.h"
#endif
#ifdef MECHGEN_HAVE_fourbar_crossed
#include "fourbar_crossed.h"
#endif
#ifdef MECHGEN_HAVE_slider_crank
#include "slider_crank.h"
#endif
#ifdef MECHGEN_HAVE_inverted_slider_crank
#include "inverted_slider_crank.h"
#endif
#ifdef MECHGEN_HAVE_fivebar
#include "fivebar.h"
#endif

namespace mechgen::position {
namespace {

constexpr double kPi = 3.14159265358979323846;
using Vec1 = Eigen::Matrix<double, 1, 1>;
using Vec2 = Eigen::Vector2d;
Vec1 Q(double q) { return Vec1::Constant(q); }
double AngleDistance(double a, double b) { return std::abs(std::remainder(a - b, 2 * kPi)); }

template <class M>
class ModelTest : public ::testing::Test {};

using Models = ::testing::Types<
#ifdef MECHGEN_HAVE_fourbar
    mech::fourbar::Model,
#endif
#ifdef MECHGEN_HAVE_fourbar_crossed
    mech::fourbar_crossed::Model,
#endif
#ifdef MECHGEN_HAVE_slider_crank
    mech::slider_crank::Model,
#endif
#ifdef MECHGEN_HAVE_inverted_slider_crank
    mech::inverted_slider_crank::Model,
#endif
#ifdef MECHGEN_HAVE_fivebar
    mech::fivebar::Model,
#endif
    mech::handwritten_fourbar::Model>;

class ModelNames {
 public:
  template <class M>
  static std::string GetName(int) {
    return M::kName;
  }
};
TYPED_TEST_SUITE(ModelTest, Models, ModelNames);

TYPED_TEST(ModelTest, FullRangeSweepClosesLoopsKeepsLinksAndBranch) {
  using M = TypeParam;
  CeresPositionSolver<M> solver;
  Summary summary;
  ASSERT_EQ(solver.AssembleDefault(&summary), Status::kConverged) << FormatSummary(summary);
  std::vector<SweepRecord<M>> records;
  using VecQ = typename ModelTypes<M>::VecQ;
  const int failures = Sweep(&solver, testing::QMin<M>(), testing::QMax<M>(), 720,
                             VecQ::Constant(1.0), VecQ::Zero(), &records);
  ASSERT_EQ(failures, 0);
  for (const auto& r : records) {
    ASSERT_EQ(r.summary.status, Status::kConverged) << FormatSummary(r.summary);
    EXPECT_LE(testing::ResidualNorm<M>(solver.params(), r.state.q, r.state.phi), 1e-10);
    EXPECT_EQ(r.state.branch, summary.branch);
    EXPECT_TRUE(r.state.K.allFinite() && r.state.L.allFinite());
  }
  if constexpr (M::kNumScenePoints > 0) {
    EXPECT_LT(testing::MaxLinkLengthChange<M>(solver.params(), records), 1e-9);
  }
  EXPECT_LT(testing::MaxTaylorDefect(records), 1e-4);
}

TYPED_TEST(ModelTest, JacobiansMatchJetAutodiff) {
  using M = TypeParam;
  constexpr int kN = M::kNq + M::kNphi;
  using Jet = ceres::Jet<double, kN>;
  CeresPositionSolver<M> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  const auto& q = solver.state().q;
  const auto& phi = solver.state().phi;
  Eigen::Matrix<Jet, M::kNq, 1> q_jet;
  Eigen::Matrix<Jet, M::kNphi, 1> phi_jet;
  for (int j = 0; j < M::kNq; ++j) q_jet(j) = Jet(q(j), j);
  for (int i = 0; i < M::kNphi; ++i) phi_jet(i) = Jet(phi(i), M::kNq + i);
  Eigen::Matrix<Jet, M::kNc, 1> Phi_jet;
  M::template Phi<Jet>(solver.params().template Cast<Jet>(), q_jet, phi_jet, &Phi_jet, nullptr,
                       nullptr);
  typename ModelTypes<M>::MatCPhi Phi_phi;
  typename ModelTypes<M>::MatCQ Phi_q;
  M::template Phi<double>(solver.params(), q, phi, nullptr, &Phi_phi, &Phi_q);
  for (int r = 0; r < M::kNc; ++r) {
    for (int j = 0; j < M::kNq; ++j) EXPECT_NEAR(Phi_q(r, j), Phi_jet(r).v(j), 1e-12);
    for (int i = 0; i < M::kNphi; ++i)
      EXPECT_NEAR(Phi_phi(r, i), Phi_jet(r).v(M::kNq + i), 1e-12);
  }
}

TYPED_TEST(ModelTest, CoefficientsMatchFiniteDifferencesOfSolvedPositions) {
  // h = 1e-4; positions are exact to ~1e-15 in practice (Newton's last step is quadratic)
  // but only guaranteed to 1e-10, giving 1e-10 / h = 1e-6 plus truncation h^2 |phi'''| / 6.
  using M = TypeParam;
  using VecQ = typename ModelTypes<M>::VecQ;
  const double h = 1e-4;
  CeresPositionSolver<M> solver, probe;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  ASSERT_EQ(probe.AssembleDefault(nullptr), Status::kConverged);
  const VecQ q_min = testing::QMin<M>(), q_max = testing::QMax<M>();
  for (int k = 0; k < 8; ++k) {
    const VecQ q = q_min + (q_max - q_min) * ((k + 0.5) / 8);
    ASSERT_EQ(solver.MoveTo(q, nullptr), Status::kConverged);
    const State<M> s = solver.state();
    for (int j = 0; j < M::kNq; ++j) {
      const VecQ dq = VecQ::Unit(j) * h;
      ASSERT_EQ(probe.MoveTo(q + dq, nullptr), Status::kConverged);
      const State<M> plus = probe.state();
      ASSERT_EQ(probe.MoveTo(q - dq, nullptr), Status::kConverged);
      const State<M> minus = probe.state();
      const double scale = 1 + s.K.cwiseAbs().maxCoeff() + s.L.cwiseAbs().maxCoeff();
      EXPECT_LT((s.K.col(j) - (plus.phi - minus.phi) / (2 * h)).cwiseAbs().maxCoeff(),
                1e-5 * scale);
      for (int i = 0; i < M::kNq; ++i) {
        // L(:, i + kNq j) = dK(:, i)/dq_j.
        EXPECT_LT((s.L.col(i + M::kNq * j) - (plus.K.col(i) - minus.K.col(i)) / (2 * h))
                      .cwiseAbs()
                      .maxCoeff(),
                  1e-5 * scale);
      }
      if constexpr (ModelFeatures<M>::kHasPointVelocities) {
        for (int m = 0; m < M::kNumPoints; ++m)
          for (int a = 0; a < 2; ++a)
            EXPECT_NEAR(s.K_P(2 * m + a, j), (plus.r_P(a, m) - minus.r_P(a, m)) / (2 * h),
                        1e-5 * scale);
      }
    }
  }
}

TYPED_TEST(ModelTest, NaNInputIsRejectedAndNextCallWorks) {
  using M = TypeParam;
  using VecQ = typename ModelTypes<M>::VecQ;
  CeresPositionSolver<M> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  const auto phi = solver.state().phi;
  Summary summary;
  EXPECT_EQ(solver.MoveTo(VecQ::Constant(NAN), &summary), Status::kInvalidInput);
  EXPECT_EQ(solver.state().phi, phi);
  EXPECT_EQ(solver.MoveTo(testing::QMin<M>(), &summary), Status::kConverged);
}

TYPED_TEST(ModelTest, PositionsOnlyModelFormsTheGeneratedKAndL) {
  // Over the model's range, K and L the solver forms for PositionsOnly<M> (Phi_q and the
  // second derivatives of Phi along the motion from Model::Coeffs in Dual and HyperDual
  // numbers, seeded with Solve's sin and cos) equal the generated symbolic K and L of M to
  // rounding, and the positions agree.
  using M = TypeParam;
  if constexpr (!ModelFeatures<M>::kHasTrig) {
    GTEST_SKIP() << "no Model::TrigT";
  } else {
    using P = testing::PositionsOnly<M>;
    static_assert(!ModelFeatures<P>::kHasK && !ModelFeatures<P>::kHasL &&
                  ModelFeatures<P>::kHasTrig && ModelFeatures<P>::kCoeffsHavePhi);
    using VecQ = typename ModelTypes<M>::VecQ;
    CeresPositionSolver<M> exact;
    CeresPositionSolver<P> formed;
    ASSERT_EQ(exact.AssembleDefault(nullptr), Status::kConverged);
    ASSERT_EQ(formed.AssembleDefault(nullptr), Status::kConverged);
    P::trig_calls = 0;
    const VecQ q_min = testing::QMin<M>(), q_max = testing::QMax<M>();
    double worst_K = 0, worst_L = 0;
    constexpr int kSteps = 720;
    for (int k = 0; k <= kSteps; ++k) {
      const VecQ q = q_min + (q_max - q_min) * (double(k) / kSteps);
      Summary exact_summary, formed_summary;
      ASSERT_EQ(exact.MoveTo(q, &exact_summary), Status::kConverged) << q.transpose();
      ASSERT_EQ(formed.MoveTo(q, &formed_summary), Status::kConverged) << q.transpose();
      // The same path: no step of PositionsOnly<M> refused (its checks on the formed K and L
      // pass where M's pass on the generated ones) or finished by Newton.
      EXPECT_EQ(formed_summary.rejected_substeps, exact_summary.rejected_substeps)
          << q.transpose();
      EXPECT_EQ(formed_summary.iterations, exact_summary.iterations) << q.transpose();
      const State<M>& e = exact.state();
      const State<P>& f = formed.state();
      ASSERT_LE((f.phi - e.phi).cwiseAbs().maxCoeff(), 1e-13) << q.transpose();
      const double K_error =
          (f.K - e.K).cwiseAbs().maxCoeff() / (1 + e.K.cwiseAbs().maxCoeff());
      const double L_error =
          (f.L - e.L).cwiseAbs().maxCoeff() / (1 + e.L.cwiseAbs().maxCoeff());
      worst_K = std::max(worst_K, K_error);
      worst_L = std::max(worst_L, L_error);
      EXPECT_LE(K_error, 1e-13) << q.transpose();
      EXPECT_LE(L_error, 1e-13) << q.transpose();
    }
    EXPECT_GE(P::trig_calls, 2 * kSteps);  // Dual and HyperDual at (nearly) every step
    EXPECT_GT(worst_L, 0.0);  // two computations, not one copied
    std::printf("%s: worst relative K %.2e, L %.2e\n", M::kName, worst_K, worst_L);
  }
}

#ifdef MECHGEN_HAVE_fourbar
TEST(GeneratedFourBar, EqualsHandwrittenClosedForm) {
  // The generated model against the hand-written oracle: positions from the circle
  // intersection (1e-9: solver tolerance), and K, L, r_P, K_P, L_P evaluated at the same
  // phi (1e-12: the same formulas up to rounding).
  using M = mech::fourbar::Model;
  using H = mech::handwritten_fourbar::Model;
  CeresPositionSolver<M> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  const H::ParamsT<double> hp;
  for (int k = 0; k <= 720; ++k) {
    const double q = k * kPi / 360;
    ASSERT_EQ(solver.MoveTo(Q(q), nullptr), Status::kConverged);
    const auto& s = solver.state();
    Vec2 exact;
    ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(hp, q, +1, &exact));
    EXPECT_LT(AngleDistance(s.phi(0), exact(0)), 1e-9) << q;
    EXPECT_LT(AngleDistance(s.phi(1), exact(1)), 1e-9) << q;
    H::CoefficientsT<double> c;
    H::Coeffs<double>(hp, Q(q), s.phi, &c);
    EXPECT_LT((s.K - c.K).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((s.L - c.L).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((s.r_P - c.r_P).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((s.K_P - c.K_P).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((s.L_P - c.L_P).cwiseAbs().maxCoeff(), 1e-12);
  }
}
#endif

#ifdef MECHGEN_HAVE_fourbar
// The generated four-bar with its evaluations counted.
struct CountingFourBar : mech::fourbar::Model {
  static inline long phi_calls = 0;
  static inline long coeffs_calls = 0;
  static inline long coeffs_calls_with_trig = 0;
  template <typename Scalar>
  static void Phi(const ParamsT<Scalar>& p, const mech::fourbar::Vec<Scalar, kNq>& q,
                  const mech::fourbar::Vec<Scalar, kNphi>& phi,
                  mech::fourbar::Vec<Scalar, kNc>* Phi_out,
                  mech::fourbar::Mat<Scalar, kNc, kNphi>* Phi_phi = nullptr,
                  mech::fourbar::Mat<Scalar, kNc, kNq>* Phi_q = nullptr) {
    ++phi_calls;
    mech::fourbar::Model::Phi<Scalar>(p, q, phi, Phi_out, Phi_phi, Phi_q);
  }
  template <typename Scalar>
  static void Coeffs(const ParamsT<Scalar>& p, const mech::fourbar::Vec<Scalar, kNq>& q,
                     const mech::fourbar::Vec<Scalar, kNphi>& phi,
                     CoefficientsT<Scalar>* out, const TrigT<Scalar>* trig = nullptr) {
    ++coeffs_calls;
    coeffs_calls_with_trig += trig != nullptr;
    mech::fourbar::Model::Coeffs<Scalar>(p, q, phi, out, trig);
  }
};

TEST(GeneratedFourBar, ContinuationStepEvaluatesTheModelOnce) {
  // A continuation step of a sweep with small steps: M::Solve, then one Model::Coeffs that
  // gives the residual and Phi_phi for the checks with K, L and the points, from the sin
  // and cos that M::Solve handed over; no Model::Phi.
  using M = CountingFourBar;
  static_assert(ModelFeatures<M>::kCoeffsHavePhi && ModelFeatures<M>::kHasSolve &&
                ModelFeatures<M>::kHasTrig);
  CeresPositionSolver<M> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  ASSERT_EQ(solver.MoveTo(Q(0), nullptr), Status::kConverged);
  M::phi_calls = M::coeffs_calls = M::coeffs_calls_with_trig = 0;
  Summary summary;
  for (int k = 1; k <= 720; ++k) {
    ASSERT_EQ(solver.MoveTo(Q(k * kPi / 360), &summary), Status::kConverged);
    EXPECT_EQ(summary.substeps, 1);
    EXPECT_EQ(summary.rejected_substeps, 0);
  }
  EXPECT_EQ(M::coeffs_calls, 720);
  EXPECT_EQ(M::coeffs_calls_with_trig, 720);
  EXPECT_EQ(M::phi_calls, 0);
}

TEST(GeneratedFourBar, ReportedDistanceToSingularityMatchesJacobiSvdEveryStep) {
  // MoveTo() computes the distance to singularity of a kNphi <= 2 step last, after the
  // checks (PositionSolver::Deferred); what it reports must still be that of the new
  // configuration. Oracle: Eigen's JacobiSVD and FullPivLU of Model::Phi's Phi_phi at the
  // reported (q, phi), every 0.5 deg step of a turn and on sub-divided 40 deg steps.
  using M = mech::fourbar::Model;
  CeresPositionSolver<M> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  const auto check = [](const CeresPositionSolver<M>& at, const Summary& summary, double q) {
    const State<M>& s = at.state();
    Eigen::Matrix2d Phi_phi;
    M::Phi<double>(at.params(), s.q, s.phi, nullptr, &Phi_phi, nullptr);
    const Eigen::JacobiSVD<Eigen::Matrix2d> svd(Phi_phi, Eigen::ComputeFullV);
    const double smax = svd.singularValues()(0), smin = svd.singularValues()(1);
    EXPECT_TRUE(s.sigma_exact) << q;
    EXPECT_NEAR(s.sigma_max, smax, 1e-13 * smax) << q;
    EXPECT_NEAR(s.sigma_min, smin, 1e-13 * smax) << q;
    EXPECT_EQ(summary.sigma_min, s.sigma_min) << q;  // reported after it was computed
    // Right singular vectors up to sign, fixed so that the largest-magnitude entry is positive.
    for (int k = 0; k < 2; ++k) {
      Eigen::Vector2d v = svd.matrixV().col(1 - k);
      if (v.cwiseAbs()(1) > v.cwiseAbs()(0) ? v(1) < 0 : v(0) < 0) v = -v;
      const Eigen::Vector2d& got = k == 0 ? s.singular_direction : s.largest_direction;
      EXPECT_LT((got - v).norm(), 1e-12 * smax / (smax - smin)) << q << " vector " << k;
    }
    const Eigen::FullPivLU<Eigen::Matrix2d> lu(Phi_phi);
    const double norm1 = Phi_phi.cwiseAbs().colwise().sum().maxCoeff();
    const double inverse_norm1 = lu.inverse().cwiseAbs().colwise().sum().maxCoeff();
    EXPECT_NEAR(s.inverse_norm, inverse_norm1, 1e-12 * inverse_norm1) << q;
    EXPECT_NEAR(s.condition, norm1 * inverse_norm1, 1e-12 * norm1 * inverse_norm1) << q;
    EXPECT_EQ(s.branch, lu.determinant() > 0 ? 1 : -1) << q;
    EXPECT_GT(s.phi_error, 0) << q;
    EXPECT_EQ(summary.phi_error, s.phi_error) << q;
  };
  Summary summary;
  for (int k = 0; k <= 720; ++k) {
    const double q = k * kPi / 360;
    ASSERT_EQ(solver.MoveTo(Q(q), &summary), Status::kConverged) << q;
    check(solver, summary, q);
  }
  Options options;
  options.max_predicted_angle = 0.2;  // 40 deg steps are split (Subdivide())
  CeresPositionSolver<M> coarse(options);
  ASSERT_EQ(coarse.AssembleDefault(nullptr), Status::kConverged);
  int split = 0;
  for (int k = 0; k <= 18; ++k) {
    const double q = k * 40 * kPi / 180;
    ASSERT_EQ(coarse.MoveTo(Q(q), &summary), Status::kConverged) << q;
    split += summary.substeps > 1;
    check(coarse, summary, q);
  }
  EXPECT_GT(split, 0);
}
#endif

#ifdef MECHGEN_HAVE_fourbar_crossed
TEST(GeneratedFourBarCrossed, StaysCrossed) {
  using M = mech::fourbar_crossed::Model;
  CeresPositionSolver<M> solver;
  Summary summary;
  ASSERT_EQ(solver.AssembleDefault(&summary), Status::kConverged);
  EXPECT_EQ(summary.branch, +1);  // det Phi_phi = b c sin(th2 - th3) > 0: crossed
  const mech::handwritten_fourbar::Params<double> hp;  // same lengths
  for (int k = 0; k <= 1440; ++k) {  // two turns, 0.5 deg steps
    const double q = k * kPi / 360;
    ASSERT_EQ(solver.MoveTo(Q(q), nullptr), Status::kConverged);
    Vec2 crossed;
    ASSERT_TRUE(mech::handwritten_fourbar::ClosedFormPosition(hp, q, -1, &crossed));
    EXPECT_LT(AngleDistance(solver.state().phi(0), crossed(0)), 1e-9) << q;
    EXPECT_LT(AngleDistance(solver.state().phi(1), crossed(1)), 1e-9) << q;
    EXPECT_EQ(solver.state().branch, +1);
  }
}
#endif

#ifdef MECHGEN_HAVE_slider_crank
// Offset slider-crank, crank a = 1, rod b = 3.2, slider pin C on y = e = 0.4, slider to the
// right of B. With u = e - a sin(th), w = sqrt(b^2 - u^2) (w = b cos(rod)):
//   s = a cos(th) + w,            rod = atan2(u, w)
//   w' = a u cos(th) / w,         s' = -a sin(th) + w'
//   s'' = -a cos(th) + a [(-a cos^2(th) - u sin(th)) w - u cos(th) w'] / w^2
//   rod' = -a cos(th) / w,        rod'' = (a sin(th) w + a cos(th) w') / w^2
struct SliderCrankClosedForm {
  double s, rod, ds, drod, dds, ddrod;
  explicit SliderCrankClosedForm(double th, double a = 1.0, double b = 3.2, double e = 0.4) {
    const double S = std::sin(th), C = std::cos(th);
    const double u = e - a * S, w = std::sqrt(b * b - u * u);
    const double dw = a * u * C / w;
    s = a * C + w;
    rod = std::atan2(u, w);
    ds = -a * S + dw;
    dds = -a * C + a * ((-a * C * C - u * S) * w - u * C * dw) / (w * w);
    drod = -a * C / w;
    ddrod = (a * S * w + a * C * dw) / (w * w);
  }
};

TEST(GeneratedSliderCrank, PositionVelocityAccelerationMatchClosedForm) {
  using M = mech::slider_crank::Model;
  ASSERT_STREQ(M::kPhiNames[0], "theta_rod");
  ASSERT_STREQ(M::kPhiNames[1], "s_slide");
  CeresPositionSolver<M> solver;
  ASSERT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);
  EXPECT_DOUBLE_EQ(solver.params().a, 1.0);
  EXPECT_DOUBLE_EQ(solver.params().b, 3.2);
  EXPECT_DOUBLE_EQ(solver.params().e, 0.4);
  const double w = 2.0, alpha = 0.5;  // crank speed and acceleration
  for (int k = 0; k <= 720; ++k) {
    const double th = k * kPi / 360;
    ASSERT_EQ(solver.MoveTo(Q(th), nullptr), Status::kConverged);
    const SliderCrankClosedForm x(th);
    const auto& s = solver.state();
    // Positions to the solver's accuracy; derivatives are formulas at those positions,
    // so they agree to ~1e-9 as well.
    EXPECT_LT(AngleDistance(s.phi(0), x.rod), 1e-9) << th;
    EXPECT_NEAR(s.phi(1), x.s, 1e-9) << th;
    Motion<M> m;
    ComputeMotion(s, Q(w), Q(alpha), &m);
    EXPECT_NEAR(m.phid(0), x.drod * w, 1e-8);
    EXPECT_NEAR(m.phid(1), x.ds * w, 1e-8);
    EXPECT_NEAR(m.phidd(0), x.drod * alpha + x.ddrod * w * w, 1e-8);
    EXPECT_NEAR(m.phidd(1), x.ds * alpha + x.dds * w * w, 1e-8);
    // The slider pin C moves along y = e: its velocity is (s_dot, 0).
    EXPECT_NEAR(s.r_P(0, 0), x.s, 1e-9);
    EXPECT_NEAR(s.r_P(1, 0), 0.4, 1e-9);
    EXPECT_NEAR(m.v_P(0, 0), x.ds * w, 1e-8);
    EXPECT_NEAR(m.v_P(1, 0), 0.0, 1e-8);
    EXPECT_NEAR(m.a_P(0, 0), x.ds * alpha + x.dds * w * w, 1e-8);
  }
}
#endif

#ifdef MECHGEN_HAVE_inverted_slider_crank
// Paul (1.2-3, -4): phi = atan2(a sin th, d - a cos th), r = |DB|; the model's
// theta_rocker = pi - phi and s_slot = r. (1.2-8, -9): r_dot = a w sin(th + phi),
// r phi_dot = a w cos(th + phi), and theta_rocker_dot = -phi_dot.
TEST(GeneratedInvertedSliderCrank, MatchesPaulClosedForm) {
  using M = mech::inverted_slider_crank::Model;
  for (double d : {2.5, 0.6}) {  // oscillating block (d > a), Whitworth quick return (d < a)
    M::ParamsT<double> p;
    p.d = d;
    CeresPositionSolver<M> solver(Options(), p);
    // Assemble at 90 deg from Paul's closed form, perturbed.
    const double a = p.a, th0 = kPi / 2;
    const double phi0 = std::atan2(a * std::sin(th0), d - a * std::cos(th0));
    ASSERT_EQ(solver.Assemble(Q(th0), Vec2(kPi - phi0 + 0.1, std::hypot(a, d) - 0.1), 0, nullptr),
              Status::kConverged);
    for (int k = 0; k <= 720; ++k) {
      const double th = th0 + k * kPi / 360;
      ASSERT_EQ(solver.MoveTo(Q(th), nullptr), Status::kConverged) << d << " " << th;
      const double phi = std::atan2(a * std::sin(th), d - a * std::cos(th));
      const double r = std::sqrt(a * a + d * d - 2 * a * d * std::cos(th));
      const auto& s = solver.state();
      EXPECT_LT(AngleDistance(s.phi(0), kPi - phi), 1e-9) << th;
      EXPECT_NEAR(s.phi(1), r, 1e-9) << th;
      EXPECT_NEAR(s.K(1, 0), a * std::sin(th + phi), 1e-9) << th;
      EXPECT_NEAR(-s.K(0, 0) * r, a * std::cos(th + phi), 1e-9) << th;
    }
  }
}

TEST(GeneratedInvertedSliderCrank, DEqualsAPassesThroughSingularityNeverWrong) {
  // d = a: B reaches D at th = 0, where r = 0 and Phi_phi (det = -r) loses rank. Driven
  // through it, the solver must refuse (kSingular or kNotAssemblable), keep its last valid
  // configuration and never report a configuration of the other sign of r as converged.
  using M = mech::inverted_slider_crank::Model;
  M::ParamsT<double> p;
  p.d = p.a;
  CeresPositionSolver<M> solver(Options(), p);
  const double th0 = kPi / 2;
  ASSERT_EQ(solver.Assemble(Q(th0), Vec2(kPi - kPi / 4, std::sqrt(2.0)), 0, nullptr),
            Status::kConverged);
  int refused = 0;
  for (int k = 0; k <= 720; ++k) {
    const double th = th0 + k * kPi / 360;  // passes th = 2 pi
    Summary summary;
    const Status status = solver.MoveTo(Q(th), &summary);
    if (status == Status::kConverged) {
      EXPECT_GT(solver.state().phi(1), 0) << th;  // r keeps its sign: same branch
      EXPECT_LE(testing::ResidualNorm<M>(p, solver.state().q, solver.state().phi), 1e-10);
    } else {
      ++refused;
      EXPECT_TRUE(status == Status::kSingular || status == Status::kNotAssemblable ||
                  status == Status::kDidNotConverge)
          << FormatSummary(summary);
      EXPECT_TRUE(solver.state().valid);
    }
  }
  EXPECT_GT(refused, 0);
}
#endif

}  // namespace
}  // namespace mechgen::position
