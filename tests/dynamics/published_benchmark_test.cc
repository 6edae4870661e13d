// A published planar multibody benchmark with reference values: Andrews' squeezing mechanism
// (the "seven-body mechanism"), modelled in tests/dynamics/models/published_andrews.yaml and
// simulated by mechgen's minimal method (MinimalDynamics on the generated model).
//
// Source of the problem and of the reference values:
//   F. Mazzia, C. Magherini, "Test Set for Initial Value Problem Solvers", release 2.4,
//   University of Bari, problem "andrews" (Andrews' squeezing mechanism, index-3 DAE of 27
//   equations), https://archimede.uniba.it/~testset/problems/andrews.php, Fortran andrews.f:
//   subroutine INIT (consistent initial values and derivatives) and SOLN (the reference
//   solution at t = 0.03 s, computed by the test set's authors with RADAU5 at tight tolerances);
//   the problem and its data as in E. Hairer, G. Wanner, "Solving Ordinary Differential
//   Equations II", 2nd ed., Springer 1996, sec. VII.7 (after Manning 1981 and Schiehlen's
//   Multibody Systems Handbook, 1990).
// Quantities compared:
//   (1) t = 0: the consistent accelerations of INIT, beta'' = 14222.4439199541138705911625887
//       and Theta'' = -10666.8329399655854029433719415 rad/s^2 (all other angles' second
//       derivatives 0: the joint E is at rest at t = 0 to first order); tolerance 1e-12
//       relative (measured: 4e-15).
//   (2) t = 0.03 s: the seven angles beta, Theta, gamma, Phi, delta, Omega, epsilon of SOLN,
//       from a simulation with Dop853 at rtol = atol = 1e-12; tolerance 1e-8 rad on beta and
//       Theta (|beta| = 15.8 rad: 2.5 turns of the crank) and 2e-10 rad on the others
//       (measured: 1.2e-9 and 1.5e-9 on beta and Theta, <= 2.1e-11 on the others).
// The model's link angles are Hairer's absolute angles (k1: beta, k2: beta + Theta, k3: gamma,
// k4: Phi + delta, k5: delta, k6: Omega + epsilon, k7: epsilon); the velocities are zero at
// t = 0. Only the positions at 0.03 s and the initial accelerations are compared: the test
// set's velocities and Lagrange multipliers at 0.03 s are not used.
#include <array>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "mechgen/dynamics/forward.h"
#include "published_andrews.h"

namespace {

using Model = mech::published_andrews::Model;
namespace dyn = mechgen::dynamics;

// INIT of andrews.f (positions; velocities are 0).
constexpr double kBeta0 = -0.0617138900142764496358948458001;
constexpr double kGamma0 = 0.455279819163070380255912382449;
constexpr double kPhi0 = 0.222668390165885884674473185609;
constexpr double kDelta0 = 0.487364979543842550225598953530;
constexpr double kOmega0 = -0.222668390165885884674473185609;
constexpr double kEpsilon0 = 1.23054744454982119249735015568;
// INIT: the consistent second derivatives of beta and Theta at t = 0.
constexpr double kBetaDdot0 = 14222.4439199541138705911625887;
constexpr double kThetaDdot0 = -10666.8329399655854029433719415;
// SOLN: beta, Theta, gamma, Phi, delta, Omega, epsilon at t = 0.03 s.
constexpr double kRef[7] = {0.1581077119629904e+2,  -0.1575637105984298e+2, 0.4082224013073101e-1,
                            -0.5347301163226948e+0, 0.5244099658805304e+0,  0.5347301163226948e+0,
                            0.1048080741042263e+1};

// The model's phi = (theta_k2 .. theta_k7) in its coordinate order, checked by name.
int PhiIndex(const char* name) {
  for (int i = 0; i < Model::kNphi; ++i)
    if (std::string(Model::kPhiNames[i]) == name) return i;
  return -1;
}

// Hairer's seven angles from (q, phi).
std::array<double, 7> HairerAngles(double q, const Eigen::Matrix<double, Model::kNphi, 1>& phi) {
  const double k2 = phi(PhiIndex("theta_k2")), k3 = phi(PhiIndex("theta_k3"));
  const double k4 = phi(PhiIndex("theta_k4")), k5 = phi(PhiIndex("theta_k5"));
  const double k6 = phi(PhiIndex("theta_k6")), k7 = phi(PhiIndex("theta_k7"));
  return {q, k2 - q, k3, k4 - k5, k5, k6 - k7, k7};
}

// The difference of two angles, modulo 2 pi (the dependent angles may come back wrapped).
double AngleDiff(double a, double b) { return std::remainder(a - b, 2 * M_PI); }

using Sim = dyn::MinimalDynamics<Model, dyn::Dop853>;

Sim::VecPhi InitialPhi() {
  Sim::VecPhi phi;
  phi(PhiIndex("theta_k2")) = kBeta0;  // Theta(0) = 0
  phi(PhiIndex("theta_k3")) = kGamma0;
  phi(PhiIndex("theta_k4")) = kPhi0 + kDelta0;
  phi(PhiIndex("theta_k5")) = kDelta0;
  phi(PhiIndex("theta_k6")) = kOmega0 + kEpsilon0;
  phi(PhiIndex("theta_k7")) = kEpsilon0;
  return phi;
}

TEST(PublishedBenchmark, AndrewsModelHasHairersCoordinates) {
  ASSERT_EQ(Model::kNq, 1);
  ASSERT_EQ(Model::kNphi, 6);
  for (const char* name : {"theta_k2", "theta_k3", "theta_k4", "theta_k5", "theta_k6", "theta_k7"})
    EXPECT_GE(PhiIndex(name), 0) << name;
}

TEST(PublishedBenchmark, AndrewsInitialConfigurationAssemblesOnHairersValues) {
  // The generated solver at beta(0), on the assembly modes of the model's guess, reproduces the
  // test set's consistent initial angles (which close the three loops to ~1e-16 m).
  const Sim::Params p;
  Sim sim(p);
  const Sim::VecQ q0 = Sim::VecQ::Constant(kBeta0);
  ASSERT_TRUE(sim.Initialize(q0, InitialPhi()));
  Sim::VecPhi phi;
  Sim::Coefficients c;
  ASSERT_TRUE(sim.Positions(q0, &phi, &c));
  const Sim::VecPhi ref = InitialPhi();
  for (int i = 0; i < Model::kNphi; ++i)
    EXPECT_NEAR(AngleDiff(phi(i), ref(i)), 0.0, 1e-12) << Model::kPhiNames[i];
}

TEST(PublishedBenchmark, AndrewsInitialAccelerationsMatchTheTestSet) {
  const Sim::Params p;
  Sim sim(p);
  const Sim::VecQ q0 = Sim::VecQ::Constant(kBeta0);
  ASSERT_TRUE(sim.Initialize(q0, InitialPhi()));
  Sim::State y;
  y << kBeta0, 0.0, 0.0;
  dyn::Sample<Model> s;
  ASSERT_TRUE(sim.Evaluate(0.0, y, &s));
  // (1) beta'' = Q / I at rest, and Theta'' = (K_k2 - 1) beta'' (qd = 0: no L term).
  EXPECT_NEAR(s.qdd(0) / kBetaDdot0, 1.0, 1e-12) << s.qdd(0);
  const double theta_ddot = (s.K(PhiIndex("theta_k2"), 0) - 1.0) * s.qdd(0);
  EXPECT_NEAR(theta_ddot / kThetaDdot0, 1.0, 1e-12) << theta_ddot;
  // The test set's other second derivatives are 0: E is at rest, so K of the angles of
  // K3 .. K7 vanish at t = 0.
  for (const char* name : {"theta_k3", "theta_k4", "theta_k5", "theta_k6", "theta_k7"})
    EXPECT_NEAR(s.K(PhiIndex(name), 0) * s.qdd(0), 0.0, 1e-6) << name;
}

TEST(PublishedBenchmark, AndrewsAnglesAtThreeHundredthsOfASecondMatchTheTestSet) {
  const Sim::Params p;
  dyn::MinimalOptions options;
  options.integrator.rtol = 1e-12;
  options.integrator.atol = 1e-12;
  options.sample_dt = 0.03;
  Sim sim(p, options);
  const Sim::VecQ q0 = Sim::VecQ::Constant(kBeta0), qd0 = Sim::VecQ::Zero();
  ASSERT_TRUE(sim.Initialize(q0, InitialPhi()));
  dyn::MinimalSummary summary;
  dyn::Sample<Model> last;
  ASSERT_TRUE(sim.Simulate(0.0, q0, qd0, 0.03, [](const dyn::Sample<Model>&) { return true; },
                           &summary, &last))
      << dyn::FormatSummary(summary);
  ASSERT_NEAR(last.t, 0.03, 1e-15);
  const std::array<double, 7> angles = HairerAngles(last.q(0), last.phi);
  const char* names[7] = {"beta", "Theta", "gamma", "Phi", "delta", "Omega", "epsilon"};
  for (int i = 0; i < 7; ++i) {
    const double tol = i < 2 ? 1e-8 : 2e-10;
    // beta is integrated (unwrapped); Theta = theta_k2 - beta may differ by whole turns.
    const double diff = i == 0 ? angles[i] - kRef[i] : AngleDiff(angles[i], kRef[i]);
    EXPECT_NEAR(diff, 0.0, tol) << names[i] << " = " << angles[i] << ", reference " << kRef[i];
  }
}

}  // namespace
