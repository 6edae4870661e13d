// The generated position solver (SolvePositions): block by block, closed-form dyads and
// Newton blocks. Checked against an independent full Newton–Raphson on the generated Phi
// (the oracle path: only Phi and Phi_phi, solved densely), over each model's input range:
// the loops close, the default mode is the model's assembly (continuous, no branch jump),
// the other mode is a different closed configuration, and an unreachable input is reported.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>

#include "fivebar.h"
#include "fourbar.h"
#include "fourbar_crossed.h"
#include "inverted_slider_crank.h"
#include "slider_crank.h"

namespace {

template <class M>
using VecQ = Eigen::Matrix<double, M::kNq, 1>;
template <class M>
using VecPhi = Eigen::Matrix<double, M::kNphi, 1>;

// Dense Newton on the whole system from `phi`; returns false if it does not converge.
template <class M>
bool DenseNewton(const typename M::template ParamsT<double>& p, const VecQ<M>& q, VecPhi<M>* phi) {
  Eigen::Matrix<double, M::kNc, 1> Phi;
  Eigen::Matrix<double, M::kNc, M::kNphi> J;
  for (int it = 0; it < 50; ++it) {
    M::Phi(p, q, *phi, &Phi, &J);
    if (Phi.cwiseAbs().maxCoeff() < 1e-14) return true;
    *phi -= J.partialPivLu().solve(Phi);
  }
  return false;
}

template <class M>
class SolvePositionsTest : public ::testing::Test {};
using Models = ::testing::Types<mech::fourbar::Model, mech::fourbar_crossed::Model, mech::slider_crank::Model,
                                mech::inverted_slider_crank::Model, mech::fivebar::Model>;
TYPED_TEST_SUITE(SolvePositionsTest, Models);

TYPED_TEST(SolvePositionsTest, MatchesDenseNewtonOverTheRangeWithoutJumps) {
  using M = TypeParam;
  const typename M::template ParamsT<double> p;
  VecQ<M> q;
  VecPhi<M> phi, previous;
  for (int i = 0; i < M::kNq; ++i) q(i) = M::kAssemblyQ[i];
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  // Assemble at the model's configuration with the dense oracle, then compare.
  VecPhi<M> oracle = phi;
  ASSERT_TRUE(DenseNewton<M>(p, q, &oracle));
  auto report = M::Solve(p, q, &phi);
  ASSERT_EQ(static_cast<int>(report.status), 0) << "block " << report.block;
  for (int i = 0; i < M::kNphi; ++i) EXPECT_NEAR(phi(i), oracle(i), 1e-11) << M::kPhiNames[i];

  // Sweep the first input over its range (the others at their assembly values) in small
  // steps; 1e-11 is ~100 ulps of the link lengths, what a dense Newton converges to.
  const int steps = 720;
  for (int s = 0; s <= steps; ++s) {
    q(0) = M::kQMin[0] + (M::kQMax[0] - M::kQMin[0]) * s / steps;
    previous = phi;
    report = M::Solve(p, q, &phi);
    ASSERT_EQ(static_cast<int>(report.status), 0) << "step " << s << " block " << report.block;
    Eigen::Matrix<double, M::kNc, 1> Phi;
    M::Phi(p, q, phi, &Phi);
    EXPECT_LT(Phi.cwiseAbs().maxCoeff(), 1e-12) << "step " << s;
    VecPhi<M> from_previous = previous;
    ASSERT_TRUE(DenseNewton<M>(p, q, &from_previous)) << "step " << s;
    for (int i = 0; i < M::kNphi; ++i)
      ASSERT_NEAR(phi(i), from_previous(i), 1e-10) << M::kPhiNames[i] << " at step " << s
                                                   << ": the closed form left the branch Newton follows";
  }
}

TYPED_TEST(SolvePositionsTest, OtherModesGiveOtherClosedConfigurations) {
  using M = TypeParam;
  const typename M::template ParamsT<double> p;
  VecQ<M> q;
  VecPhi<M> phi, other;
  for (int i = 0; i < M::kNq; ++i) q(i) = M::kAssemblyQ[i];
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  other = phi;
  ASSERT_EQ(static_cast<int>(M::Solve(p, q, &phi).status), 0);
  for (int b = 0; b < M::kNumBlocks; ++b) {
    if (!M::kBlockClosedForm[b]) continue;
    auto modes = M::kDefaultModes;
    modes[b] = -modes[b];
    VecPhi<M> flipped = other;
    if (static_cast<int>(M::Solve(p, q, &flipped, modes).status) != 0) continue;
    Eigen::Matrix<double, M::kNc, 1> Phi;
    M::Phi(p, q, flipped, &Phi);
    EXPECT_LT(Phi.cwiseAbs().maxCoeff(), 1e-12);
    // A linear block has one solution: flipping its mode changes nothing.
    double change = 0;
    for (int i = 0; i < M::kNphi; ++i) change = std::max(change, std::abs(flipped(i) - phi(i)));
    double det = 0, det_other = 0;
    M::DetPhiPhi(p, q, phi, &det);
    M::DetPhiPhi(p, q, flipped, &det_other);
    if (change > 1e-6) {
      EXPECT_LT(det * det_other, 0) << "the other mode of block " << b << " is the other branch";
    }
  }
}

TEST(SolvePositions, FourBarReportsAnUnreachableInput) {
  // A crank of 3.2 cannot turn fully with coupler 3.5, rocker 3, ground 4: at theta = 180
  // deg, |DB| = 7.2 > b + c = 6.5, so the circles of the RRR dyad do not meet.
  using M = mech::fourbar::Model;
  M::ParamsT<double> p;
  p.a = 3.2;
  Eigen::Matrix<double, 1, 1> q(M_PI);
  Eigen::Matrix<double, 2, 1> phi(0.5, 1.5);
  const Eigen::Matrix<double, 2, 1> before = phi;
  const auto report = M::Solve(p, q, &phi);
  EXPECT_EQ(report.status, mech::fourbar::SolveStatus::kNotAssemblable);
  EXPECT_EQ(report.block, 0);
  EXPECT_LT(report.measure, 0.0);
  EXPECT_EQ(phi, before) << "a failed solve must leave phi as it was";
}

TEST(SolvePositions, DetPhiPhiMatchesTheDenseDeterminant) {
  using M = mech::fivebar::Model;
  const M::ParamsT<double> p;
  Eigen::Matrix<double, 2, 1> q(1.7, 1.2), phi(0.9, 1.8);
  ASSERT_EQ(static_cast<int>(M::Solve(p, q, &phi).status), 0);
  Eigen::Matrix<double, 2, 1> Phi;
  Eigen::Matrix<double, 2, 2> J;
  M::Phi(p, q, phi, &Phi, &J);
  Eigen::Matrix<double, 2, 2> J_alone;
  M::Phi(p, q, phi, nullptr, &J_alone);  // any output may be nullptr, the first one too
  EXPECT_EQ(J_alone, J);
  double det = 0;
  M::DetPhiPhi(p, q, phi, &det);
  EXPECT_NEAR(det, J.determinant(), 1e-12 * std::max(1.0, std::abs(det)));
}

}  // namespace
