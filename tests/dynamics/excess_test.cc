// The excess-coordinate method and the differential-equation method of kinematics (excess.h)
// on the handwritten massive four-bar: they agree with the minimal method (forward.h, a
// different formulation of the same motion), keep the energy, and their constraint drift is
// what stabilization and projection are for; the kinematics by integration of K drifts from
// the position solver by no more than the integrator's tolerance.
#include <cmath>

#include <gtest/gtest.h>

#include "handwritten_fourbar_dynamics.h"
#include "mechgen/dynamics/excess.h"
#include "mechgen/dynamics/forward.h"

namespace {

namespace hw = mech::handwritten_fourbar_dynamics;
using mechgen::dynamics::Dop853;
using mechgen::dynamics::Dopri5;
using mechgen::dynamics::ExcessDynamics;
using mechgen::dynamics::ExcessOptions;
using mechgen::dynamics::ExcessSummary;
using Vec1 = Eigen::Matrix<double, 1, 1>;
constexpr double kPi = 3.14159265358979323846;

double MinimalTheta(double t_end) {
  mechgen::dynamics::MinimalOptions o;
  o.integrator.rtol = 1e-12;
  o.integrator.atol = 1e-13;
  mechgen::dynamics::MinimalDynamics<hw::Model, Dop853> sim(hw::Params<double>(), o);
  EXPECT_TRUE(sim.Initialize(Vec1(kPi / 2)));
  mechgen::dynamics::MinimalSummary s;
  mechgen::dynamics::Sample<hw::Model> last;
  EXPECT_TRUE(sim.Simulate(0.0, Vec1(kPi / 2), Vec1(0.0), t_end, [](const auto&) { return true; },
                           &s, &last));
  return last.q(0);
}

struct ExcessRun {
  double theta = 0;
  double energy_error = 0;
  ExcessSummary summary;
};

ExcessRun RunExcess(const ExcessOptions& o, double t_end) {
  ExcessRun r;
  ExcessDynamics<hw::Model, Dop853> sim(hw::Params<double>(), o);
  double E0 = std::numeric_limits<double>::quiet_NaN();
  mechgen::dynamics::ExcessSample<hw::Model> last;
  EXPECT_TRUE(sim.Simulate(0.0, Vec1(kPi / 2), Vec1(0.0), Eigen::Vector2d(0.5, 1.9), t_end,
                           [&](const auto& s) {
                             if (std::isnan(E0)) E0 = s.E;
                             r.energy_error = std::max(r.energy_error, std::abs(s.E - E0));
                             return true;
                           },
                           &r.summary, &last));
  r.theta = last.x(0);
  return r;
}

TEST(Excess, AgreesWithTheMinimalMethod) {
  const double t_end = 3.0;
  const double reference = MinimalTheta(t_end);
  ExcessOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-12;
  // Without stabilization: the drift stays small over 3 s at this tolerance, and theta agrees.
  const ExcessRun plain = RunExcess(o, t_end);
  EXPECT_NEAR(plain.theta, reference, 1e-6);
  EXPECT_LT(plain.summary.max_Phi, 1e-6);
  // With projection: Phi back to round-off after every step, same answer.
  o.projection = true;
  const ExcessRun projected = RunExcess(o, t_end);
  EXPECT_NEAR(projected.theta, reference, 1e-7);
  EXPECT_GT(projected.summary.projections, 10);
  EXPECT_EQ(projected.summary.failed_projections, 0);
  EXPECT_LT(projected.summary.max_Phi, 1e-9);
  EXPECT_LT(projected.energy_error, 1e-5);
  // Baumgarte.
  o.projection = false;
  o.alpha = 5;
  o.beta = 5;
  const ExcessRun baumgarte = RunExcess(o, t_end);
  EXPECT_NEAR(baumgarte.theta, reference, 1e-6);
  EXPECT_LT(baumgarte.summary.max_Phi, 1e-8);
}

TEST(Excess, StabilizationReducesTheDriftOfALooseRun) {
  ExcessOptions o;
  o.integrator.rtol = 1e-5;
  o.integrator.atol = 1e-7;
  const ExcessRun plain = RunExcess(o, 10.0);
  o.projection = true;
  const ExcessRun projected = RunExcess(o, 10.0);
  EXPECT_GT(plain.summary.max_Phi, 1e-7);
  EXPECT_LT(projected.summary.max_Phi, 1e-3 * plain.summary.max_Phi);
}

TEST(Excess, IsASystemOfTheOneSimulatorAndStopsWhereTheMinimalMethodDoes) {
  // From rest at pi/2 the crank swings and turns back. The simulator's witnesses on the excess
  // method's dense output find the speed's zero (the turning point), and the user's event
  // (the crank 0.1 rad from its start), where the minimal method (a different formulation of
  // the same motion) finds them.
  auto run = [](bool speed_zero, bool user_event, mechgen::dynamics::Event expected) {
    auto user = [user_event](double, const Vec1& q, const Vec1&, const auto&) {
      return user_event ? std::abs(q(0) - kPi / 2) - 0.1 : 1.0;
    };
    mechgen::dynamics::MinimalOptions mo;
    mo.integrator.rtol = 1e-12;
    mo.integrator.atol = 1e-13;
    mo.stop_at_speed_zero = speed_zero;
    mechgen::dynamics::MinimalDynamics<hw::Model, Dop853> minimal(hw::Params<double>(), mo);
    ASSERT_TRUE(minimal.Initialize(Vec1(kPi / 2)));
    mechgen::dynamics::MinimalSummary ms;
    EXPECT_TRUE(minimal.Simulate(0.0, Vec1(kPi / 2), Vec1(0.0), 10.0, [](const auto&) { return true; }, user, &ms));
    ExcessOptions o;
    o.integrator.rtol = 1e-12;
    o.integrator.atol = 1e-13;
    o.projection = true;
    o.stop_at_speed_zero = speed_zero;
    ExcessDynamics<hw::Model, Dop853> excess(hw::Params<double>(), o);
    ExcessSummary es;
    EXPECT_TRUE(excess.Simulate(0.0, Vec1(kPi / 2), Vec1(0.0), Eigen::Vector2d(0.5, 1.9), 10.0,
                                [](const auto&) { return true; }, user, &es));
    EXPECT_EQ(ms.event, expected);
    EXPECT_EQ(es.event, expected);
    EXPECT_EQ(es.status, mechgen::dynamics::Status::kStoppedByEvent);
    EXPECT_NEAR(es.t_end, ms.t_end, 1e-7);
    EXPECT_GT(es.t_end, 0.0);
    EXPECT_GT(es.samples, 2);
  };
  run(true, false, mechgen::dynamics::Event::kSpeedZero);
  run(false, true, mechgen::dynamics::Event::kUser);
}

TEST(Excess, KinematicsByIntegrationFollowsThePositionSolver) {
  const hw::Params<double> p;
  Eigen::Vector2d phi0(0.5, 1.9);
  ASSERT_EQ(hw::Model::Solve(p, Vec1(0.0), &phi0).status, hw::SolveStatus::kConverged);
  for (double rtol : {1e-6, 1e-10}) {
    mechgen::dynamics::IntegratorOptions o;
    o.rtol = rtol;
    o.atol = rtol * 1e-2;
    mechgen::dynamics::KinematicsByIntegration<hw::Model, Dopri5> kin(p, o);
    mechgen::dynamics::KinematicsByIntegration<hw::Model, Dopri5>::Summary s;
    int n = 0;
    ASSERT_TRUE(kin.Run(0.0, phi0, 4 * kPi, 200,
                        [&](double q, const Eigen::Vector2d& phi, const Eigen::Vector2d&) {
                          // The closed-form circle intersection as an independent oracle.
                          Eigen::Vector2d exact(phi(0), phi(1));
                          hw::SolvePositions(p, Vec1(q), &exact, hw::Model::kDefaultModes);
                          EXPECT_NEAR(phi(0), exact(0), 2000 * rtol);
                          ++n;
                        },
                        &s));
    EXPECT_EQ(n, 200);
    // Two revolutions: the drift is of the order of the tolerance, never zero.
    EXPECT_LT(s.max_drift, 2000 * rtol);
    EXPECT_GT(s.max_drift, 0.0);
    EXPECT_LT(s.max_Phi, 2000 * rtol * 4);
  }
}

}  // namespace
