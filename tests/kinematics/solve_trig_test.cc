// The generated SolveTrig (Model::SolveTrig), for every shipped model that has it: sin and
// cos of every angle without the angles (no atan2), the same statuses as SolvePositions.
// Oracles:
//  - std::sin / std::cos of the angles the test's own Newton continuation finds on the
//    assembly branch (kinematics_test_util.h), over the model's input range;
//  - on every mode combination and over inputs beyond the range (where the loop may not
//    close): SolvePositions' status, and std::sin / std::cos of its angles where it converges;
//  - EvalCoefficients given SolveTrig's trig and a phi of NaNs equals EvalCoefficients
//    without trig at the solved phi (the generator's promise that nothing reads phi then);
//  - hostile parameters and inputs (non-finite, zero, tiny, huge, subnormal; one at a time and
//    all scaled together): what SolveTrig and EvalKinematics report as converged is finite
//    (their direction cosines carry no test of their own where the RRR dyad's range checks
//    prove them finite, symbolic/dyads.cc); Paul's four-bar in other units gives the same
//    cosines, K and L inside that range and is refused as singular beyond it.
// Models without SolveTrig (Newton blocks, displacement unknowns, one-angle forms, an angle
// read downstream other than through sin and cos) skip.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

#include "all_models.h"
#include "kinematics_test_util.h"

namespace {

template <class M, class = void>
struct HasSolveTrig : std::false_type {};
template <class M>
struct HasSolveTrig<M, std::void_t<decltype(M::template SolveTrig<double>(
                           std::declval<const typename M::template ParamsT<double>&>(),
                           std::declval<const Eigen::Matrix<double, M::kNq, 1>&>(),
                           std::declval<const std::array<int, M::kNumBlocks>&>(),
                           std::declval<typename M::template TrigT<double>*>()))>> : std::true_type {};

template <class M>
class SolveTrigTest : public ::testing::Test {};
TYPED_TEST_SUITE(SolveTrigTest, mechtest::AllModels, mechtest::ModelNames);

template <class Trig>
void Poison(Trig* trig) {
  trig->sin_q.setConstant(NAN);
  trig->cos_q.setConstant(NAN);
  trig->sin_phi.setConstant(NAN);
  trig->cos_phi.setConstant(NAN);
}

// Input k of n over twice the range, centred on it (beyond the range the loop may not close):
// evenly spaced for one input, a golden-ratio sequence per input for several.
template <class M>
mechtest::VecQ<M> InputOverTwiceTheRange(int k, int n) {
  mechtest::VecQ<M> q;
  for (int j = 0; j < M::kNq; ++j) {
    const double lo = M::kQMin[j], hi = M::kQMax[j], span = hi - lo;
    const double u = M::kNq == 1 ? double(k) / (n - 1) : std::fmod(0.6180339887498949 * (k + 1) * (j + 1), 1.0);
    q(j) = lo - 0.5 * span + 2 * span * u;
  }
  return q;
}

// |a - b| / max(1, |b|), the worst entry.
template <class A, class B>
double WorstRelative(const A& a, const B& b) {
  double worst = 0;
  for (int i = 0; i < a.rows(); ++i)
    for (int j = 0; j < a.cols(); ++j)
      worst = std::max(worst, std::abs(a(i, j) - b(i, j)) / std::max(1.0, std::abs(b(i, j))));
  return worst;
}

TYPED_TEST(SolveTrigTest, DirectionCosinesOfTheAssemblyBranch) {
  using M = TypeParam;
  if constexpr (!HasSolveTrig<M>::value) {
    GTEST_SKIP() << "no SolveTrig (Newton blocks, displacements or a raw angle downstream)";
  } else {
    const mechtest::ParamsD<M> p;
    const auto configs = mechtest::SweepConfigs<M>(p, M::kNq == 1 ? 360 : 12);
    ASSERT_FALSE(configs.empty());
    for (const auto& c : configs) {
      typename M::template TrigT<double> trig;
      Poison(&trig);
      const auto report = M::SolveTrig(p, c.q, M::kDefaultModes, &trig);
      ASSERT_EQ(static_cast<int>(report.status), 0) << "q = " << c.q.transpose();
      for (int j = 0; j < M::kNq; ++j) {
        if (!M::kQIsAngle[j]) continue;
        EXPECT_EQ(trig.sin_q(j), std::sin(c.q(j)));
        EXPECT_EQ(trig.cos_q(j), std::cos(c.q(j)));
      }
      for (int i = 0; i < M::kNphi; ++i) {
        EXPECT_NEAR(trig.sin_phi(i), std::sin(c.phi(i)), 1e-11) << M::kPhiNames[i] << " q = " << c.q.transpose();
        EXPECT_NEAR(trig.cos_phi(i), std::cos(c.phi(i)), 1e-11) << M::kPhiNames[i] << " q = " << c.q.transpose();
      }
      // Given trig, EvalCoefficients does not read phi: NaNs there change nothing.
      mechtest::VecPhi<M> nan_phi;
      nan_phi.setConstant(NAN);
      mechtest::CoeffsD<M> with, without;
      M::Coeffs(p, c.q, nan_phi, &with, &trig);
      M::Coeffs(p, c.q, c.phi, &without);
      constexpr double kTol = 1e-9;
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
}

TYPED_TEST(SolveTrigTest, SameStatusesAsSolvePositionsOnEveryMode) {
  using M = TypeParam;
  if constexpr (!HasSolveTrig<M>::value) {
    GTEST_SKIP() << "no SolveTrig";
  } else {
    const mechtest::ParamsD<M> p;
    constexpr int kBlocks = M::kNumBlocks;
    int converged = 0, failed = 0;
    for (int combo = 0; combo < (1 << kBlocks); ++combo) {
      std::array<int, kBlocks> modes;
      for (int b = 0; b < kBlocks; ++b) modes[b] = (combo >> b) & 1 ? -1 : 1;
      const int n = M::kNq == 1 ? 400 : 40;
      for (int k = 0; k < n; ++k) {
        const mechtest::VecQ<M> q = InputOverTwiceTheRange<M>(k, n);
        mechtest::VecPhi<M> phi;
        for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
        typename M::template TrigT<double> trig, trig_positions;
        Poison(&trig);
        const auto expected = M::Solve(p, q, &phi, modes, 20, 0.0, &trig_positions);
        const auto report = M::SolveTrig(p, q, modes, &trig);
        ASSERT_EQ(static_cast<int>(report.status), static_cast<int>(expected.status)) << "q = " << q.transpose();
        EXPECT_EQ(report.block, expected.block);
        if (expected.status != decltype(expected.status)::kConverged) {
          // Later blocks read the earlier angles' direction cosines (not sin/cos of atan2).
          EXPECT_NEAR(report.measure, expected.measure, 1e-9 * std::max(1.0, std::abs(expected.measure)))
              << "q = " << q.transpose();
          ++failed;
          continue;
        }
        ++converged;
        EXPECT_NEAR(report.branch_measure, expected.branch_measure, 1e-12);
        EXPECT_EQ(report.branch_block, expected.branch_block);
        for (int i = 0; i < M::kNphi; ++i) {
          ASSERT_TRUE(std::isfinite(trig.sin_phi(i)) && std::isfinite(trig.cos_phi(i)));
          EXPECT_NEAR(trig.sin_phi(i), std::sin(phi(i)), 1e-11) << M::kPhiNames[i] << " q = " << q.transpose();
          EXPECT_NEAR(trig.cos_phi(i), std::cos(phi(i)), 1e-11) << M::kPhiNames[i] << " q = " << q.transpose();
        }
      }
    }
    EXPECT_GT(converged, 0);
    this->RecordProperty("converged", converged);
    this->RecordProperty("failed", failed);
  }
}

// The one-pass kinematics (Model::Kinematics = EvalKinematics), where the model has it: on
// every mode combination and over twice the input range, the same report as SolveTrig (status,
// block, measure, branch_measure, branch_block); where it converges, the same direction cosines
// as SolveTrig's, and K, L, Phi_phi as EvalCoefficients gives them from those cosines (with a
// phi of NaNs: the one pass reads no angle either). The oracles of its values are elsewhere
// (finite_difference_test.cc, paul_fourbar_test.cc); this is its contract with SolveTrig.
TYPED_TEST(SolveTrigTest, OnePassKinematicsReportsAsSolveTrigOnEveryMode) {
  using M = TypeParam;
  if constexpr (!M::kHasKinematics) {
    GTEST_SKIP() << "no EvalKinematics";
  } else {
    static_assert(HasSolveTrig<M>::value, "EvalKinematics exists only where SolveTrig does");
    const mechtest::ParamsD<M> p;
    constexpr int kBlocks = M::kNumBlocks;
    int converged = 0, failed = 0;
    // The same closed forms, compiled inline here and out of line in the model's library: equal
    // up to the compiler's contraction of products and sums (a few ulps).
    constexpr double kSame = 1e-13;
    for (int combo = 0; combo < (1 << kBlocks); ++combo) {
      std::array<int, kBlocks> modes;
      for (int b = 0; b < kBlocks; ++b) modes[b] = (combo >> b) & 1 ? -1 : 1;
      const int n = M::kNq == 1 ? 200 : 30;
      for (int k = 0; k < n; ++k) {
        const mechtest::VecQ<M> q = InputOverTwiceTheRange<M>(k, n);
        typename M::template TrigT<double> trig, trig_solve;
        typename M::template KinematicsT<double> kin;
        Poison(&trig);
        const auto expected = M::SolveTrig(p, q, modes, &trig_solve);
        const auto report = M::Kinematics(p, q, modes, &trig, &kin);
        ASSERT_EQ(static_cast<int>(report.status), static_cast<int>(expected.status)) << "q = " << q.transpose();
        EXPECT_EQ(report.block, expected.block);
        EXPECT_EQ(report.iterations, expected.iterations);
        if (expected.status != decltype(expected.status)::kConverged) {
          EXPECT_NEAR(report.measure, expected.measure, kSame * std::max(1.0, std::abs(expected.measure))) << "q = " << q.transpose();
          ++failed;
          continue;
        }
        ++converged;
        EXPECT_NEAR(report.branch_measure, expected.branch_measure, kSame);
        EXPECT_EQ(report.branch_block, expected.branch_block);
        for (int i = 0; i < M::kNphi; ++i) {
          EXPECT_NEAR(trig.sin_phi(i), trig_solve.sin_phi(i), kSame) << M::kPhiNames[i] << " q = " << q.transpose();
          EXPECT_NEAR(trig.cos_phi(i), trig_solve.cos_phi(i), kSame) << M::kPhiNames[i] << " q = " << q.transpose();
        }
        for (int j = 0; j < M::kNq; ++j) {
          if (!M::kQIsAngle[j]) continue;
          EXPECT_NEAR(trig.sin_q(j), trig_solve.sin_q(j), kSame);
          EXPECT_NEAR(trig.cos_q(j), trig_solve.cos_q(j), kSame);
        }
        mechtest::VecPhi<M> nan_phi;
        nan_phi.setConstant(NAN);
        mechtest::CoeffsD<M> c;
        M::Coeffs(p, q, nan_phi, &c, &trig_solve);
        constexpr double kTol = 1e-12;
        EXPECT_LT(WorstRelative(kin.Phi_phi, c.Phi_phi), kTol) << "q = " << q.transpose();
        EXPECT_LT(WorstRelative(kin.K, c.K), kTol) << "q = " << q.transpose();
        if constexpr (M::kHasL) {
          EXPECT_LT(WorstRelative(kin.L, c.L), kTol) << "q = " << q.transpose();
        }
      }
    }
    EXPECT_GT(converged, 0);
    this->RecordProperty("converged", converged);
    this->RecordProperty("failed", failed);
  }
}

// What the one-pass functions promise: finite values whenever they say kConverged, for any
// parameters and inputs. Each parameter in turn, then every parameter at once, is set to
// hostile values, at an input inside the range and at hostile inputs; then every parameter is
// scaled by factors inside and beyond the RRR dyad's range of lengths.
TYPED_TEST(SolveTrigTest, HostileParametersAndInputsNeverConvergeToNonFiniteValues) {
  using M = TypeParam;
  if constexpr (!HasSolveTrig<M>::value) {
    GTEST_SKIP() << "no SolveTrig";
  } else {
    using Params = mechtest::ParamsD<M>;
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const double bad[] = {NAN, kInf, -kInf, 0.0, -1.0, 1e300, -1e300, 1e150, 1e70, 1e-70, 1e-150, 1e-300,
                          std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::max()};
    int converged = 0, calls = 0;
    auto check = [&](const Params& p, const mechtest::VecQ<M>& q, const std::string& what) {
      typename M::template TrigT<double> trig;
      Poison(&trig);
      const auto report = M::SolveTrig(p, q, M::kDefaultModes, &trig);
      ++calls;
      if (report.status == decltype(report.status)::kConverged) {
        ++converged;
        EXPECT_TRUE(trig.sin_phi.allFinite() && trig.cos_phi.allFinite()) << what << ": SolveTrig converged with "
                                                                          << trig.cos_phi.transpose();
        EXPECT_TRUE(report.branch_measure >= 0 && report.branch_measure <= 1) << what;
      }
      if constexpr (M::kHasKinematics) {
        typename M::template KinematicsT<double> kin;
        Poison(&trig);
        const auto k = M::Kinematics(p, q, M::kDefaultModes, &trig, &kin);
        EXPECT_EQ(static_cast<int>(k.status), static_cast<int>(report.status)) << what;
        if (k.status == decltype(k.status)::kConverged) {
          EXPECT_TRUE(trig.sin_phi.allFinite() && trig.cos_phi.allFinite() && kin.Phi_phi.allFinite())
              << what << ": Kinematics converged with " << trig.cos_phi.transpose();
        }
      }
    };
    const mechtest::VecQ<M> q0 = InputOverTwiceTheRange<M>(1, 4);
    for (const char* name : Params::kNames) {
      for (const double x : bad) {
        Params p;
        *p.Find(name) = x;
        const std::string what = std::string(name) + " = " + std::to_string(x);
        check(p, q0, what);
        for (int j = 0; j < M::kNq; ++j) {
          mechtest::VecQ<M> q = q0;
          q(j) = x;
          check(p, q, what + ", q(" + std::to_string(j) + ") = " + std::to_string(x));
        }
      }
    }
    for (const double x : bad) {
      Params p;
      for (const char* name : Params::kNames) *p.Find(name) = x;
      check(p, q0, std::string("every parameter = ") + std::to_string(x));
    }
    for (const double scale : {1e-80, 1e-69, 1e-68, 1e-60, 1e60, 1e68, 1e69, 1e80}) {
      Params p, defaults;
      for (const char* name : Params::kNames) *p.Find(name) = *defaults.Find(name) * scale;
      check(p, q0, "every parameter x " + std::to_string(scale));
    }
    this->RecordProperty("converged", converged);
    this->RecordProperty("calls", calls);
  }
}

// The RRR dyad's range of lengths (1e-69 .. 1e69 for double: squared lengths within
// [norm2_min, norm2_max]): Paul's four-bar in other units is the same mechanism inside it (the
// same direction cosines, K and L, which are ratios of lengths: scaled by nothing), and is
// refused as singular, with the offending squared length, beyond it.
TEST(SolveTrigRange, FourBarInOtherUnitsIsTheSameInsideTheRangeAndRefusedBeyondIt) {
  using M = mech::fourbar::Model;
  const mechtest::ParamsD<M> unit;
  const mechtest::VecQ<M> q = mechtest::VecQ<M>::Constant(0.7);
  M::TrigT<double> trig0, trig;
  M::KinematicsT<double> kin0, kin;
  ASSERT_EQ(static_cast<int>(M::Kinematics(unit, q, M::kDefaultModes, &trig0, &kin0).status), 0);
  for (const double scale : {1e-66, 1e-60, 1e-30, 1e30, 1e60, 1e66}) {
    mechtest::ParamsD<M> p;
    for (double* x : {&p.a, &p.b, &p.c, &p.d, &p.xi, &p.eta}) *x *= scale;
    const auto report = M::Kinematics(p, q, M::kDefaultModes, &trig, &kin);
    ASSERT_EQ(static_cast<int>(report.status), 0) << "lengths x " << scale;
    EXPECT_NEAR(report.branch_measure, M::Kinematics(unit, q, M::kDefaultModes, &trig0, &kin0).branch_measure, 1e-12);
    EXPECT_LT(WorstRelative(trig.cos_phi, trig0.cos_phi), 1e-13) << scale;
    EXPECT_LT(WorstRelative(trig.sin_phi, trig0.sin_phi), 1e-13) << scale;
    EXPECT_LT(WorstRelative(kin.K, kin0.K), 1e-13) << scale;               // dimensionless
    EXPECT_LT(WorstRelative(kin.L, kin0.L), 1e-13) << scale;               // L of angles: too
  }
  for (const double scale : {1e-72, 1e72}) {
    mechtest::ParamsD<M> p;
    for (double* x : {&p.a, &p.b, &p.c, &p.d, &p.xi, &p.eta}) *x *= scale;
    const auto report = M::SolveTrig(p, q, M::kDefaultModes, &trig);
    EXPECT_EQ(report.status, mech::fourbar::SolveStatus::kSingular) << "lengths x " << scale;
    EXPECT_TRUE(report.measure == p.b * p.b || report.measure == p.c * p.c) << report.measure;
  }
}

}  // namespace
