// The float instantiations of every shipped model (compiled in <name>.cc next to double)
// give the double results to float precision, at solved configurations over the sweeps.
//
// Tolerance. Inputs are rounded to float (eps_f = 6e-8), and each output is an O(100)-flop
// expression with one division by det(Phi_phi). The computed values are the exact values at
// inputs perturbed by ~eps_f, amplified by the conditioning of Phi_phi (well conditioned on
// these sweeps) and by the chain K -> L: some tens of eps_f (the worst case measured over all
// models is 1.6e-6 = 26 eps_f, inverted_slider_crank). kTol = 2e-5 (~330 eps_f) relative to
// max(1, |value|) leaves an order of margin; an error in the float code path (a literal
// truncated to an integer, a double-only function, a float/double mix) would be O(1e-3) or
// more. Phi at a double-solved configuration, evaluated in float: ~|terms| eps_f ~ 5e-7;
// kPhiTol = 1e-5.
#include <gtest/gtest.h>

#include <cmath>

#include "all_models.h"
#include "kinematics_test_util.h"

namespace {

constexpr double kTol = 2e-5;
constexpr double kPhiTol = 1e-5;

template <class M>
class FloatInstantiationTest : public ::testing::Test {};
TYPED_TEST_SUITE(FloatInstantiationTest, mechtest::AllModels, mechtest::ModelNames);

template <class A, class B>
double MaxRelDiff(const A& f, const B& d) {
  double worst = 0;
  for (int i = 0; i < d.rows(); ++i) {
    for (int j = 0; j < d.cols(); ++j) {
      const double e =
          std::abs(static_cast<double>(f(i, j)) - d(i, j)) / std::max(1.0, std::abs(d(i, j)));
      if (!(e <= worst)) worst = std::isnan(e) ? INFINITY : e;
    }
  }
  return worst;
}

TYPED_TEST(FloatInstantiationTest, FloatMatchesDoubleWithinFloatPrecision) {
  using M = TypeParam;
  const typename M::template ParamsT<double> pd;
  const auto pf = pd.template Cast<float>();
  const auto sweep = mechtest::SweepConfigs<M>(pd, mechtest::kSamplesPerDof<M>);
  ASSERT_FALSE(sweep.empty());
  double worst_coeff = 0, worst_phi = 0, worst_scene = 0;
  for (const auto& c : sweep) {
    const Eigen::Matrix<float, M::kNq, 1> qf = c.q.template cast<float>();
    const Eigen::Matrix<float, M::kNphi, 1> phif = c.phi.template cast<float>();

    Eigen::Matrix<float, M::kNc, 1> Phif;
    Eigen::Matrix<float, M::kNc, M::kNphi> Phi_phif;
    Eigen::Matrix<float, M::kNc, M::kNq> Phi_qf;
    M::Phi(pf, qf, phif, &Phif, &Phi_phif, &Phi_qf);
    Eigen::Matrix<double, M::kNc, 1> Phid;
    Eigen::Matrix<double, M::kNc, M::kNphi> Phi_phid;
    Eigen::Matrix<double, M::kNc, M::kNq> Phi_qd;
    M::Phi(pd, c.q, c.phi, &Phid, &Phi_phid, &Phi_qd);
    worst_phi = std::max(worst_phi, MaxRelDiff(Phif, Phid));
    worst_coeff =
        std::max({worst_coeff, MaxRelDiff(Phi_phif, Phi_phid), MaxRelDiff(Phi_qf, Phi_qd)});

    typename M::template CoefficientsT<float> cf;
    typename M::template CoefficientsT<double> cd;
    M::Coeffs(pf, qf, phif, &cf);
    M::Coeffs(pd, c.q, c.phi, &cd);
    worst_coeff = std::max({worst_coeff, MaxRelDiff(cf.K, cd.K), MaxRelDiff(cf.L, cd.L),
                            MaxRelDiff(cf.r_P, cd.r_P), MaxRelDiff(cf.K_P, cd.K_P),
                            MaxRelDiff(cf.L_P, cd.L_P)});

    Eigen::Matrix<float, 2, M::kNumScenePoints> sf;
    Eigen::Matrix<double, 2, M::kNumScenePoints> sd;
    M::Scene(pf, qf, phif, &sf);
    M::Scene(pd, c.q, c.phi, &sd);
    worst_scene = std::max(worst_scene, MaxRelDiff(sf, sd));
  }
  this->RecordProperty("max_rel_error", mechtest::Sci(worst_coeff));
  EXPECT_LT(worst_phi, kPhiTol) << "Phi (double-closed configuration) in float";
  EXPECT_LT(worst_coeff, kTol) << "Phi_phi, Phi_q, K, L, r_P, K_P, L_P in float vs double";
  EXPECT_LT(worst_scene, kTol) << "EvalScene in float vs double";
  // Float really was used: the results are not bit-identical to double everywhere.
  EXPECT_GT(worst_coeff, 1e-9);
}

}  // namespace
