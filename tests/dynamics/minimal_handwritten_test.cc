// The minimal method (forward.h) on the massive four-bar written by hand
// (handwritten_fourbar_dynamics.h). Oracles: conservation of energy (no driver, gravity
// only), the generalized inertia from point velocities (finite differences of the solved
// centres of mass), Newton–Euler kinetostatics against the Lagrange equation, inverse then
// forward dynamics, and a dead point reached as a status.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "dynamics_test_util.h"
#include "handwritten_fourbar_dynamics.h"
#include "mechgen/dynamics/forward.h"

namespace {

namespace hw = mech::handwritten_fourbar_dynamics;
using mechgen::dynamics::Dop853;
using mechgen::dynamics::Dopri5;
using mechgen::dynamics::MinimalDynamics;
using mechgen::dynamics::MinimalOptions;
using mechgen::dynamics::MinimalSummary;
using mechgen::dynamics::Status;
using Vec1 = Eigen::Matrix<double, 1, 1>;
using Vec2 = Eigen::Vector2d;

constexpr double kPi = 3.14159265358979323846;

template <template <int> class Method>
void CheckEnergyKept(double rtol, double tolerance) {
  MinimalOptions o;
  o.integrator.rtol = rtol;
  o.integrator.atol = rtol * 1e-2;
  o.sample_dt = 0.01;
  MinimalDynamics<hw::Model, Method> sim(hw::Params<double>(), o);
  ASSERT_TRUE(sim.Initialize(Vec1(kPi / 2)));
  MinimalSummary summary;
  double E0 = std::numeric_limits<double>::quiet_NaN(), max_err = 0, q_min = 1e9, q_max = -1e9;
  int samples = 0;
  ASSERT_TRUE(sim.Simulate(0.0, Vec1(kPi / 2), Vec1(0.0), 10.0,
                           [&](const auto& s) {
                             if (samples++ == 0) E0 = s.E;
                             max_err = std::max(max_err, std::abs(s.E - E0));
                             q_min = std::min(q_min, s.q(0));
                             q_max = std::max(q_max, s.q(0));
                             return true;
                           },
                           &summary))
      << mechgen::dynamics::FormatSummary(summary);
  EXPECT_EQ(summary.status, Status::kSuccess);
  EXPECT_EQ(samples, 1001);
  // It moves (it is released away from equilibrium) ...
  EXPECT_GT(q_max - q_min, 0.5);
  // ... and keeps its energy (E0 ~ 2 kg/m * 7.5 m * 9.81 * ~1.5 m ~ 200 J).
  EXPECT_LT(max_err, tolerance) << "E0 = " << E0;
  EXPECT_NEAR(summary.max_energy_error, max_err, 1e-12 + 1e-9 * std::abs(E0));
}

TEST(MinimalHandwritten, ConservativeFourBarKeepsItsEnergyDopri5) {
  CheckEnergyKept<Dopri5>(1e-10, 1e-6);
}
TEST(MinimalHandwritten, ConservativeFourBarKeepsItsEnergyDop853) {
  CheckEnergyKept<Dop853>(1e-10, 1e-6);
}

TEST(MinimalHandwritten, EnergyProjectionRemovesTheDrift) {
  // A loose tolerance drifts in energy; the projection keeps E to round-off.
  MinimalOptions o;
  o.integrator.rtol = 1e-5;
  o.integrator.atol = 1e-7;
  auto run = [&](bool project, MinimalSummary* summary) {
    o.energy_projection = project;
    MinimalDynamics<hw::Model, Dopri5> sim(hw::Params<double>(), o);
    EXPECT_TRUE(sim.Initialize(Vec1(kPi / 2)));
    EXPECT_TRUE(sim.Simulate(0.0, Vec1(kPi / 2), Vec1(0.0), 30.0, [](const auto&) { return true; },
                             summary));
  };
  MinimalSummary free_run, projected;
  run(false, &free_run);
  run(true, &projected);
  EXPECT_GT(projected.projections, 10);
  EXPECT_GT(free_run.max_energy_error, 1e-6);
  EXPECT_LT(projected.max_energy_error, 1e-3 * free_run.max_energy_error);
}

// I(q) against 2 T / qd^2 from the velocities of the centres of mass (finite differences of
// closed-form positions), and I' against finite differences of I.
TEST(MinimalHandwritten, InertiaFromPointVelocities) {
  const hw::Params<double> p;
  const double L[3] = {p.a, p.b, p.c};
  double m[3], J[3];
  for (int i = 0; i < 3; ++i) {
    m[i] = p.rho * L[i];
    J[i] = m[i] * L[i] * L[i] / 12;
  }
  auto centre = [&](double q, int link, Eigen::Vector2d* g, double* angle) {
    Vec2 phi(0.5, 1.9);
    hw::SolvePositions(p, Vec1(q), &phi, hw::Model::kDefaultModes);
    Eigen::Matrix<double, 2, hw::Model::kNumScenePoints> r;
    hw::EvalScene(p, Vec1(q), phi, &r);
    // crank A-B (2, 3), coupler B-C (4, 5), rocker D-C (6, 7)
    *g = 0.5 * (r.col(2 + 2 * link) + r.col(3 + 2 * link));
    *angle = link == 0 ? q : phi(link - 1);
  };
  for (double q = 0.1; q < 2 * kPi; q += 0.7) {
    Vec2 phi(0.5, 1.9);
    ASSERT_EQ(hw::SolvePositions(p, Vec1(q), &phi, hw::Model::kDefaultModes).status,
              hw::SolveStatus::kConverged);
    hw::Coefficients<double> c;
    hw::EvalCoefficients(p, Vec1(q), phi, &c);
    hw::Dynamics<double> d;
    hw::EvalDynamics(p, Vec1(q), phi, Vec1(1.0), 0.0, c, &d);
    const double I_fd = dynamics_test::InertiaFromPointVelocities(q, 3, m, J, centre);
    EXPECT_NEAR(d.I(0, 0), I_fd, 1e-7 * I_fd) << "q = " << q;
    EXPECT_NEAR(d.T, 0.5 * I_fd, 1e-7 * I_fd);
    const double h = 1e-5;
    const double dI_fd = (dynamics_test::InertiaFromPointVelocities(q + h, 3, m, J, centre) -
                          dynamics_test::InertiaFromPointVelocities(q - h, 3, m, J, centre)) /
                         (2 * h);
    EXPECT_NEAR(d.dI_dq(0, 0), dI_fd, 1e-4 * std::max(1.0, std::abs(dI_fd))) << "q = " << q;
    // Q = -dV/dq by finite differences of V.
    auto V_at = [&](double qq) {
      Vec2 ph(0.5, 1.9);
      hw::SolvePositions(p, Vec1(qq), &ph, hw::Model::kDefaultModes);
      hw::Dynamics<double> dd;
      hw::EvalDynamics(p, Vec1(qq), ph, Vec1(0.0), 0.0, c, &dd);
      return dd.V;
    };
    EXPECT_NEAR(d.Q(0), -(V_at(q + h) - V_at(q - h)) / (2 * h), 1e-6 * std::abs(d.V));
  }
}

// Newton–Euler with d'Alembert forces (EvalKinetostatics) against the Lagrange form
// I qdd + 1/2 I' qd^2 = Q + drive: two separate derivations.
TEST(MinimalHandwritten, NewtonEulerDriveEqualsLagrange) {
  hw::Params<double> p;
  p.tau = 3.0;
  p.damp = 0.7;
  for (double q = 0.2; q < 2 * kPi; q += 0.9) {
    Vec2 phi(0.5, 1.9);
    hw::SolvePositions(p, Vec1(q), &phi, hw::Model::kDefaultModes);
    hw::Coefficients<double> c;
    hw::EvalCoefficients(p, Vec1(q), phi, &c);
    const Vec1 qd(1.3), qdd(-2.1);
    hw::Dynamics<double> d;
    hw::EvalDynamics(p, Vec1(q), phi, qd, 0.0, c, &d);
    hw::Statics<double> k;
    hw::EvalKinetostatics(p, Vec1(q), phi, qd, qdd, 0.0, c, &k);
    const double lagrange = d.I(0, 0) * qdd(0) + d.h(0) - d.Q(0);
    EXPECT_NEAR(k.drive(0), lagrange, 1e-10 * (1 + std::abs(lagrange))) << "q = " << q;
    // Whole machine: sum of the external forces = sum m a_G (ground reactions A and D).
    // Ground on crank at A: F_A; ground on rocker at D: -F_D; weights.
  }
}

// Inverse then forward: the drive of a prescribed motion (kinetostatics), applied as a
// time-dependent torque, reproduces the motion.
struct Prescribed {
  static double q(double t) { return 0.3 + 2.0 * t + 0.4 * std::sin(3.0 * t); }
  static double qd(double t) { return 2.0 + 1.2 * std::cos(3.0 * t); }
  static double qdd(double t) { return -3.6 * std::sin(3.0 * t); }
};

struct DrivenModel : hw::Model {
  template <typename Scalar>
  static void Dynamics(const hw::Params<Scalar>& p, const hw::Vec<Scalar, 1>& q,
                       const hw::Vec<Scalar, 2>& phi, const hw::Vec<Scalar, 1>& qd,
                       const Scalar& t, const hw::Coefficients<Scalar>& c,
                       hw::Dynamics<Scalar>* out, const void* = nullptr,
                       const hw::Trig<Scalar>* trig = nullptr) {
    hw::EvalDynamics(p, q, phi, qd, t, c, out, nullptr, trig);
    out->Q(0) += Drive(p, t);
  }
  static double Drive(const hw::Params<double>& p, double t) {
    Vec2 phi(0.5, 1.9);
    const Vec1 q(Prescribed::q(t));
    phi(0) = 0.5;
    hw::SolvePositions(p, q, &phi, kDefaultModes);
    hw::Coefficients<double> c;
    hw::EvalCoefficients(p, q, phi, &c);
    hw::Statics<double> k;
    hw::EvalKinetostatics(p, q, phi, Vec1(Prescribed::qd(t)), Vec1(Prescribed::qdd(t)), t, c, &k);
    return k.drive(0);
  }
};

TEST(MinimalHandwritten, InverseThenForwardReproducesTheMotion) {
  MinimalOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-12;
  o.sample_dt = 0.05;
  MinimalDynamics<DrivenModel, Dop853> sim(hw::Params<double>(), o);
  ASSERT_TRUE(sim.Initialize(Vec1(Prescribed::q(0))));
  MinimalSummary summary;
  double max_err = 0;
  ASSERT_TRUE(sim.Simulate(0.0, Vec1(Prescribed::q(0)), Vec1(Prescribed::qd(0)), 4.0,
                           [&](const auto& s) {
                             max_err = std::max(max_err, std::abs(s.q(0) - Prescribed::q(s.t)));
                             max_err = std::max(max_err, 0.1 * std::abs(s.qd(0) - Prescribed::qd(s.t)));
                             return true;
                           },
                           &summary))
      << mechgen::dynamics::FormatSummary(summary);
  EXPECT_LT(max_err, 1e-7);
}

TEST(MinimalHandwritten, SpeedThroughZeroIsLocated) {
  // Released from rest at 90 deg the crank swings down and back: qd returns to 0 at a turning
  // point where (conservative) V equals V(90 deg).
  MinimalOptions o;
  o.integrator.rtol = 1e-10;
  o.integrator.atol = 1e-12;
  o.stop_at_speed_zero = true;
  MinimalDynamics<hw::Model, Dopri5> sim(hw::Params<double>(), o);
  ASSERT_TRUE(sim.Initialize(Vec1(kPi / 2)));
  MinimalSummary summary;
  mechgen::dynamics::Sample<hw::Model> first, last;
  int n = 0;
  // From rest: the start itself is not an event (qd = 0 there, no sign change).
  ASSERT_TRUE(sim.Simulate(0.0, Vec1(kPi / 2), Vec1(0.0), 20.0,
                           [&](const auto& s) {
                             if (n++ == 0) first = s;
                             return true;
                           },
                           &summary, &last))
      << mechgen::dynamics::FormatSummary(summary);
  EXPECT_EQ(summary.status, Status::kStoppedByEvent);
  EXPECT_EQ(summary.event, mechgen::dynamics::Event::kSpeedZero);
  EXPECT_LT(std::abs(last.qd(0)), 1e-6);
  EXPECT_NEAR(last.V, first.E, 1e-6 * std::abs(first.E));
  EXPECT_GT(summary.t_end, 0.1);
}

TEST(MinimalHandwritten, DeadPointIsAStatusNotANaN) {
  // A non-Grashof linkage (d = 4, a = 2.5, b = 2, c = 3): the crank cannot turn through; thrown
  // hard, it reaches the limit where coupler and rocker align (Phi_phi singular).
  hw::Params<double> p;
  p.a = 2.5;
  p.b = 2.0;
  p.c = 3.0;
  p.g = 0;
  MinimalOptions o;
  o.integrator.rtol = 1e-9;
  MinimalDynamics<hw::Model, Dopri5> sim(p, o);
  Vec2 guess(0.3, 1.8);
  ASSERT_TRUE(sim.Initialize(Vec1(kPi / 2), guess));
  MinimalSummary summary;
  bool finite = true;
  const bool ok = sim.Simulate(0.0, Vec1(kPi / 2), Vec1(5.0), 10.0,
                               [&](const auto& s) {
                                 finite = finite && s.q.allFinite() && s.qd.allFinite() &&
                                          s.phi.allFinite();
                                 return true;
                               },
                               &summary);
  EXPECT_FALSE(ok) << mechgen::dynamics::FormatSummary(summary);
  EXPECT_EQ(summary.status, Status::kDeadPoint) << mechgen::dynamics::FormatSummary(summary);
  EXPECT_TRUE(finite);
  EXPECT_LT(summary.min_rcond_seen, 1e-3);
}

}  // namespace
