// The generated design sensitivities (EvalDesignDerivatives, issue 27) against three oracles
// independent of them:
//   - Jets: dphi/dp = -Phi_phi^-1 Phi_p with Phi_phi and Phi_p from ceres::Jet derivatives of
//     the generated EvalPhi; then EvalCoefficients instantiated with Jet<double, kNumDesign>
//     at (p seeded, phi carrying that dphi/dp) gives d/dp of K, L, r_P, K_P and L_P: the same
//     generated values code, differentiated by forward-mode automatic differentiation;
//   - central differences with Richardson extrapolation of positions solved by Newton's
//     method and of EvalCoefficients at p +- h, p +- h/2;
//   - hand formulas: the four-bar's dtheta_3/dp and dtheta_4/dp from its loop equation
//     differentiated by hand, and the offset slider-crank's ds/da, ds/db, ds/de from
//     s = a cos(theta) + sqrt(b^2 - (e - a sin(theta))^2).
// The models: the shipped ones with a design section (fourbar, slider_crank, watt_sixbar), two
// test models (design_stephenson: a four-unknown block, solved by an LU and Newton's method;
// design_fivebar: two inputs, L with three input pairs) and four shipped models of other
// structures with `design: {parameters: all}` appended (tests/design/CMakeLists.txt): a cam with
// a roller follower (cam_roller: e, rb, rr, phase; its law's lift h is left out), gears
// (geared_fivebar), a slot (quick_return) and an engine (engine_single).
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <string>

#include "design_cam_roller.h"
#include "design_engine_single.h"
#include "design_fivebar.h"
#include "design_geared_fivebar.h"
#include "design_quick_return.h"
#include "design_test_util.h"
#include "design_stephenson.h"
#include "fourbar.h"
#include "kinematics_test_util.h"
#include "mechgen/position/design.h"
#include "mechgen/position/solver.h"
#include "slider_crank.h"
#include "watt_sixbar.h"

namespace {

using mechtest::Config;
using mechtest::ParamsD;

template <class M>
using DesignD = typename M::template DesignDerivativesT<double>;

using DesignModels = ::testing::Types<mech::fourbar::Model, mech::slider_crank::Model, mech::watt_sixbar::Model,
                                      mech::design_stephenson::Model, mech::design_fivebar::Model,
                                      mech::design_cam_roller::Model, mech::design_geared_fivebar::Model,
                                      mech::design_quick_return::Model, mech::design_engine_single::Model>;

class ModelNames {
 public:
  template <typename M>
  static std::string GetName(int) {
    return M::kName;
  }
};

double Rel(double v) { return std::max(1.0, std::abs(v)); }

// A few dozen configurations over the input range (every fifth of the kinematics tests'
// sweep): each costs a Jet evaluation and, for the differences, 4 x kNumDesign solves.
template <class M>
std::vector<Config<M>> Configs(const ParamsD<M>& p, int every) {
  const std::vector<Config<M>> all = mechtest::SweepConfigs<M>(p, M::kNq == 1 ? 72 : M::kNq == 2 ? 6 : 12);
  std::vector<Config<M>> out;
  for (size_t i = 0; i < all.size(); i += every) out.push_back(all[i]);
  return out;
}

template <class M>
double& DesignParam(ParamsD<M>* p, int d) {
  double* v = p->Find(M::kDesignNames[d]);
  EXPECT_NE(v, nullptr) << M::kDesignNames[d];
  return *v;
}

template <class M>
class DesignDerivativesTest : public ::testing::Test {
 protected:
  static constexpr int kNd = M::kNumDesign;
  void SetUp() override {
    configs_ = Configs<M>(p_, M::kNq == 1 ? 5 : 1);
    ASSERT_FALSE(configs_.empty());
  }
  DesignD<M> Generated(const Config<M>& c) const {
    DesignD<M> out;
    M::Design(p_, c.q, c.phi, &out);
    return out;
  }
  ParamsD<M> p_;
  std::vector<Config<M>> configs_;
};
TYPED_TEST_SUITE(DesignDerivativesTest, DesignModels, ModelNames);

// Both sides are rounding of O(1000) flops through one factorization of Phi_phi away from
// the singular configurations: ~1e-14; 1e-12 relative to max(1, |value|) is the bar.
constexpr double kJetTol = 1e-12;

TYPED_TEST(DesignDerivativesTest, AgreesWithJetsOfTheGeneratedValues) {
  using M = TypeParam;
  constexpr int kNd = M::kNumDesign, kNphi = M::kNphi, kNq = M::kNq;
  using Jet = ceres::Jet<double, kNd>;
  double worst = 0;
  for (const auto& c : this->configs_) {
    const Eigen::Matrix<double, kNphi, kNd> dphi_dp = designtest::JetDphiDp<M>(this->p_, c.q, c.phi);

    const DesignD<M> g = this->Generated(c);
    for (int i = 0; i < kNphi; ++i)
      for (int d = 0; d < kNd; ++d) {
        const double e = std::abs(g.dphi_dp(i, d) - dphi_dp(i, d)) / Rel(dphi_dp(i, d));
        worst = std::max(worst, e);
        EXPECT_LE(e, kJetTol) << "dphi_dp(" << i << ", " << M::kDesignNames[d] << ")";
      }

    // EvalCoefficients in Jets carrying d/dp: p seeded, phi(p) to first order.
    const auto pk = designtest::SeededParams<M, Jet>(this->p_);
    const Eigen::Matrix<Jet, kNq, 1> qk = c.q.template cast<Jet>();
    const Eigen::Matrix<Jet, kNphi, 1> phik = designtest::PhiJets<M, Jet>(c.phi, dphi_dp);
    typename M::template CoefficientsT<Jet> cj;
    M::Coeffs(pk, qk, phik, &cj);
    auto compare = [&](double ref, double got, const std::string& what) {
      const double e = std::abs(got - ref) / Rel(ref);
      worst = std::max(worst, e);
      EXPECT_LE(e, kJetTol) << what << " at q(0) = " << c.q(0);
    };
    if constexpr (M::kNumTransmissionAngles > 0) {
      Eigen::Matrix<Jet, M::kNumTransmissionAngles, 1> muj;
      M::TransmissionAngles(pk, qk, phik, &muj);
      for (int i = 0; i < M::kNumTransmissionAngles; ++i)
        for (int d = 0; d < kNd; ++d) {
          const double e = std::abs(g.dmu_dp(i, d) - muj(i).v(d)) / Rel(muj(i).v(d));
          worst = std::max(worst, e);
          EXPECT_LE(e, kJetTol) << "dmu /d " << M::kDesignNames[d];
        }
    }
    for (int d = 0; d < kNd; ++d) {
      const std::string p_name = std::string("/d ") + M::kDesignNames[d];
      if constexpr (M::kOrder >= 1)
        for (int i = 0; i < kNphi; ++i)
          for (int j = 0; j < kNq; ++j) compare(cj.K(i, j).v(d), g.dK_dp(i, j + kNq * d), "dK" + p_name);
      if constexpr (M::kOrder >= 2)
        for (int i = 0; i < kNphi; ++i)
          for (int jk = 0; jk < kNq * kNq; ++jk)
            compare(cj.L(i, jk).v(d), g.dL_dp(i, jk + kNq * kNq * d), "dL" + p_name);
      if constexpr (M::kNumPoints > 0) {
        for (int m = 0; m < M::kNumPoints; ++m)
          for (int a = 0; a < 2; ++a) {
            compare(cj.r_P(a, m).v(d), g.dr_P_dp(2 * m + a, d), "dr_P" + p_name);
            if constexpr (M::kOrder >= 1)
              for (int j = 0; j < kNq; ++j)
                compare(cj.K_P(2 * m + a, j).v(d), g.dK_P_dp(2 * m + a, j + kNq * d), "dK_P" + p_name);
            if constexpr (M::kOrder >= 2)
              for (int jk = 0; jk < kNq * kNq; ++jk)
                compare(cj.L_P(2 * m + a, jk).v(d), g.dL_P_dp(2 * m + a, jk + kNq * kNq * d), "dL_P" + p_name);
          }
      }
    }
  }
  this->RecordProperty("worst_relative_error", mechtest::Sci(worst));
}

// Richardson-extrapolated central differences: (4 D(h/2) - D(h)) / 3, error O(h^4) plus
// rounding ~1e-15 / h: h = 1e-4 max(1, |p_d|) gives ~1e-11; 1e-7 is the bar.
TYPED_TEST(DesignDerivativesTest, AgreesWithRichardsonDifferences) {
  using M = TypeParam;
  constexpr int kNd = M::kNumDesign, kNphi = M::kNphi, kNq = M::kNq;
  using CoeffsD = mechtest::CoeffsD<M>;
  struct Values {
    mechtest::VecPhi<M> phi;
    CoeffsD c;
  };
  double worst = 0;
  for (size_t ci = 0; ci < this->configs_.size(); ci += 3) {
    const Config<M>& c = this->configs_[ci];
    const DesignD<M> g = this->Generated(c);
    for (int d = 0; d < kNd; ++d) {
      const double p0 = DesignParam<M>(&this->p_, d), h = 1e-4 * Rel(p0);
      auto at = [&](double delta) {
        ParamsD<M> p = this->p_;
        DesignParam<M>(&p, d) = p0 + delta;
        Values v;
        v.phi = c.phi;
        EXPECT_TRUE(mechtest::SolvePhi<M>(p, c.q, &v.phi).converged);
        M::Coeffs(p, c.q, v.phi, &v.c);
        return v;
      };
      const Values a = at(h), b = at(-h), a2 = at(h / 2), b2 = at(-h / 2);
      auto D = [&](double fa, double fb, double fa2, double fb2) {
        return (4 * (fa2 - fb2) / h - (fa - fb) / (2 * h)) / 3;
      };
      auto compare = [&](double ref, double got, const std::string& what) {
        const double e = std::abs(got - ref) / Rel(ref);
        worst = std::max(worst, e);
        EXPECT_LE(e, 1e-7) << what << " /d " << M::kDesignNames[d] << " at q(0) = " << c.q(0) << ": " << got
                           << " vs " << ref;
      };
      for (int i = 0; i < kNphi; ++i)
        compare(D(a.phi(i), b.phi(i), a2.phi(i), b2.phi(i)), g.dphi_dp(i, d), "dphi(" + std::to_string(i) + ")");
      if constexpr (M::kOrder >= 1)
        for (int i = 0; i < kNphi; ++i)
          for (int j = 0; j < kNq; ++j)
            compare(D(a.c.K(i, j), b.c.K(i, j), a2.c.K(i, j), b2.c.K(i, j)), g.dK_dp(i, j + kNq * d), "dK");
      if constexpr (M::kOrder >= 2)
        for (int i = 0; i < kNphi; ++i)
          for (int jk = 0; jk < kNq * kNq; ++jk)
            compare(D(a.c.L(i, jk), b.c.L(i, jk), a2.c.L(i, jk), b2.c.L(i, jk)), g.dL_dp(i, jk + kNq * kNq * d), "dL");
      if constexpr (M::kNumPoints > 0)
        for (int m = 0; m < M::kNumPoints; ++m)
          for (int ax = 0; ax < 2; ++ax)
            compare(D(a.c.r_P(ax, m), b.c.r_P(ax, m), a2.c.r_P(ax, m), b2.c.r_P(ax, m)), g.dr_P_dp(2 * m + ax, d),
                    "dr_P");
    }
  }
  this->RecordProperty("worst_relative_error", mechtest::Sci(worst));
}

// The design checks' derivatives against central differences of their margins (a model with
// four-bar loops: kNumDesignChecks > 0).
TYPED_TEST(DesignDerivativesTest, DesignCheckDerivativesAreDifferencesOfTheMargins) {
  using M = TypeParam;
  if constexpr (M::kNumDesignChecks > 0) {
    Eigen::Matrix<double, M::kNumDesignChecks, 1> margin, plus, minus;
    Eigen::Matrix<double, M::kNumDesignChecks, M::kNumDesign> dm;
    M::DesignChecks(this->p_, &margin, &dm);
    for (int d = 0; d < M::kNumDesign; ++d) {
      ParamsD<M> pp = this->p_, pm = this->p_;
      const double v = DesignParam<M>(&pp, d), h = 1e-6 * Rel(v);
      DesignParam<M>(&pp, d) = v + h;
      DesignParam<M>(&pm, d) = v - h;
      M::DesignChecks(pp, &plus);
      M::DesignChecks(pm, &minus);
      for (int i = 0; i < M::kNumDesignChecks; ++i)
        EXPECT_NEAR(dm(i, d), (plus(i) - minus(i)) / (2 * h), 1e-8) << M::kDesignCheckNames[i] << " / " << M::kDesignNames[d];
    }
  } else {
    GTEST_SKIP() << M::kName << " has no four-bar loop";
  }
}

// ---- Hand formulas ----

// The four-bar's checks: its link lengths a, b, c, d, and Grashof's margin with s = a (crank),
// l = d (ground): (b + c) - (a + d) = 1.5 at the defaults, derivatives -1, +1, +1, -1.
TEST(DesignHandFormulas, FourBarGrashofMargin) {
  using M = mech::fourbar::Model;
  ParamsD<M> p;
  Eigen::Matrix<double, M::kNumDesignChecks, 1> margin;
  Eigen::Matrix<double, M::kNumDesignChecks, M::kNumDesign> dm;
  M::DesignChecks(p, &margin, &dm);
  ASSERT_EQ(M::kNumDesignChecks, 7);
  ASSERT_STREQ(M::kDesignCheckNames[4], "grashof_loop0");
  // The coupler-rocker dyad's reach over a crank turn: (b + c)^2 - (a + d)^2, (d - a)^2 - (b - c)^2.
  ASSERT_STREQ(M::kDesignCheckNames[5], "reach_far_block0");
  ASSERT_STREQ(M::kDesignCheckNames[6], "reach_near_block0");
  EXPECT_NEAR(margin(5), (p.b + p.c) * (p.b + p.c) - (p.a + p.d) * (p.a + p.d), 1e-14);
  EXPECT_NEAR(margin(6), (p.d - p.a) * (p.d - p.a) - (p.b - p.c) * (p.b - p.c), 1e-14);
  EXPECT_NEAR(margin(4), (p.b + p.c) - (p.a + p.d), 1e-15);
  const double expected[6] = {-1, 1, 1, -1, 0, 0};  // a, b, c, d, xi, eta
  for (int d = 0; d < 6; ++d) EXPECT_NEAR(dm(4, d), expected[d], 1e-15) << M::kDesignNames[d];
  for (int i = 0; i < 4; ++i) EXPECT_GT(margin(i), 0) << M::kDesignCheckNames[i];
  p.b = 2.0;  // (2 + 3) - (1 + 4) = 0: a change point
  M::DesignChecks(p, &margin);
  EXPECT_NEAR(margin(4), 0.0, 1e-15);
}

// The slider-crank's reach margins (b - a + e, b - a - e: the rod reaches the slide all round
// iff b >= a + |e|) against the generated solver: with the rod 1e-6 shorter than a + |e| some
// crank angle of a turn (sampled every 0.25 deg and at +-90 deg, where |e - a sin(theta)| is
// largest) is not assemblable; 1e-6 longer, every one closes.
TEST(DesignHandFormulas, SliderCrankReachMarginIsWhereTheSolverStopsClosing) {
  using M = mech::slider_crank::Model;
  static_assert(M::kNumDesignChecks == 2);
  for (const double delta : {-1e-6, 1e-6}) {
    ParamsD<M> p;
    p.b = p.a + std::abs(p.e) + delta;
    Eigen::Matrix<double, 2, 1> margin;
    M::DesignChecks(p, &margin);
    EXPECT_NEAR(margin.minCoeff(), delta, 1e-14);
    bool all_close = true;
    std::vector<double> angles{M_PI / 2, -M_PI / 2};
    for (int i = 0; i < 1440; ++i) angles.push_back(2 * M_PI * i / 1440);
    for (const double theta : angles) {
      Eigen::Matrix<double, M::kNphi, 1> phi(0.0, 1.0);
      const auto report = M::Solve(p, Eigen::Matrix<double, 1, 1>(theta), &phi);
      if (report.status != mech::slider_crank::SolveStatus::kConverged) {
        all_close = false;
        EXPECT_EQ(report.status, mech::slider_crank::SolveStatus::kNotAssemblable) << theta;
      }
    }
    EXPECT_EQ(all_close, margin.minCoeff() >= 0) << "b = a + |e| + " << delta;
  }
}

// ---- Near a singular configuration ----

// The four-bar with its ground lengthened to d = 5.6 (its reach_far margin (b + c)^2 -
// (a + d)^2 < 0: the crank cannot turn fully) stops at a toggle, coupler and rocker aligned
// (|DB| = b + c), near theta = acos((a^2 + d^2 - (b + c)^2) / (2 a d)) = 152.0 deg. The crank
// moved toward it by the runtime's PositionSolver in steps of 0.25 deg: the design derivatives
// take the values' status. At every converged state they are finite, agree with Jets of EvalPhi
// to 1e-12 cond_1(Phi_phi) and obey |dphi/dp_d| <= |dPhi/dp_d| / sigma_min(Phi_phi) (|dPhi/dp_d|
// = 1 for a, b, c, d: a unit vector), growing like 1/sigma_min as the toggle nears; where the
// solver refuses (kSingular next to the toggle) the state is not valid and position::EvalDesign
// gives NaN, never a huge number.
TEST(DesignNearToggle, DerivativesTakeTheValuesStatus) {
  using M = mech::fourbar::Model;
  ParamsD<M> p;
  p.d = 5.6;
  Eigen::Matrix<double, M::kNumDesignChecks, 1> margin;
  M::DesignChecks(p, &margin);
  ASSERT_LT(margin(5), 0);  // reach_far_block0
  const double toggle = std::acos((p.a * p.a + p.d * p.d - (p.b + p.c) * (p.b + p.c)) / (2 * p.a * p.d));
  mechgen::position::PositionSolver<M> solver(mechgen::position::Options(), p);
  Eigen::Matrix<double, 1, 1> q(M_PI / 2);
  // At 90 deg: B = (0, 1), the coupler and rocker meet above the line DB.
  ASSERT_EQ(solver.Assemble(q, Eigen::Vector2d(0.3, 1.6), 0, nullptr), mechgen::position::Status::kConverged);
  int converged = 0;
  bool refused = false;
  double largest = 0, closest = 1;
  for (int step = 1; step < 400 && !refused; ++step) {
    q(0) = M_PI / 2 + step * (M_PI / 720);
    const auto status = solver.MoveTo(q, nullptr);
    const auto& s = solver.state();
    mechgen::position::DesignOf<M> g;
    if (status != mechgen::position::Status::kConverged) {
      EXPECT_EQ(status, mechgen::position::Status::kSingular) << q(0);
      EXPECT_LT(std::abs(q(0) - toggle), 0.02) << "refused away from the toggle";
      mechgen::position::State<M> failed = s;
      failed.valid = false;  // the row a sweep records for a refused step
      mechgen::position::EvalDesign<M>(p, failed, &g);
      EXPECT_TRUE(g.dphi_dp.array().isNaN().all());
      EXPECT_TRUE(g.dK_dp.array().isNaN().all());
      refused = true;
      break;
    }
    ++converged;
    ASSERT_TRUE(s.valid);
    mechgen::position::EvalDesign<M>(p, s, &g);
    ASSERT_TRUE(g.dphi_dp.allFinite());
    const Eigen::Matrix<double, M::kNphi, M::kNumDesign> jet = designtest::JetDphiDp<M>(p, s.q, s.phi);
    for (int d = 0; d < 4; ++d) {
      EXPECT_LE(g.dphi_dp.col(d).norm(), (1 + 1e-9) / s.sigma_min) << M::kDesignNames[d] << " at " << q(0);
      largest = std::max(largest, g.dphi_dp.col(d).norm());
      for (int i = 0; i < M::kNphi; ++i)
        EXPECT_NEAR(g.dphi_dp(i, d), jet(i, d), 1e-12 * s.condition * Rel(jet(i, d))) << q(0);
    }
    closest = std::min(closest, s.sigma_min / s.sigma_max);
  }
  EXPECT_TRUE(refused) << "the crank passed theta = " << toggle;
  EXPECT_GT(converged, 200);
  EXPECT_LT(closest, 1e-2);  // it came close to the toggle
  EXPECT_GT(largest, 30.0);  // and the derivatives grew like 1/sigma_min
  RecordProperty("closest_sigma_ratio", mechtest::Sci(closest));
  RecordProperty("largest_dphi_dp", mechtest::Sci(largest));
}

// Four-bar a u2 + b u3 - c u4 - d e_x = 0 (u_k = (cos theta_k, sin theta_k)). Differentiated
// with respect to a parameter at fixed theta_2: b n3 dtheta_3 - c n4 dtheta_4 = -w, n_k = u_k
// turned +90 deg, w the explicit derivative of the loop (u2, u3, -u4, -e_x for a, b, c, d).
// Dotted with u4 and with u3: dtheta_3 = (w . u4) / (b sin(theta_3 - theta_4)),
// dtheta_4 = (w . u3) / (c sin(theta_3 - theta_4)).
TEST(DesignHandFormulas, FourBarCouplerAndRocker) {
  using M = mech::fourbar::Model;
  ParamsD<M> p;
  double worst = 0;
  for (const auto& c : Configs<M>(p, 3)) {
    typename M::template DesignDerivativesT<double> g;
    M::Design(p, c.q, c.phi, &g);
    const double t2 = c.q(0), t3 = c.phi(0), t4 = c.phi(1);
    const Eigen::Vector2d u2(std::cos(t2), std::sin(t2)), u3(std::cos(t3), std::sin(t3)), u4(std::cos(t4), std::sin(t4));
    const double s34 = std::sin(t3 - t4);
    const Eigen::Vector2d w[4] = {u2, u3, -u4, Eigen::Vector2d(-1, 0)};
    for (int d = 0; d < 4; ++d) {  // a, b, c, d (kDesignNames' first four)
      ASSERT_STREQ(M::kDesignNames[d], std::string("abcd").substr(d, 1).c_str());
      const double dt3 = w[d].dot(u4) / (p.b * s34), dt4 = w[d].dot(u3) / (p.c * s34);
      worst = std::max({worst, std::abs(g.dphi_dp(0, d) - dt3), std::abs(g.dphi_dp(1, d) - dt4)});
      EXPECT_NEAR(g.dphi_dp(0, d), dt3, 1e-12 * Rel(dt3)) << "dtheta_coupler/d" << M::kDesignNames[d];
      EXPECT_NEAR(g.dphi_dp(1, d), dt4, 1e-12 * Rel(dt4)) << "dtheta_rocker/d" << M::kDesignNames[d];
    }
    // The coupler point P = B + xi u3 + eta n3: dP/dxi = u3, dP/deta = n3 (the angles do not move).
    EXPECT_NEAR(g.dr_P_dp(0, 4), u3.x(), 1e-15);
    EXPECT_NEAR(g.dr_P_dp(1, 4), u3.y(), 1e-15);
    EXPECT_NEAR(g.dr_P_dp(0, 5), -u3.y(), 1e-15);
    EXPECT_NEAR(g.dr_P_dp(1, 5), u3.x(), 1e-15);
  }
  RecordProperty("worst_absolute_error", mechtest::Sci(worst));
}

// Offset slider-crank: slider C = (s, e), s = a cos(theta) + D, D = sqrt(b^2 - (e - a sin(theta))^2):
// ds/da = cos(theta) + (e - a sin(theta)) sin(theta) / D, ds/db = b / D, ds/de = -(e - a sin(theta)) / D.
TEST(DesignHandFormulas, SliderCrankStroke) {
  using M = mech::slider_crank::Model;
  ParamsD<M> p;
  ASSERT_STREQ(M::kPhiNames[1], "s_slide");
  for (const auto& c : Configs<M>(p, 3)) {
    typename M::template DesignDerivativesT<double> g;
    M::Design(p, c.q, c.phi, &g);
    const double th = c.q(0), y = p.e - p.a * std::sin(th), D = std::sqrt(p.b * p.b - y * y);
    const double ds[3] = {std::cos(th) + y * std::sin(th) / D, p.b / D, -y / D};
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(g.dphi_dp(1, d), ds[d], 1e-13 * Rel(ds[d])) << "ds/d" << M::kDesignNames[d];
      EXPECT_NEAR(g.dr_P_dp(0, d), ds[d], 1e-13 * Rel(ds[d])) << "dx_C/d" << M::kDesignNames[d];
    }
    EXPECT_NEAR(g.dr_P_dp(1, 2), 1.0, 1e-15);  // y_C = e
    EXPECT_NEAR(g.dr_P_dp(1, 0), 0.0, 1e-15);
  }
}

}  // namespace
