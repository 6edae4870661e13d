// A published planar multibody benchmark of two degrees of freedom with reference values:
// the double pendulum of the Modelica PlanarMechanics library (DLR Institute of System
// Dynamics and Control), modelled in tests/dynamics/models/published_double_pendulum.yaml
// and simulated by mechgen's minimal method (MinimalDynamics on the generated model; the
// rods' absolute angles are the inputs through a massless parallelogram, see the model).
//
// Source of the problem: PlanarMechanics.Examples.DoublePendulum,
//   https://github.com/dzimmer/PlanarMechanics, PlanarMechanics/Examples/DoublePendulum.mo
//   (body m = 1, I = 0.1 at the end of FixedTranslation r = {1, 0}; body1 m = 0.2, I = 0.01 at
//   r = {0.4, 0} from the second revolute; both revolutes phi(start = 0), w(start = 0);
//   PlanarWorld's constantGravity = {0, -9.81}; PlanarMechanics/PlanarWorld.mo).
// Source of the reference values: https://github.com/DLR-SR/PlanarMechanics_ReferenceResults,
//   PlanarMechanics/Examples/DoublePendulum/DoublePendulum.csv at commit 97ce49c (2025-09-22,
//   "Reference results for v2.0.0-alpha"; creation.txt: Dymola 2025x Refresh 1, DASSL,
//   tolerance 1e-6, output interval 0.002 s). The earlier results of the same repository
//   (v1.6.0, commit 3649b83; 2020, ca15f06) agree with these to 4e-12 rad up to t = 5 s and
//   3e-9 rad at 10 s. The library's documentation warns that the system is chaotic after
//   10 s; the rows compared here are t = 1, 2, ..., 9 s and the first output row (0.002 s).
// Columns: revolute.phi (the first rod's angle from +x, CCW), revolute.w, revolute1.phi (the
// second rod's angle relative to the first), revolute1.w. mechgen's q = (theta_link1,
// theta_crank3) are absolute angles: revolute.phi = q0, revolute1.phi = q1 - q0.
// Oracles: (1) the hand-derived Lagrange equations integrated by a fixed-step RK4 in the test
// (tight: 1e-9); (2) the published values, to their own accuracy (DASSL at tolerance 1e-6:
// the hand oracle differs from them as much as mechgen does; tolerances and measured values
// in the test).
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "mechgen/dynamics/forward.h"
#include "published_double_pendulum.h"

namespace {

using Model = mech::published_double_pendulum::Model;
namespace dyn = mechgen::dynamics;

// t, revolute.phi, revolute.w, revolute1.phi, revolute1.w of DoublePendulum.csv (97ce49c).
constexpr double kRef[10][5] = {
    {0.002, -1.7910374471707118e-05, -0.017910373441303976, 1.4653942733643588e-05, 0.014653941888944495},
    {1, -2.7613153813542928, -2.3445692829950806, -0.67749356230552116, -0.42798749429177929},
    {2, -1.3213958185751349, 3.23389557262308, 0.57533615109683467, 8.0783175993635776},
    {3, -0.85889947338627792, -3.3322388149922948, 1.2446497335806987, -3.0490168957569321},
    {4, -3.0211333545735561, 1.2115603555413224, -0.40310243992877876, 0.66744506151163208},
    {5, -0.093953305608399429, 1.0854936334388805, 0.28698556465804592, 0.52096680581621713},
    {6, -2.3470892636149681, -3.2822702548615506, -1.1212209863772236, -1.8689463438436433},
    {7, -1.7960843806360347, 3.4530875459488883, -0.1419227214101651, 5.9923589637246462},
    {8, -0.38085646433700499, -2.5883135643905866, -0.045847490020660672, 1.1305524632566191},
    {9, -3.0679537192666806, 0.28694513222471923, -1.1807352830463202, -2.8006296224173619},
};

// The hand-derived equations of motion of the double pendulum in the absolute angles (a, b)
// of the rods (Lagrange, see InitialAccelerationsByHand), integrated by the classical
// Runge-Kutta method with a fixed step: an oracle independent of the generator and of the
// runtime's integrators (h = 1e-4 s; h = 2e-4 s gives the same values to 1e-12 up to 5 s).
std::array<double, 4> HandPendulum(const std::array<double, 4>& y) {
  const double m1 = 1, I1 = 0.1, m2 = 0.2, I2 = 0.01, l1 = 1, l2 = 0.4, g = 9.81;
  const double a = y[0], b = y[1], ad = y[2], bd = y[3];
  const double c = std::cos(a - b), s = std::sin(a - b);
  const double M11 = m1 * l1 * l1 + I1 + m2 * l1 * l1, M12 = m2 * l1 * l2 * c, M22 = m2 * l2 * l2 + I2;
  const double Q1 = -(m1 + m2) * g * l1 * std::cos(a) - m2 * l1 * l2 * s * bd * bd;
  const double Q2 = -m2 * g * l2 * std::cos(b) + m2 * l1 * l2 * s * ad * ad;
  const double det = M11 * M22 - M12 * M12;
  return {ad, bd, (M22 * Q1 - M12 * Q2) / det, (M11 * Q2 - M12 * Q1) / det};
}

TEST(PublishedDoublePendulum, MatchesThePlanarMechanicsReferenceResults) {
  dyn::MinimalOptions o;
  o.integrator.rtol = 1e-12;
  o.integrator.atol = 1e-12;
  o.sample_dt = 0.002;
  dyn::MinimalDynamics<Model, dyn::Dop853> sim(Model::ParamsT<double>(), o);
  const Eigen::Vector2d q0(0.0, 0.0), qd0(0.0, 0.0);
  ASSERT_TRUE(sim.Initialize(q0));
  int next = 0;
  double min_rcond = 1, E0 = 0;
  double got[10][4] = {};
  dyn::MinimalSummary summary;
  ASSERT_TRUE(sim.Simulate(0.0, q0, qd0, 9.0 + 1e-9,
                           [&](const dyn::Sample<Model>& s) {
                             if (s.t == 0.0) E0 = s.E;
                             // The parallelogram branch: link2 parallel to crank3, the coupler to link1.
                             EXPECT_NEAR(s.phi(0), s.q(1), 1e-9) << s.t;
                             EXPECT_NEAR(s.phi(1), s.q(0), 1e-9) << s.t;
                             min_rcond = std::min(min_rcond, s.rcond);
                             if (next < 10 && std::abs(s.t - kRef[next][0]) < 1e-9) {
                               got[next][0] = s.q(0);
                               got[next][1] = s.qd(0);
                               got[next][2] = s.q(1) - s.q(0);
                               got[next][3] = s.qd(1) - s.qd(0);
                               ++next;
                             }
                             return true;
                           },
                           &summary))
      << dyn::FormatSummary(summary);
  ASSERT_EQ(next, 10);
  EXPECT_LT(summary.max_energy_error, 1e-9 * std::max(1.0, std::abs(E0)));
  EXPECT_GT(min_rcond, 1e-3);  // the parallelogram's singular relative angle was not approached

  // (1) The hand-derived equations (RK4, h = 1e-4 s) at t = 1 .. 5 s: to 1e-9 (measured 1e-12).
  std::array<double, 4> y{0, 0, 0, 0};
  const double h = 1e-4;
  double worst_hand = 0;
  for (int second = 1; second <= 5; ++second) {
    for (int i = 0; i < 10000; ++i) {
      std::array<double, 4> k[4], z;
      k[0] = HandPendulum(y);
      for (int j = 0; j < 4; ++j) z[j] = y[j] + 0.5 * h * k[0][j];
      k[1] = HandPendulum(z);
      for (int j = 0; j < 4; ++j) z[j] = y[j] + 0.5 * h * k[1][j];
      k[2] = HandPendulum(z);
      for (int j = 0; j < 4; ++j) z[j] = y[j] + h * k[2][j];
      k[3] = HandPendulum(z);
      for (int j = 0; j < 4; ++j) y[j] += h / 6 * (k[0][j] + 2 * k[1][j] + 2 * k[2][j] + k[3][j]);
    }
    const double hand[4] = {y[0], y[2], y[1] - y[0], y[3] - y[2]};
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(got[second][c], hand[c], 1e-9) << "t = " << second << ", column " << c + 1;
      worst_hand = std::max(worst_hand, std::abs(got[second][c] - hand[c]));
    }
  }

  // (2) The published reference values. Their own accuracy is that of DASSL at tolerance 1e-6
  // (the hand oracle above differs from them by as much as mechgen does): at t = 0.002 .. 5 s
  // to 2e-4 rad and 2e-3 rad/s, at 6 .. 9 s (the motion grows chaotic) to 5e-3 and 5e-2
  // (measured: see the line printed below).
  double worst[2] = {0, 0};
  for (int r = 0; r < 10; ++r) {
    const bool early = kRef[r][0] <= 5.0;
    for (int c = 0; c < 4; ++c) {
      const double tol = (c % 2 == 0 ? 2e-4 : 2e-3) * (early ? 1 : 25);
      EXPECT_NEAR(got[r][c], kRef[r][c + 1], tol) << "t = " << kRef[r][0] << ", column " << c + 1;
      worst[early ? 0 : 1] = std::max(worst[early ? 0 : 1], std::abs(got[r][c] - kRef[r][c + 1]));
    }
  }
  std::printf(
      "published double pendulum: max |mechgen - hand RK4| %.3g (t <= 5 s); max |mechgen - "
      "reference| %.3g (t <= 5 s), %.3g (6..9 s); min 1/cond(Phi_phi) %.3g; %s\n",
      worst_hand, worst[0], worst[1], min_rcond, dyn::FormatSummary(summary).c_str());
}

TEST(PublishedDoublePendulum, InitialAccelerationsByHand) {
  // From rest with both rods horizontal (along +x), Lagrange's equations by hand: with
  // absolute angles a (rod 1, body at l1) and b (rod 2, body at l2 from the joint),
  //   [m1 l1^2 + I1 + m2 l1^2,  m2 l1 l2 cos(a - b)] [a'']   [-(m1 + m2) g l1 cos a]
  //   [m2 l1 l2 cos(a - b),     m2 l2^2 + I2       ] [b''] = [-m2 g l2 cos b       ]  at rest.
  const double m1 = 1, I1 = 0.1, m2 = 0.2, I2 = 0.01, l1 = 1, l2 = 0.4, g = 9.81;
  Eigen::Matrix2d M;
  M << m1 * l1 * l1 + I1 + m2 * l1 * l1, m2 * l1 * l2, m2 * l1 * l2, m2 * l2 * l2 + I2;
  const Eigen::Vector2d Q(-(m1 + m2) * g * l1, -m2 * g * l2);
  const Eigen::Vector2d acc = M.inverse() * Q;
  Model::ParamsT<double> p;
  Eigen::Vector2d q(0, 0), qd(0, 0);
  Eigen::Matrix<double, Model::kNphi, 1> phi(0.0, 0.0);
  ASSERT_EQ(Model::Solve(p, q, &phi).status, mech::published_double_pendulum::SolveStatus::kConverged);
  Model::CoefficientsT<double> c;
  Model::Coeffs(p, q, phi, &c);
  Model::DynamicsT<double> d;
  Model::Dynamics(p, q, phi, qd, 0.0, c, &d);
  EXPECT_NEAR((d.I - M).norm(), 0.0, 1e-12);
  const Eigen::Vector2d qdd = d.I.ldlt().solve(d.Q - d.h);
  EXPECT_NEAR(qdd(0), acc(0), 1e-12);
  EXPECT_NEAR(qdd(1), acc(1), 1e-12);
  // The reference's first row: w(0.002) = a'' 0.002 + O(0.002^3).
  EXPECT_NEAR(acc(0) * 0.002, kRef[0][2], 1e-6);
  EXPECT_NEAR((acc(1) - acc(0)) * 0.002, kRef[0][4], 1e-6);
}

}  // namespace
