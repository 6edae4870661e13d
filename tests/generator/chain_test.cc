// The N-chain scaling model (tools/make_chain.sh): the block-ordered emission (closed-form
// dyads, K and L by forward substitution) against the monolithic one (one Newton solve
// and one dense LU over all loops) — two independent code paths from the same Phi — over
// a full input turn: same positions, K and L; loops closed; the solve order is one RRR
// dyad per loop, in loop order.
#include <gtest/gtest.h>

#include <cmath>

#include "chain_8.h"
#include "chain_8_monolithic.h"

namespace {

using Blocks = mech::chain_8::Model;
using Mono = mech::chain_8_monolithic::Model;

TEST(Chain8, OneClosedFormDyadPerLoopInLoopOrder) {
  ASSERT_EQ(Blocks::kNumBlocks, 8);
  for (int b = 0; b < Blocks::kNumBlocks; ++b) EXPECT_TRUE(Blocks::kBlockClosedForm[b]);
  ASSERT_EQ(Mono::kNumBlocks, 1);
  EXPECT_FALSE(Mono::kBlockClosedForm[0]);
}

TEST(Chain8, BlockOrderedAndMonolithicAgreeOverAFullTurn) {
  const Blocks::ParamsT<double> pb;
  const Mono::ParamsT<double> pm;
  Eigen::Matrix<double, 1, 1> q;
  Eigen::Matrix<double, 16, 1> phi_b, phi_m;
  for (int i = 0; i < 16; ++i) phi_b(i) = phi_m(i) = Blocks::kAssemblyPhi[i];
  q(0) = Blocks::kAssemblyQ[0];
  // The monolithic Newton needs a start near the branch: take the closed form's first.
  ASSERT_EQ(static_cast<int>(Blocks::Solve(pb, q, &phi_b).status), 0);
  phi_m = phi_b;
  const int steps = 360;
  for (int s = 0; s <= steps; ++s) {
    q(0) = 2 * M_PI * s / steps;
    const auto rb = Blocks::Solve(pb, q, &phi_b);
    const auto rm = Mono::Solve(pm, q, &phi_m);
    ASSERT_EQ(static_cast<int>(rb.status), 0) << "step " << s << " block " << rb.block;
    ASSERT_EQ(static_cast<int>(rm.status), 0) << "step " << s << " measure " << rm.measure;
    Eigen::Matrix<double, 16, 1> Phi;
    Blocks::Phi(pb, q, phi_b, &Phi);
    EXPECT_LT(Phi.cwiseAbs().maxCoeff(), 1e-12) << "step " << s;
    // Newton stops at |Phi| <= 1e-12; cond(Phi_phi) of the chain is O(10), so positions
    // agree to ~1e-11.
    for (int i = 0; i < 16; ++i) ASSERT_NEAR(phi_b(i), phi_m(i), 1e-10) << Blocks::kPhiNames[i] << " step " << s;
    mech::chain_8::Coefficients<double> cb;
    mech::chain_8_monolithic::Coefficients<double> cm;
    Blocks::Coeffs(pb, q, phi_b, &cb);
    Mono::Coeffs(pm, q, phi_b, &cm);  // same configuration: compares the two K/L paths alone
    for (int i = 0; i < 16; ++i) {
      EXPECT_NEAR(cb.K(i, 0), cm.K(i, 0), 1e-11 * (1 + std::abs(cm.K(i, 0)))) << "K " << Blocks::kPhiNames[i];
      EXPECT_NEAR(cb.L(i, 0), cm.L(i, 0), 1e-10 * (1 + std::abs(cm.L(i, 0)))) << "L " << Blocks::kPhiNames[i];
    }
    EXPECT_NEAR(cb.r_P(0, 0), cm.r_P(0, 0), 1e-12);
    EXPECT_NEAR(cb.L_P(1, 0), cm.L_P(1, 0), 1e-9 * (1 + std::abs(cm.L_P(1, 0))));
  }
}

TEST(Chain8, DetPhiPhiIsTheProductOfTheLoopDeterminants) {
  const Blocks::ParamsT<double> pb;
  const Mono::ParamsT<double> pm;
  Eigen::Matrix<double, 1, 1> q(0.3);
  Eigen::Matrix<double, 16, 1> phi;
  for (int i = 0; i < 16; ++i) phi(i) = Blocks::kAssemblyPhi[i];
  ASSERT_EQ(static_cast<int>(Blocks::Solve(pb, q, &phi).status), 0);
  double det_b = 0, det_m = 0;
  Blocks::DetPhiPhi(pb, q, phi, &det_b);
  Mono::DetPhiPhi(pm, q, phi, &det_m);
  Eigen::Matrix<double, 16, 1> Phi;
  Eigen::Matrix<double, 16, 16> J;
  Blocks::Phi(pb, q, phi, &Phi, &J);
  const double dense = J.determinant();
  EXPECT_NEAR(det_b, dense, 1e-9 * std::abs(dense));
  EXPECT_NEAR(det_m, dense, 1e-9 * std::abs(dense));
}

}  // namespace
