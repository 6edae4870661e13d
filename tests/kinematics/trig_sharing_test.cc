// The Trig<Scalar> hand-over between the generated functions, for every shipped model:
// SolvePositions(..., &trig) writes sin and cos of every angle coordinate at its solution
// (a closed-form dyad from its own dot and cross products, without calling sin or cos),
// and EvalCoefficients(..., &trig) then gives what it gives without them.
// Oracles: std::sin / std::cos of the solved angles; EvalCoefficients without trig.
// Configurations: the model's input range on its assembly branch, solved by the test's own
// Newton iteration (kinematics_test_util.h), not by SolvePositions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "all_models.h"
#include "kinematics_test_util.h"

namespace {

template <class M>
class TrigSharingTest : public ::testing::Test {};
TYPED_TEST_SUITE(TrigSharingTest, mechtest::AllModels, mechtest::ModelNames);

// |a - b| <= tol * max(1, |b|), entry by entry.
template <class A, class B>
double WorstRelative(const A& a, const B& b) {
  double worst = 0;
  for (int i = 0; i < a.rows(); ++i)
    for (int j = 0; j < a.cols(); ++j)
      worst = std::max(worst, std::abs(a(i, j) - b(i, j)) / std::max(1.0, std::abs(b(i, j))));
  return worst;
}

TYPED_TEST(TrigSharingTest, SolveHandsOutSinCosAndCoefficientsAgree) {
  using M = TypeParam;
  const mechtest::ParamsD<M> p;
  const auto configs = mechtest::SweepConfigs<M>(p, M::kNq == 1 ? 180 : 12);
  ASSERT_FALSE(configs.empty());
  for (const auto& c : configs) {
    mechtest::VecPhi<M> phi = c.phi;
    typename M::template TrigT<double> trig;
    trig.sin_q.setConstant(NAN);
    trig.cos_q.setConstant(NAN);
    trig.sin_phi.setConstant(NAN);
    trig.cos_phi.setConstant(NAN);
    const auto report = M::Solve(p, c.q, &phi, M::kDefaultModes, 20, 0.0, &trig);
    ASSERT_EQ(static_cast<int>(report.status), 0) << "q = " << c.q.transpose();
    // The closed forms reproduce the Newton solution (same branch) to rounding.
    ASSERT_LT((phi - c.phi).template lpNorm<Eigen::Infinity>(), 1e-9) << "q = " << c.q.transpose();
    for (int j = 0; j < M::kNq; ++j) {
      if (!M::kQIsAngle[j]) continue;
      EXPECT_EQ(trig.sin_q(j), std::sin(c.q(j)));
      EXPECT_EQ(trig.cos_q(j), std::cos(c.q(j)));
    }
    for (int i = 0; i < M::kNphi; ++i) {
      if (!M::kPhiIsAngle[i]) continue;
      // A dyad's dot / |a|^2 is cos of the atan2 it stores to a few ulps.
      EXPECT_NEAR(trig.sin_phi(i), std::sin(phi(i)), 1e-14) << M::kPhiNames[i];
      EXPECT_NEAR(trig.cos_phi(i), std::cos(phi(i)), 1e-14) << M::kPhiNames[i];
    }
    mechtest::CoeffsD<M> with, without;
    M::Coeffs(p, c.q, phi, &without);
    M::Coeffs(p, c.q, phi, &with, &trig);
    // Inputs differing by ~1e-16 move the coefficients by ~cond(Phi_phi) * 1e-16; the
    // shipped models keep cond below ~1e3 over their ranges.
    constexpr double kTol = 1e-12;
    EXPECT_LT(WorstRelative(with.Phi, without.Phi), kTol);
    EXPECT_LT(WorstRelative(with.Phi_phi, without.Phi_phi), kTol);
    if constexpr (M::kOrder >= 1) {
      EXPECT_LT(WorstRelative(with.K, without.K), kTol);
    }
    if constexpr (M::kOrder >= 2) {
      EXPECT_LT(WorstRelative(with.L, without.L), kTol);
    }
    if constexpr (M::kNumPoints > 0) {
      EXPECT_LT(WorstRelative(with.r_P, without.r_P), kTol);
    }
  }
}

}  // namespace
