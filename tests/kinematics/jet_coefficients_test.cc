// The coefficients of every shipped model against ceres::Jet autodiff through the
// templated generated functions (which also proves EvalCoefficients and EvalScene compile
// for Jet scalars).
//
// On the solution manifold phi = phi(q), so a total derivative is
//   d f(q, phi(q)) / dq_k = df/dq_k + sum_i df/dphi_i K(i, k).
// With Jets seeded on (q, phi) this gives exact (to rounding) references:
//   K      = -Phi_phi^-1 Phi_q     with Phi_phi, Phi_q from Jet derivatives of EvalPhi
//   K_P    = d r_P / dq            total derivative of the Jet r_P (and of the scene point)
//   L      = d K / dq              total derivative of the Jet K
//   L_P    = d K_P / dq            total derivative of the Jet K_P
// The generated K enters the chain rule for L, K_P and L_P, so these are consistency
// checks; K itself is checked independently here (through Jet Phi_phi, Phi_q) and by
// finite differences of positions (finite_difference_test.cc).
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "all_models.h"
#include "kinematics_test_util.h"

namespace {

using mechtest::Config;
using mechtest::ParamsD;

// Both sides are analytic expressions evaluated in double; they differ only by rounding
// of O(100) flops with one division by det(Phi_phi), which stays well away from zero on
// the swept ranges (the models avoid their singular configurations, see their
// descriptions): ~1e-14. 1e-12 relative to max(1, |value|) leaves two orders of margin.
constexpr double kTol = 1e-12;

template <class M>
class JetCoefficientsTest : public ::testing::Test {
 protected:
  static constexpr int kN = M::kNq + M::kNphi;
  using Jet = ceres::Jet<double, kN>;

  void SetUp() override {
    sweep_ = mechtest::SweepConfigs<M>(p_, mechtest::kSamplesPerDof<M>);
    ASSERT_FALSE(sweep_.empty());
  }
  // Jet (q, phi) seeded on all kNq + kNphi variables.
  static void Seed(const Config<M>& c,
                   Eigen::Matrix<Jet, M::kNq, 1>* qj,
                   Eigen::Matrix<Jet, M::kNphi, 1>* phij) {
    for (int j = 0; j < M::kNq; ++j) (*qj)(j) = Jet(c.q(j), j);
    for (int i = 0; i < M::kNphi; ++i) (*phij)(i) = Jet(c.phi(i), M::kNq + i);
  }
  // Total derivative d f / dq_k of a Jet f(q, phi) on the manifold (uses K).
  static double Total(const Jet& f, int k, const mechtest::CoeffsD<M>& gen) {
    double d = f.v(k);
    for (int i = 0; i < M::kNphi; ++i) d += f.v(M::kNq + i) * gen.K(i, k);
    return d;
  }
  ParamsD<M> p_;
  std::vector<Config<M>> sweep_;
};
TYPED_TEST_SUITE(JetCoefficientsTest, mechtest::AllModels, mechtest::ModelNames);

double Rel(double v) { return std::max(1.0, std::abs(v)); }

TYPED_TEST(JetCoefficientsTest, KEqualsMinusPhiPhiInversePhiQFromJets) {
  using M = TypeParam;
  using Jet = typename TestFixture::Jet;
  const auto pj = this->p_.template Cast<Jet>();
  for (const auto& c : this->sweep_) {
    Eigen::Matrix<Jet, M::kNq, 1> qj;
    Eigen::Matrix<Jet, M::kNphi, 1> phij;
    this->Seed(c, &qj, &phij);
    Eigen::Matrix<Jet, M::kNc, 1> Phij;
    M::Phi(pj, qj, phij, &Phij);
    Eigen::Matrix<double, M::kNc, M::kNq> Phi_q;
    Eigen::Matrix<double, M::kNc, M::kNphi> Phi_phi;
    for (int r = 0; r < M::kNc; ++r) {
      Phi_q.row(r) = Phij(r).v.template head<M::kNq>().transpose();
      Phi_phi.row(r) = Phij(r).v.template tail<M::kNphi>().transpose();
    }
    const Eigen::Matrix<double, M::kNphi, M::kNq> K_ref = -Phi_phi.fullPivLu().solve(Phi_q);
    mechtest::CoeffsD<M> gen;
    M::Coeffs(this->p_, c.q, c.phi, &gen);
    for (int i = 0; i < M::kNphi; ++i) {
      for (int j = 0; j < M::kNq; ++j) {
        EXPECT_NEAR(gen.K(i, j), K_ref(i, j), kTol * Rel(K_ref(i, j)))
            << "K(" << M::kPhiNames[i] << ", " << M::kQNames[j] << ") at q = " << c.q.transpose();
      }
    }
  }
}

TYPED_TEST(JetCoefficientsTest, KPLAndLPAreTotalDerivativesThroughJets) {
  using M = TypeParam;
  using Jet = typename TestFixture::Jet;
  const auto pj = this->p_.template Cast<Jet>();
  for (const auto& c : this->sweep_) {
    Eigen::Matrix<Jet, M::kNq, 1> qj;
    Eigen::Matrix<Jet, M::kNphi, 1> phij;
    this->Seed(c, &qj, &phij);
    typename M::template CoefficientsT<Jet> cj;
    M::Coeffs(pj, qj, phij, &cj);
    Eigen::Matrix<Jet, 2, M::kNumScenePoints> scene;
    M::Scene(pj, qj, phij, &scene);
    mechtest::CoeffsD<M> gen;
    M::Coeffs(this->p_, c.q, c.phi, &gen);
    const auto where = [&] {
      std::ostringstream s;
      s << " at q = " << c.q.transpose();
      return s.str();
    };

    for (int k = 0; k < M::kNq; ++k) {
      for (int i = 0; i < M::kNphi; ++i) {
        for (int j = 0; j < M::kNq; ++j) {
          const double ref = this->Total(cj.K(i, j), k, gen);
          EXPECT_NEAR(gen.L(i, j + M::kNq * k), ref, kTol * Rel(ref))
              << "L(" << M::kPhiNames[i] << ", " << j << " + kNq*" << k << ")" << where();
        }
      }
      for (int m = 0; m < M::kNumPoints; ++m) {
        const int s = mechtest::ScenePointIndex<M>(M::kPointNames[m]);
        ASSERT_GE(s, 0);
        for (int a = 0; a < 2; ++a) {
          const double ref_kp = this->Total(cj.r_P(a, m), k, gen);
          EXPECT_NEAR(gen.K_P(2 * m + a, k), ref_kp, kTol * Rel(ref_kp))
              << "K_P(" << M::kPointNames[m] << (a ? ".y" : ".x") << ", " << k << ")" << where();
          const double ref_scene = this->Total(scene(a, s), k, gen);
          EXPECT_NEAR(gen.K_P(2 * m + a, k), ref_scene, kTol * Rel(ref_scene))
              << "K_P vs scene " << M::kPointNames[m] << where();
          for (int j = 0; j < M::kNq; ++j) {
            const double ref_lp = this->Total(cj.K_P(2 * m + a, j), k, gen);
            EXPECT_NEAR(gen.L_P(2 * m + a, j + M::kNq * k), ref_lp, kTol * Rel(ref_lp))
                << "L_P(" << M::kPointNames[m] << (a ? ".y" : ".x") << ", " << j << " + kNq*" << k
                << ")" << where();
          }
        }
      }
    }
    // The Jet values (.a) are the double results up to rounding (Jet division multiplies
    // by a reciprocal, so the two are not bit-identical; same kTol as above).
    EXPECT_NEAR(cj.K(0, 0).a, gen.K(0, 0), kTol * Rel(gen.K(0, 0)));
    EXPECT_NEAR(cj.L(0, 0).a, gen.L(0, 0), kTol * Rel(gen.L(0, 0)));
  }
}

}  // namespace
