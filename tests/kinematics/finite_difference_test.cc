// Velocity and centripetal coefficients of every shipped model (K, L and, for each point of
// interest, K_P, L_P) against central finite differences of *positions*.
//
// Oracle path: phi(q) comes from the test-local Newton solve on the generated Phi/Phi_phi
// (kinematics_test_util.h, converged to rounding level), r_P(q) is the generated position
// of the point at that phi. Only positions are differenced; the generated K, L, K_P, L_P
// never enter the oracle (except in the one test named "...OfGeneratedK", a consistency
// check of L against K).
//
// Step sizes and tolerances. Positions are O(1) and accurate to delta ~ 1e-15 (a few ulps,
// times the conditioning of Phi_phi, which is O(1) on the swept ranges).
//  * K by the central first difference with h = 1e-5: truncation h^2/6 |f'''| ~ 1.7e-11 |f'''|,
//    rounding delta/h ~ 1e-10. The third derivatives of these mechanisms are O(1..10), so the
//    error is ~1e-10; kKTol = 1e-8 (relative to max(1, |K|)) leaves two orders of margin and
//    is still five orders below an O(1e-3) error of a wrong term.
//  * L by the central second difference of positions with h = 1e-4 (the near-optimal step
//    (delta)^(1/4) for an O(h^2) second difference): truncation h^2/3 |f''''| ~ 3e-9 |f''''|,
//    rounding 4 delta/(4 h^2) ~ 1e-7. kLTol = 1e-6 relative: one order above the rounding
//    estimate (measured worst case 8.7e-8, inverted_slider_crank); a wrong term is O(1e-3).
//    Smaller relative errors in L are caught by the difference of the generated K below.
//  * L against the central difference of the generated K (h = 1e-5): K is a closed-form
//    expression accurate to ~1e-15, so rounding ~1e-10 as for K; kLFromKTol = 1e-8.
// Measured worst cases (all models, all samples): K 2.2e-10, L from K 7.7e-10 (fivebar).
// The worst case over all samples is asserted once per test, with its location.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "all_models.h"
#include "kinematics_test_util.h"

namespace {

using mechtest::CoeffsD;
using mechtest::Config;
using mechtest::kSamplesPerDof;
using mechtest::ParamsD;

constexpr double kHFirst = 1e-5;
constexpr double kHSecond = 1e-4;
constexpr double kKTol = 1e-8;
constexpr double kLTol = 1e-6;
constexpr double kLFromKTol = 1e-8;
constexpr double kSymmetryTol = 1e-14;

// Tracks the worst relative error |gen - ref| / max(1, |gen|) and where it occurred.
struct Worst {
  double err = 0;
  std::string where = "(none)";
  template <class M, class A, class B>
  void Update(const A& gen, const B& ref, const Config<M>& c, const char* what) {
    for (int i = 0; i < gen.rows(); ++i) {
      for (int j = 0; j < gen.cols(); ++j) {
        const double e = std::abs(gen(i, j) - ref(i, j)) / std::max(1.0, std::abs(gen(i, j)));
        if (!(e <= err)) {  // also catches NaN
          err = std::isnan(e) ? INFINITY : e;
          std::ostringstream s;
          s << what << "(" << mechtest::PositionName<M>(i) << ", col " << j
            << ") at q = " << c.q.transpose() << ": generated " << gen(i, j) << ", reference "
            << ref(i, j);
          where = s.str();
        }
      }
    }
  }
};

template <class M>
class FiniteDifferenceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    sweep_ = mechtest::SweepConfigs<M>(p_, kSamplesPerDof<M>);
    const size_t expected = M::kNq == 2 ? kSamplesPerDof<M> * kSamplesPerDof<M> : kSamplesPerDof<M>;
    ASSERT_EQ(sweep_.size(), expected) << "the test-local Newton sweep failed";
  }
  CoeffsD<M> Generated(const Config<M>& c) const {
    CoeffsD<M> out;
    M::Coeffs(p_, c.q, c.phi, &out);
    return out;
  }
  ParamsD<M> p_;
  std::vector<Config<M>> sweep_;
};
TYPED_TEST_SUITE(FiniteDifferenceTest, mechtest::AllModels, mechtest::ModelNames);

// Both columns of K (all columns for the five-bar) and K_P of every point.
TYPED_TEST(FiniteDifferenceTest, KAndKPMatchCentralDifferencesOfPositions) {
  using M = TypeParam;
  Worst worst;
  for (const auto& c : this->sweep_) {
    bool ok = true;
    const auto fd = mechtest::FirstDifferences<M>(this->p_, c, kHFirst, &ok);
    ASSERT_TRUE(ok) << "Newton failed near q = " << c.q.transpose();
    worst.Update<M>(mechtest::StackedK<M>(this->Generated(c)), fd, c, "K");
  }
  this->RecordProperty("max_rel_error", mechtest::Sci(worst.err));
  EXPECT_LT(worst.err, kKTol) << "worst: " << worst.where;
}

// Every 2x2 block of L (column j + kNq*k = d^2 / dq_j dq_k) and L_P of every point.
TYPED_TEST(FiniteDifferenceTest, LAndLPMatchSecondDifferencesOfPositions) {
  using M = TypeParam;
  Worst worst;
  for (const auto& c : this->sweep_) {
    bool ok = true;
    const auto fd = mechtest::SecondDifferences<M>(this->p_, c, kHSecond, &ok);
    ASSERT_TRUE(ok) << "Newton failed near q = " << c.q.transpose();
    worst.Update<M>(mechtest::StackedL<M>(this->Generated(c)), fd, c, "L");
  }
  this->RecordProperty("max_rel_error", mechtest::Sci(worst.err));
  EXPECT_LT(worst.err, kLTol) << "worst: " << worst.where;
}

// Consistency: L(:, j + kNq*k) = d K(:, j) / d q_k along the solved path (and likewise
// L_P from K_P), by central differences of the generated K with h = 1e-5.
TYPED_TEST(FiniteDifferenceTest, LAndLPMatchCentralDifferencesOfGeneratedK) {
  using M = TypeParam;
  Worst worst;
  for (const auto& c : this->sweep_) {
    Eigen::Matrix<double, mechtest::kNumPositions<M>, M::kNq * M::kNq> fd;
    for (int k = 0; k < M::kNq; ++k) {
      Config<M> cp = c, cm = c;
      cp.q(k) += kHFirst;
      cm.q(k) -= kHFirst;
      ASSERT_TRUE(mechtest::SolvePhi<M>(this->p_, cp.q, &cp.phi).converged);
      ASSERT_TRUE(mechtest::SolvePhi<M>(this->p_, cm.q, &cm.phi).converged);
      const auto Kp = mechtest::StackedK<M>(this->Generated(cp));
      const auto Km = mechtest::StackedK<M>(this->Generated(cm));
      for (int j = 0; j < M::kNq; ++j)
        fd.col(j + M::kNq * k) = (Kp.col(j) - Km.col(j)) / (2 * kHFirst);
    }
    worst.Update<M>(mechtest::StackedL<M>(this->Generated(c)), fd, c, "L");
  }
  this->RecordProperty("max_rel_error", mechtest::Sci(worst.err));
  EXPECT_LT(worst.err, kLFromKTol) << "worst: " << worst.where;
}

// Mixed partials commute: L(i, j + kNq*k) = L(i, k + kNq*j), and likewise L_P. (Trivial for
// one input; for the five-bar it checks that both off-diagonal columns are filled alike.)
TYPED_TEST(FiniteDifferenceTest, LAndLPAreSymmetricInTheInputIndices) {
  using M = TypeParam;
  for (const auto& c : this->sweep_) {
    const auto L = mechtest::StackedL<M>(this->Generated(c));
    ASSERT_TRUE(L.allFinite()) << "at q = " << c.q.transpose();
    for (int j = 0; j < M::kNq; ++j) {
      for (int k = 0; k < j; ++k) {
        for (int i = 0; i < L.rows(); ++i) {
          EXPECT_NEAR(L(i, j + M::kNq * k), L(i, k + M::kNq * j),
                      kSymmetryTol * std::max(1.0, std::abs(L(i, j + M::kNq * k))))
              << mechtest::PositionName<M>(i) << " at q = " << c.q.transpose();
        }
      }
    }
  }
}

// The generated point of interest r_P is the scene point of the same name.
TYPED_TEST(FiniteDifferenceTest, PointOfInterestEqualsItsScenePoint) {
  using M = TypeParam;
  for (int m = 0; m < M::kNumPoints; ++m) {
    const int s = mechtest::ScenePointIndex<M>(M::kPointNames[m]);
    ASSERT_GE(s, 0) << M::kPointNames[m];
    for (const auto& c : this->sweep_) {
      Eigen::Matrix<double, 2, M::kNumScenePoints> scene;
      M::Scene(this->p_, c.q, c.phi, &scene);
      const auto gen = this->Generated(c);
      EXPECT_NEAR(gen.r_P(0, m), scene(0, s), 1e-14 * std::max(1.0, std::abs(scene(0, s))));
      EXPECT_NEAR(gen.r_P(1, m), scene(1, s), 1e-14 * std::max(1.0, std::abs(scene(1, s))));
    }
  }
}

// The one-pass kinematics (Model::Kinematics = EvalKinematics: SolveTrig's direction cosines,
// K, L and Phi_phi together), where the model has it: K against the central differences of the
// test-local Newton positions (as above), L against the central differences of its own K at
// q -+ h along the branch (kLFromKTol, as above), Phi_phi against the central differences of
// the generated residual Phi in each angle (h = 1e-5: Phi is O(1) and accurate to ~1e-15, so
// rounding ~1e-10 and truncation ~1e-11; kKTol), and its direction cosines against std::sin /
// std::cos of the Newton angles (1e-11, as tests/kinematics/solve_trig_test.cc).
TYPED_TEST(FiniteDifferenceTest, OnePassKinematicsMatchCentralDifferences) {
  using M = TypeParam;
  if constexpr (!M::kHasKinematics) {
    GTEST_SKIP() << "no EvalKinematics (no SolveTrig, or no K asked for)";
  } else {
    using KinematicsD = typename M::template KinematicsT<double>;
    using TrigD = typename M::template TrigT<double>;
    Worst worst_K, worst_L, worst_Phi_phi;
    for (const auto& c : this->sweep_) {
      KinematicsD kin;
      TrigD trig;
      const auto report = M::Kinematics(this->p_, c.q, M::kDefaultModes, &trig, &kin);
      ASSERT_EQ(static_cast<int>(report.status), 0) << "q = " << c.q.transpose();
      for (int i = 0; i < M::kNphi; ++i) {
        EXPECT_NEAR(trig.sin_phi(i), std::sin(c.phi(i)), 1e-11) << M::kPhiNames[i] << " q = " << c.q.transpose();
        EXPECT_NEAR(trig.cos_phi(i), std::cos(c.phi(i)), 1e-11) << M::kPhiNames[i] << " q = " << c.q.transpose();
      }
      bool ok = true;
      const auto fd = mechtest::FirstDifferences<M>(this->p_, c, kHFirst, &ok);
      ASSERT_TRUE(ok) << "Newton failed near q = " << c.q.transpose();
      worst_K.Update<M>(kin.K, fd.template topRows<M::kNphi>(), c, "K");
      Eigen::Matrix<double, M::kNc, M::kNphi> Phi_phi_fd;
      for (int j = 0; j < M::kNphi; ++j) {
        mechtest::VecPhi<M> phi_p = c.phi, phi_m = c.phi;
        phi_p(j) += kHFirst;
        phi_m(j) -= kHFirst;
        Eigen::Matrix<double, M::kNc, 1> res_p, res_m;
        M::Phi(this->p_, c.q, phi_p, &res_p);
        M::Phi(this->p_, c.q, phi_m, &res_m);
        Phi_phi_fd.col(j) = (res_p - res_m) / (2 * kHFirst);
      }
      worst_Phi_phi.Update<M>(kin.Phi_phi, Phi_phi_fd, c, "Phi_phi");
      if constexpr (M::kHasL) {
        Eigen::Matrix<double, M::kNphi, M::kNq * M::kNq> L_fd;
        for (int k = 0; k < M::kNq; ++k) {
          mechtest::VecQ<M> qp = c.q, qm = c.q;
          qp(k) += kHFirst;
          qm(k) -= kHFirst;
          KinematicsD kp, km;
          TrigD tp, tm;
          ASSERT_EQ(static_cast<int>(M::Kinematics(this->p_, qp, M::kDefaultModes, &tp, &kp).status), 0);
          ASSERT_EQ(static_cast<int>(M::Kinematics(this->p_, qm, M::kDefaultModes, &tm, &km).status), 0);
          for (int j = 0; j < M::kNq; ++j) L_fd.col(j + M::kNq * k) = (kp.K.col(j) - km.K.col(j)) / (2 * kHFirst);
        }
        worst_L.Update<M>(kin.L, L_fd, c, "L");
      }
    }
    this->RecordProperty("max_rel_error_K", mechtest::Sci(worst_K.err));
    this->RecordProperty("max_rel_error_L", mechtest::Sci(worst_L.err));
    EXPECT_LT(worst_K.err, kKTol) << "worst: " << worst_K.where;
    EXPECT_LT(worst_L.err, kLFromKTol) << "worst: " << worst_L.where;
    EXPECT_LT(worst_Phi_phi.err, kKTol) << "worst: " << worst_Phi_phi.where;
  }
}

// The finite differences are sharp enough to see a small error: perturbing the generated K
// by 1e-6 (100 x kKTol) must fail the comparison (guards against a vacuous oracle).
TYPED_TEST(FiniteDifferenceTest, FiniteDifferenceOracleDetectsAPerturbation) {
  using M = TypeParam;
  const auto& c = this->sweep_[this->sweep_.size() / 3];
  bool ok = true;
  const auto fd = mechtest::FirstDifferences<M>(this->p_, c, kHFirst, &ok);
  ASSERT_TRUE(ok);
  auto gen = mechtest::StackedK<M>(this->Generated(c));
  gen(0, 0) += 1e-6 * std::max(1.0, std::abs(gen(0, 0)));
  Worst worst;
  worst.Update<M>(gen, fd, c, "K");
  EXPECT_GT(worst.err, kKTol);
}

}  // namespace
