// The generated one-pass right-hand side (EvalRhs = Model::Rhs, with its constants from
// Model::Prepare) of models/fourbar_massive.yaml, against the hand derivation of the same
// machine (handwritten_fourbar_dynamics.h: Paul's K and L, I = sum m |K_G|^2 + J K^2 and its
// derivative written out), over a turn of the crank in both assembly modes; its statuses
// against SolvePositionsTrig on a four-bar that does not assemble everywhere; and the
// constants' contract (they carry the parameters: prepared again after a change, and the
// runtime's MinimalDynamics does so by itself).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "damped_fourbar.h"
#include "fivebar_locked_fourbar.h"
#include "fivebar_massive.h"
#include "fivebar_robot.h"
#include "fivebar_spring_damper.h"
#include "fourbar_massive.h"
#include "handwritten_fourbar_dynamics.h"
#include "mechgen/dynamics/forward.h"
#include "published_andrews.h"
#include "published_double_pendulum.h"

namespace {

using M = mech::fourbar_massive::Model;
namespace hw = mech::handwritten_fourbar_dynamics;
using Vec1 = Eigen::Matrix<double, 1, 1>;
using Vec2 = Eigen::Matrix<double, 2, 1>;
constexpr double kPi = 3.14159265358979323846;

static_assert(mechgen::dynamics::MinimalDynamics<M>::kStagesByRhs,
              "the stages of the minimal method use Model::Rhs where it is generated");

struct Hand {
  bool ok = false;
  hw::Trig<double> trig;
  hw::Coefficients<double> c;
  hw::Dynamics<double> d;
};

hw::Params<double> HandParams(const M::ParamsT<double>& p) {
  hw::Params<double> h;
  h.a = p.a;
  h.b = p.b;
  h.c = p.c;
  h.d = p.d;
  h.rho = p.rho;
  h.g = p.g;
  return h;
}

Hand HandAt(const hw::Params<double>& p, double q, double qd, int mode) {
  Hand h;
  Vec2 phi(1.0, 1.5);
  const auto report = hw::SolvePositions(p, Vec1(q), &phi, {mode}, 20, 0.0, &h.trig);
  if (report.status != hw::SolveStatus::kConverged) return h;
  hw::EvalCoefficients(p, Vec1(q), phi, &h.c, &h.trig);
  hw::EvalDynamics(p, Vec1(q), phi, Vec1(qd), 0.0, h.c, &h.d, nullptr, &h.trig);
  h.ok = true;
  return h;
}

void ExpectSame(const M::RhsT<double>& r, const M::TrigT<double>& trig, const Hand& h, const std::string& at) {
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(trig.cos_phi(i), h.trig.cos_phi(i), 1e-13) << at;
    EXPECT_NEAR(trig.sin_phi(i), h.trig.sin_phi(i), 1e-13) << at;
    EXPECT_NEAR(r.K(i, 0), h.c.K(i), 1e-11 * (1 + std::abs(h.c.K(i)))) << at;
    for (int j = 0; j < 2; ++j) EXPECT_NEAR(r.Phi_phi(i, j), h.c.Phi_phi(i, j), 1e-13) << at;
  }
  const double scale = 1 + std::abs(h.d.I(0, 0));
  EXPECT_NEAR(r.I(0, 0), h.d.I(0, 0), 1e-12 * scale) << at;
  EXPECT_NEAR(r.h(0), h.d.h(0), 1e-11 * (1 + std::abs(h.d.h(0)))) << at;
  EXPECT_NEAR(r.Q(0), h.d.Q(0), 1e-11 * (1 + std::abs(h.d.Q(0)))) << at;
  EXPECT_NEAR(r.T, h.d.T, 1e-12 * (1 + std::abs(h.d.T))) << at;
  EXPECT_NEAR(r.V, h.d.V, 1e-11 * (1 + std::abs(h.d.V))) << at;
  EXPECT_EQ(r.P_nc, 0.0) << at;  // conservative
}

TEST(GeneratedRhs, FourBarMatchesTheHandDerivationOverATurnInBothModes) {
  M::ParamsT<double> p;
  M::RhsConstantsT<double> rc;
  M::Prepare(p, &rc);
  const hw::Params<double> hp = HandParams(p);
  for (int mode : {M::kDefaultModes[0], -M::kDefaultModes[0]}) {
    for (int i = 0; i < 720; ++i) {
      const double q = i * kPi / 360, qd = 2.5 - i * 0.007;
      M::TrigT<double> trig;
      M::RhsT<double> r;
      const auto report = M::Rhs(p, rc, Vec1(q), Vec1(qd), 0.0, {mode}, &trig, &r);
      // The model's default mode is the open assembly, the hand derivation's +1.
      const Hand h = HandAt(hp, q, qd, mode * M::kDefaultModes[0]);
      ASSERT_TRUE(h.ok);
      ASSERT_EQ(report.status, mech::fourbar_massive::SolveStatus::kConverged) << q;
      ExpectSame(r, trig, h, "q = " + std::to_string(q) + ", mode " + std::to_string(mode));
    }
  }
}

TEST(GeneratedRhs, SameStatusesAndBranchMeasureAsSolvePositionsTrig) {
  // b = 1.5: a non-Grashof four-bar (1 + 4 > 1.5 + 3) that does not assemble near q = pi.
  M::ParamsT<double> p;
  p.b = 1.5;
  M::RhsConstantsT<double> rc;
  M::Prepare(p, &rc);
  const hw::Params<double> hp = HandParams(p);
  int refused = 0, solved = 0;
  for (int i = 0; i < 720; ++i) {
    const double q = i * kPi / 360;
    M::TrigT<double> trig, trig_solve;
    M::RhsT<double> r;
    const auto report = M::Rhs(p, rc, Vec1(q), Vec1(1.0), 0.0, M::kDefaultModes, &trig, &r);
    const auto solve = M::SolveTrig(p, Vec1(q), M::kDefaultModes, &trig_solve);
    EXPECT_EQ(report.status, solve.status) << q;
    EXPECT_EQ(report.block, solve.block) << q;
    const Hand h = HandAt(hp, q, 1.0, 1);
    EXPECT_EQ(report.status == mech::fourbar_massive::SolveStatus::kConverged, h.ok) << q;
    if (report.status != mech::fourbar_massive::SolveStatus::kConverged) {
      EXPECT_EQ(report.status, mech::fourbar_massive::SolveStatus::kNotAssemblable) << q;
      EXPECT_LT(report.measure, 0.0) << q;  // the negative discriminant
      ++refused;
      continue;
    }
    ++solved;
    EXPECT_NEAR(report.branch_measure, solve.branch_measure, 1e-14) << q;
    EXPECT_EQ(report.branch_block, solve.branch_block) << q;
    ExpectSame(r, trig, h, "q = " + std::to_string(q));
  }
  EXPECT_GT(refused, 10);
  EXPECT_GT(solved, 10);
}

TEST(GeneratedRhs, TheConstantsCarryTheParameters) {
  M::ParamsT<double> p;
  M::RhsConstantsT<double> stale;
  M::Prepare(p, &stale);
  p.b = 3.2;
  p.rho = 2.7;
  p.g = 3.71;
  M::RhsConstantsT<double> rc;
  M::Prepare(p, &rc);
  const hw::Params<double> hp = HandParams(p);
  const double q = 0.7, qd = -1.9;
  M::TrigT<double> trig;
  M::RhsT<double> r, r_stale;
  ASSERT_EQ(M::Rhs(p, rc, Vec1(q), Vec1(qd), 0.0, M::kDefaultModes, &trig, &r).status,
            mech::fourbar_massive::SolveStatus::kConverged);
  ExpectSame(r, trig, HandAt(hp, q, qd, 1), "new parameters");
  // With the constants of the old parameters the inertia is not the new machine's: the
  // constants are part of the contract (EvalRhs' documentation says so).
  M::Rhs(p, stale, Vec1(q), Vec1(qd), 0.0, M::kDefaultModes, &trig, &r_stale);
  EXPECT_GT(std::abs(r_stale.I(0, 0) - r.I(0, 0)), 1e-3 * std::abs(r.I(0, 0)));
}

TEST(GeneratedRhs, MinimalDynamicsPreparesTheConstantsAgainAfterAParameterChange) {
  using Sim = mechgen::dynamics::MinimalDynamics<M>;
  Sim sim{Sim::Params()};
  ASSERT_TRUE(sim.Initialize(Sim::VecQ::Constant(kPi / 2)));
  sim.mutable_params()->rho = 3.3;
  sim.mutable_params()->g = 1.62;
  Sim::State y, dy;
  y << 1.1, 0.8, 0.0;
  ASSERT_TRUE(sim.Derivative(0.0, y, &dy));
  const Hand h = HandAt(HandParams(sim.params()), 1.1, 0.8, 1);
  ASSERT_TRUE(h.ok);
  const double qdd = (h.d.Q(0) - h.d.h(0)) / h.d.I(0, 0);
  EXPECT_NEAR(dy(1), qdd, 1e-11 * (1 + std::abs(qdd)));
}

template <class Model>
class RhsAgainstGeneralFunctions : public ::testing::Test {};
using RhsModels = ::testing::Types<mech::fourbar_massive::Model,
                                   mech::damped_fourbar::Model,
                                   mech::fivebar_massive::Model,
                                   mech::fivebar_robot::Model,
                                   mech::fivebar_spring_damper::Model,
                                   mech::fivebar_locked_fourbar::Model,
                                   mech::published_andrews::Model,
                                   mech::published_double_pendulum::Model>;
TYPED_TEST_SUITE(RhsAgainstGeneralFunctions, RhsModels);

TYPED_TEST(RhsAgainstGeneralFunctions, SameEquationOfMotionNearTheAssembly) {
  using Mo = TypeParam;
  constexpr int nq = Mo::kNq, nphi = Mo::kNphi;
  using VQ = Eigen::Matrix<double, nq, 1>;
  typename Mo::template ParamsT<double> p;
  typename Mo::template RhsConstantsT<double> rc;
  Mo::Prepare(p, &rc);
  Eigen::Matrix<double, nphi, 1> phi;
  for (int i = 0; i < nphi; ++i) phi(i) = Mo::kAssemblyPhi[i];
  int compared = 0;
  for (int k = 0; k <= 40; ++k) {
    VQ q, qd;
    for (int j = 0; j < nq; ++j) {
      q(j) = Mo::kAssemblyQ[j] + 0.004 * k * (j % 2 == 0 ? 1.0 : -0.7);
      qd(j) = 0.9 - 0.6 * j + 0.05 * k;
    }
    const double t = 0.01 * k;
    typename Mo::template TrigT<double> trig, trig_rhs;
    const auto solved = Mo::Solve(p, q, &phi, Mo::kDefaultModes, 50, 0.0, &trig);
    if (solved.status != decltype(solved.status)::kConverged) continue;
    typename Mo::template CoefficientsT<double> c;
    typename Mo::template DynamicsT<double> d;
    Mo::Coeffs(p, q, phi, &c, &trig);
    Mo::Dynamics(p, q, phi, qd, t, c, &d, nullptr, &trig);
    // Every member compared below starts as NaN: Rhs must write each one (and the compiler
    // sees no read of an unset value).
    typename Mo::template RhsT<double> r;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    r.I.setConstant(nan);
    r.h.setConstant(nan);
    r.Q.setConstant(nan);
    r.K.setConstant(nan);
    r.Phi_phi.setConstant(nan);
    r.T = r.V = r.P_nc = nan;
    const auto report = Mo::Rhs(p, rc, q, qd, t, Mo::kDefaultModes, &trig_rhs, &r);
    ASSERT_EQ(report.status, solved.status) << k;
    ++compared;
    auto near = [&](double a, double b, const char* what) {
      EXPECT_NEAR(a, b, 1e-10 * (1 + std::abs(b))) << what << " at step " << k;
    };
    for (int i = 0; i < nq; ++i) {
      for (int j = 0; j < nq; ++j) near(r.I(i, j), d.I(i, j), "I");
      near(r.h(i), d.h(i), "h");
      near(r.Q(i), d.Q(i), "Q");
      for (int a = 0; a < nphi; ++a) near(r.K(a, i), c.K(a, i), "K");
    }
    near(r.T, d.T, "T");
    near(r.V, d.V, "V");
    near(r.P_nc, d.P_nc, "P_nc");
    for (int a = 0; a < nphi; ++a)
      for (int b = 0; b < nphi; ++b) near(r.Phi_phi(a, b), c.Phi_phi(a, b), "Phi_phi");
  }
  EXPECT_GT(compared, 30);
}

}  // namespace
