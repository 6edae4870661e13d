// The energy integral (energy.h) against closed forms and against the simulation (forward.h),
// on the handwritten massive four-bar: two independent computations of the same motion (a
// quadrature of dq / |qd| and an ODE solver).
#include <cmath>

#include <gtest/gtest.h>

#include "handwritten_fourbar_dynamics.h"
#include "mechgen/dynamics/energy.h"
#include "mechgen/dynamics/forward.h"

namespace {

namespace hw = mech::handwritten_fourbar_dynamics;
using mechgen::dynamics::EnergyIntegral;
using mechgen::dynamics::MinimalDynamics;
using mechgen::dynamics::MinimalOptions;
using mechgen::dynamics::MinimalSummary;
using Vec1 = Eigen::Matrix<double, 1, 1>;
constexpr double kPi = 3.14159265358979323846;

// A constant torque tau, no gravity, from rest: 1/2 I(q) qd^2 = tau (q - q0) exactly (Paul §6.5),
// checked along a simulated run (at every sample: T against tau (q - q0)) and by the energy
// integral's speed.
TEST(Energy, ConstantTorqueFromRestObeysTheEnergyIntegral) {
  hw::Params<double> p;
  p.g = 0;
  p.tau = 5.0;
  const double q0 = 0.3;
  MinimalOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-12;
  o.sample_dt = 0.02;
  MinimalDynamics<hw::Model, mechgen::dynamics::Dop853> sim(p, o);
  ASSERT_TRUE(sim.Initialize(Vec1(q0)));
  EnergyIntegral<hw::Model> energy(p);
  ASSERT_TRUE(energy.Initialize(q0, 0.0, Eigen::Vector2d(0.5, 1.9)));
  MinimalSummary summary;
  int checked = 0;
  ASSERT_TRUE(sim.Simulate(0.0, Vec1(q0), Vec1(0.0), 4.0,
                           [&](const auto& s) {
                             const double work = p.tau * (s.q(0) - q0);
                             EXPECT_NEAR(s.T, work, 1e-8 * (1 + work)) << "t = " << s.t;
                             if (s.t > 0.5 && checked < 20) {
                               double qd = 0;
                               EXPECT_TRUE(energy.Speed(s.q(0), &qd));
                               EXPECT_NEAR(qd, s.qd(0), 1e-8 * (1 + std::abs(qd)));
                               ++checked;
                             }
                             return true;
                           },
                           &summary))
      << mechgen::dynamics::FormatSummary(summary);
  EXPECT_EQ(checked, 20);
  // It went round several times.
  double W = 0;
  ASSERT_TRUE(energy.Work(q0 + 2 * kPi, &W));
  EXPECT_NEAR(W, p.tau * 2 * kPi, 1e-10);
}

// Released from rest at 90 deg under gravity the crank swings (it does not go over the top):
// the half period from the simulation (speed through zero) and from the quadrature agree.
TEST(Energy, SwingPeriodOfTheMassiveFourBarAgreesWithTheSimulation) {
  hw::Params<double> p;
  MinimalOptions o;
  o.integrator.rtol = 1e-12;
  o.integrator.atol = 1e-13;
  o.stop_at_speed_zero = true;
  MinimalDynamics<hw::Model, mechgen::dynamics::Dop853> sim(p, o);
  ASSERT_TRUE(sim.Initialize(Vec1(kPi / 2)));
  MinimalSummary summary;
  mechgen::dynamics::Sample<hw::Model> last;
  ASSERT_TRUE(sim.Simulate(0.0, Vec1(kPi / 2), Vec1(0.0), 20.0, [](const auto&) { return true; },
                           &summary, &last));
  ASSERT_EQ(summary.event, mechgen::dynamics::Event::kSpeedZero);
  EnergyIntegral<hw::Model> energy(p);
  ASSERT_TRUE(energy.Initialize(kPi / 2, 0.0, Eigen::Vector2d(0.5, 1.9)));
  double period = 0, lo = 0, hi = 0;
  ASSERT_TRUE(energy.SwingPeriod(2 * kPi, 200, &period, &lo, &hi));
  EXPECT_NEAR(lo, kPi / 2, 1e-9);
  EXPECT_NEAR(hi, last.q(0), 1e-6);
  EXPECT_NEAR(0.5 * period, summary.t_end, 1e-7 * summary.t_end)
      << "quadrature " << 0.5 * period << " s, simulation " << summary.t_end << " s";
  // The time to a position on the way, both ways.
  const double q1 = 0.5 * (lo + hi);
  double t1 = 0;
  ASSERT_TRUE(energy.Time(q1, &t1));
  MinimalDynamics<hw::Model, mechgen::dynamics::Dop853> sim2(p, o);
  ASSERT_TRUE(sim2.Initialize(Vec1(kPi / 2)));
  MinimalSummary s2;
  ASSERT_TRUE(sim2.Simulate(
      0.0, Vec1(kPi / 2), Vec1(0.0), 20.0, [](const auto&) { return true; },
      [&](double, const Vec1& q, const Vec1&, const Eigen::Vector2d&) { return q(0) - q1; }, &s2));
  ASSERT_EQ(s2.event, mechgen::dynamics::Event::kUser);
  EXPECT_NEAR(t1, s2.t_end, 1e-7 * t1);
}

}  // namespace
