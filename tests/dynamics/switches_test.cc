// Switching points of the loads (issue 26): the generated EvalSwitchModes (Model::SwitchModes)
// and the restart of the minimal method's integrator at the switches it locates
// (MinimalOptions::restart_at_switches, dynamics/simulator.h), on the loop-free wheel
// tests/dynamics/models/wheel_switched.yaml (inertia J about its pin, torques
// T0 step(mod(theta, 2 pi) - theta_s) and A tent(theta)).
//
// Oracles, each independent of the integrator:
//  - the modes against the definitions (models/README.md, Expressions) evaluated by hand;
//  - T0 alone: the motion is constant speed off [theta_s, 2 pi) of each turn and constant
//    acceleration T0/J on it, so the state at t_end follows in closed form turn by turn
//    (the time to cover d at speed w and acceleration a: (sqrt(w^2 + 2 a d) - w)/a); the
//    restarted run must match it to 1e-10 and restart once per crossing of theta_s + 2 pi k
//    and 2 pi k (counted from the closed form);
//  - A alone: 1/2 J w^2 = 1/2 J w0^2 + A integral of the tent over [theta0, theta] (exact
//    piecewise quadratics) at every sample, and a restart per point of the tent passed;
//  - the shaper with masses (tests/dynamics/models/shaper_massive.yaml) coasting one turn of
//    the crank from -30 deg: the work of its cutting force, which acts over the forward
//    stroke only, is -F times the stroke (the ram's x at -30 and 210 deg from the position
//    solver), and T + V - W stays E0 across the switches.
// The runs without restarts are printed beside them (their error and steps: a comparison,
// not a timing).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/prescribed.h"
#include "shaper_massive.h"
#include "wheel_switched.h"

namespace {

namespace dyn = mechgen::dynamics;
namespace ws = mech::wheel_switched;
using M = ws::Model;
using Sim = dyn::MinimalDynamics<M>;
constexpr double kPi = 3.14159265358979323846;

static_assert(M::kNumSwitches == 4, "mod, sign, step and the table: four switching items");
static_assert(Sim::kHasSwitches, "the runtime sees the model's switches");

std::array<int, M::kNumSwitches> ModesAt(const ws::Params<double>& p, double theta, double w) {
  Eigen::Matrix<double, 1, 1> q, qd;
  q(0) = theta;
  qd(0) = w;
  Eigen::Matrix<double, 0, 1> phi;
  ws::Coefficients<double> c;
  M::Coeffs<double>(p, q, phi, &c);
  std::array<int, M::kNumSwitches> modes{};
  M::SwitchModes<double>(p, q, phi, qd, 0.0, c, &modes);
  return modes;
}

// The items in the generated order (documented in the header): 0 mod(theta, 2 pi),
// 1 sign(theta - theta_b), 2 step(mod(theta, 2 pi) - theta_s), 3 the tent table of theta.
TEST(Switches, ModesFollowTheDefinitions) {
  ws::Params<double> p;
  for (double theta : {-7.0, -1.0, 0.0, 0.5, 1.0, 1.5, 2.0, 2.99, 3.0, 3.5, 3.999, 4.0, 4.5, 6.28, 6.3, 10.4, 20.0,
                       100.0, 120.0}) {
    const auto m = ModesAt(p, theta, 1.0);
    const double floor_turns = std::floor(theta / (2 * kPi));
    EXPECT_EQ(m[0], static_cast<int>(floor_turns)) << theta;
    const double in_turn = theta - 2 * kPi * floor_turns;
    EXPECT_EQ(m[1], theta > p.theta_b ? 1 : theta < p.theta_b ? -1 : 0) << theta;
    EXPECT_EQ(m[2], in_turn >= p.theta_s ? 1 : 0) << theta;
    EXPECT_EQ(m[3], (theta >= 1) + (theta >= 2) + (theta >= 3)) << theta;
  }
  // step(0) = 1: on at theta_s exactly; sign(0) = 0.
  EXPECT_EQ(ModesAt(p, p.theta_s, 1.0)[2], 1);
  p.theta_b = 2.5;
  EXPECT_EQ(ModesAt(p, 2.5, 1.0)[1], 0);
  EXPECT_EQ(ModesAt(p, 2.6, 1.0)[1], 1);
  EXPECT_EQ(ModesAt(p, 2.4, 1.0)[1], -1);
}

struct RunResult {
  dyn::MinimalSummary summary;
  double theta = 0, w = 0;
  double max_energy_oracle_error = 0;
};

// A run of the wheel from (theta0, w0) to t_end; `energy` (optional) is the closed-form
// kinetic energy at an angle, checked at every sample.
template <class Energy>
RunResult Simulate(const ws::Params<double>& p, double theta0, double w0, double t_end, bool restart, Energy&& energy) {
  dyn::MinimalOptions o;
  o.integrator.rtol = 1e-12;
  o.integrator.atol = 1e-12;
  o.restart_at_switches = restart;
  Sim sim(p, o);
  Sim::VecQ q0, qd0;
  q0(0) = theta0;
  qd0(0) = w0;
  EXPECT_TRUE(sim.Initialize(q0));
  RunResult run;
  Sim::SampleT last;
  sim.Simulate(
      0.0, q0, qd0, t_end,
      [&](const Sim::SampleT& s) {
        const double T = 0.5 * p.J * s.qd(0) * s.qd(0);
        run.max_energy_oracle_error = std::max(run.max_energy_oracle_error, std::abs(T - energy(s.q(0))));
        return true;
      },
      &run.summary, &last);
  run.theta = last.q(0);
  run.w = last.qd(0);
  return run;
}

/// T0 alone in closed form: (theta, w) at t_end from (theta0, w0 > 0), and the crossings of
/// the switching angles theta_s + 2 pi k and 2 pi k on the way.
struct StepOracle {
  double J, T0, theta_s;
  void At(double theta0, double w0, double t_end, double* theta, double* w, int* crossings) const {
    const double a = T0 / J;
    double t = 0, th = theta0, v = w0;
    *crossings = 0;
    for (;;) {
      const double turn = std::floor(th / (2 * kPi));
      const double in_turn = th - 2 * kPi * turn;
      const bool on = in_turn >= theta_s;
      const double next = on ? 2 * kPi * (turn + 1) : 2 * kPi * turn + theta_s;
      const double d = next - th;
      const double dt = on ? (std::sqrt(v * v + 2 * a * d) - v) / a : d / v;
      if (t + dt >= t_end) {
        const double tau = t_end - t;
        *theta = th + v * tau + (on ? 0.5 * a * tau * tau : 0.0);
        *w = v + (on ? a * tau : 0.0);
        return;
      }
      t += dt;
      v = on ? std::sqrt(v * v + 2 * a * d) : v;
      th = next;
      ++*crossings;
    }
  }
};

TEST(Switches, StepTorqueMatchesTheClosedFormWithRestarts) {
  ws::Params<double> p;  // T0 = 3, theta_s = 4, J = 0.5, A = 0
  const double theta0 = 0.5, w0 = 2.0, t_end = 6.0;
  double theta_x = 0, w_x = 0;
  int crossings = 0;
  StepOracle{p.J, p.T0, p.theta_s}.At(theta0, w0, t_end, &theta_x, &w_x, &crossings);
  ASSERT_GE(crossings, 4);  // several turns: on and off, and the table's points in the first turn
  // The kinetic energy by the work of T0 over the angles in [theta_s, 2 pi) of each turn.
  auto energy = [&](double theta) {
    double on = 0;
    for (int k = 0; k < 100; ++k) {
      const double lo = std::max(theta0, 2 * kPi * k + p.theta_s), hi = std::min(theta, 2 * kPi * (k + 1));
      if (hi > lo) on += hi - lo;
    }
    return 0.5 * p.J * w0 * w0 + p.T0 * on;
  };
  const RunResult with = Simulate(p, theta0, w0, t_end, true, energy);
  const RunResult without = Simulate(p, theta0, w0, t_end, false, energy);
  ASSERT_EQ(with.summary.status, dyn::Status::kSuccess) << dyn::FormatSummary(with.summary);
  ASSERT_EQ(without.summary.status, dyn::Status::kSuccess) << dyn::FormatSummary(without.summary);
  // The table's points 1, 2, 3 rad are switching items too (A = 0: they change nothing).
  const int table_points = (theta0 < 1) + (theta0 < 2) + (theta0 < 3);
  EXPECT_EQ(with.summary.switch_restarts, crossings + table_points) << dyn::FormatSummary(with.summary);
  EXPECT_EQ(with.summary.switches_through, 0);
  EXPECT_EQ(without.summary.switch_restarts, 0);
  EXPECT_NEAR(with.theta, theta_x, 1e-10 * std::abs(theta_x));
  EXPECT_NEAR(with.w, w_x, 1e-10 * std::abs(w_x));
  EXPECT_LT(with.max_energy_oracle_error, 1e-10 * energy(theta_x));
  EXPECT_LT(with.summary.max_energy_error, 1e-10 * energy(theta_x));
  std::printf("step torque, %d crossings, closed form theta = %.15g, w = %.15g\n", crossings, theta_x, w_x);
  std::printf("  with restarts:    |theta error| = %.3g, |w error| = %.3g, max |T - T_exact| = %.3g, %d steps, "
              "%d rejected, %d rhs, %d restarts\n",
              std::abs(with.theta - theta_x), std::abs(with.w - w_x), with.max_energy_oracle_error,
              with.summary.integrator.steps, with.summary.integrator.rejected,
              with.summary.integrator.rhs_evaluations, with.summary.switch_restarts);
  std::printf("  without restarts: |theta error| = %.3g, |w error| = %.3g, max |T - T_exact| = %.3g, %d steps, "
              "%d rejected, %d rhs\n",
              std::abs(without.theta - theta_x), std::abs(without.w - w_x), without.max_energy_oracle_error,
              without.summary.integrator.steps, without.summary.integrator.rejected,
              without.summary.integrator.rhs_evaluations);
}

TEST(Switches, TableTorqueKeepsTheEnergyWithRestarts) {
  ws::Params<double> p;
  p.T0 = 0;  // the tent alone
  p.A = 4.0;
  p.theta_s = 10;  // beyond a turn: the step item never switches (the mod item does, at 2 pi)
  const double theta0 = 0.5, w0 = 1.5, t_end = 2.0;
  // Integral of the tent (0 at 1, 1 at 2, 0 at 3) from -inf to x.
  auto tent_integral = [](double x) {
    if (x <= 1) return 0.0;
    if (x <= 2) return 0.5 * (x - 1) * (x - 1);
    if (x <= 3) return 0.5 + (x - 2) - 0.5 * (x - 2) * (x - 2);
    return 1.0;
  };
  auto energy = [&](double theta) { return 0.5 * p.J * w0 * w0 + p.A * (tent_integral(theta) - tent_integral(theta0)); };
  const RunResult with = Simulate(p, theta0, w0, t_end, true, energy);
  const RunResult without = Simulate(p, theta0, w0, t_end, false, energy);
  ASSERT_EQ(with.summary.status, dyn::Status::kSuccess) << dyn::FormatSummary(with.summary);
  ASSERT_GT(with.theta, 3.0);  // past the tent
  ASSERT_GT(with.theta, 2 * kPi);
  ASSERT_LT(with.theta, 4 * kPi);
  // The tent's three points and mod(theta, 2 pi) at 2 pi.
  EXPECT_EQ(with.summary.switch_restarts, 4) << dyn::FormatSummary(with.summary);
  const double T_end = energy(with.theta);
  EXPECT_NEAR(0.5 * p.J * with.w * with.w, T_end, 1e-10 * T_end);
  EXPECT_LT(with.max_energy_oracle_error, 1e-10 * T_end);
  std::printf("tent torque: with restarts max |T - T_exact| = %.3g (%d steps, %d rhs, %d restarts); without: %.3g "
              "(%d steps, %d rhs)\n",
              with.max_energy_oracle_error, with.summary.integrator.steps, with.summary.integrator.rhs_evaluations,
              with.summary.switch_restarts, without.max_energy_oracle_error, without.summary.integrator.steps,
              without.summary.integrator.rhs_evaluations);
}

TEST(Switches, ShaperWorkPerTurnIsForceTimesStroke) {
  using S = mech::shaper_massive::Model;
  using ShaperSim = dyn::MinimalDynamics<S>;
  static_assert(S::kNumSwitches == 2, "mod and step");
  const mech::shaper_massive::Params<double> p;
  const double deg = kPi / 180;
  // The ram's x at the crank's -30 and 210 deg (its extremes) by the position solver.
  auto ram_x = [&](double theta) {
    ShaperSim::VecQ q;
    q(0) = theta;
    ShaperSim::VecPhi phi;
    for (int i = 0; i < S::kNphi; ++i) phi(i) = S::kAssemblyPhi[i];
    mech::shaper_massive::Coefficients<double> c;
    ShaperSim sim(p);
    EXPECT_TRUE(sim.Initialize(q));
    EXPECT_TRUE(sim.Positions(q, &phi, &c));
    return c.r_P(0, 0);
  };
  const double stroke = ram_x(-30 * deg) - ram_x(210 * deg);
  ASSERT_GT(stroke, 1.0);
  const double W_exact = -p.F * stroke;
  const double theta0 = -30 * deg, theta_end = 330 * deg;
  for (bool restart : {true, false}) {
    dyn::MinimalOptions o;
    o.integrator.rtol = 1e-10;
    o.integrator.atol = 1e-10;
    o.restart_at_switches = restart;
    ShaperSim sim(p, o);
    ShaperSim::VecQ q0, qd0;
    q0(0) = theta0;
    qd0(0) = 6.0;
    ASSERT_TRUE(sim.Initialize(q0));
    dyn::MinimalSummary summary;
    ShaperSim::SampleT last;
    sim.Simulate(
        0.0, q0, qd0, 100.0, [](const ShaperSim::SampleT&) { return true; },
        [&](double, const ShaperSim::VecQ& q, const ShaperSim::VecQ&, const ShaperSim::VecPhi&) {
          return q(0) - theta_end;
        },
        &summary, &last);
    ASSERT_EQ(summary.status, dyn::Status::kStoppedByEvent) << dyn::FormatSummary(summary);
    ASSERT_EQ(summary.event, dyn::Event::kUser);
    std::printf("shaper, one turn, restarts %s: W = %.12g, -F stroke = %.12g, |dW| = %.3g, max |E - W - E0| = %.3g, "
                "%d steps, %d rhs, %d restarts\n",
                restart ? "on " : "off", last.W, W_exact, std::abs(last.W - W_exact), summary.max_energy_error,
                summary.integrator.steps, summary.integrator.rhs_evaluations, summary.switch_restarts);
    if (restart) {
      // The forward stroke's end at 210 deg and the turn's end at 330 deg = -30 deg, where
      // the force comes on again (the start, at -30 deg, is on already).
      EXPECT_GE(summary.switch_restarts, 1);
      EXPECT_LE(summary.switch_restarts, 3);
      EXPECT_NEAR(last.W, W_exact, 1e-10 * std::abs(W_exact));  // 5.8e-6 J off without restarts
      EXPECT_LT(summary.max_energy_error, 1e-8 * std::abs(W_exact));
    }
  }
}

// The bang-bang spring with damping: J theta'' = -Kb sign(theta - theta_b) - cd theta'. Its
// swings about theta_b shorten without end; each half swing (constant torque -+Kb and the
// damper) is in closed form, which gives every crossing of theta_b. The guard against
// chattering is checked on it: with the defaults every crossing is restarted at; with a cap,
// the first max_switch_restarts are and the rest are stepped through (and the message says
// so); with a long switch_min_interval, a crossing is restarted at only if it comes that
// long after the last restart, which the closed form's crossing times decide.
std::vector<double> BangBangCrossings(const ws::Params<double>& p, double theta0, double t_end) {
  // From theta_b at speed v (or theta0 at rest), with a = -Kb/J s (s: the side the motion
  // goes to) and k = cd/J (v' = a - k v): v(t) = a/k + (v - a/k) e^(-k t) and
  // x(t) = x + a t/k + (v - a/k)(1 - e^(-k t))/k; the next x = 0 by bisection.
  const double k = p.cd / p.J;
  double x = theta0 - p.theta_b, v = 0, t = 0;
  std::vector<double> crossings;
  for (;;) {
    const double s = x > 0 || (x == 0 && v > 0) ? 1.0 : -1.0;
    const double a = -p.Kb / p.J * s;
    auto X = [&](double tau) { return x + a / k * tau - (v - a / k) * std::expm1(-k * tau) / k; };
    // The half swing lasts about 2 |v| / |a| (or from rest sqrt(2 |x| / |a|)): bracket it.
    double lo = 0.25 * (x != 0 ? std::sqrt(2 * std::abs(x) / std::abs(a)) : 2 * std::abs(v) / std::abs(a));
    double hi = 4 * lo;
    while (X(hi) * s > 0) hi *= 2;
    while (lo > 0 && X(lo) * s <= 0) lo *= 0.5;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (X(mid) * s > 0 ? lo : hi) = mid;
    }
    if (t + hi > t_end) return crossings;
    v = a / k + (v - a / k) * std::exp(-k * hi);
    x = 0;
    t += hi;
    crossings.push_back(t);
  }
}

dyn::MinimalSummary RunBangBang(const ws::Params<double>& p, double theta0, double t_end, const dyn::MinimalOptions& o) {
  Sim sim(p, o);
  Sim::VecQ q0, qd0;
  q0(0) = theta0;
  qd0(0) = 0;
  EXPECT_TRUE(sim.Initialize(q0));
  dyn::MinimalSummary summary;
  sim.Simulate(0.0, q0, qd0, t_end, [](const Sim::SampleT&) { return true; }, &summary);
  return summary;
}

TEST(Switches, ChatteringGuardFollowsTheCrossings) {
  ws::Params<double> p;
  p.T0 = 0;
  p.theta_s = 10;
  p.Kb = 1.0;
  p.theta_b = 1.0;
  p.cd = 0.2;
  const double theta0 = 1.5, t_end = 30.0;
  const std::vector<double> crossings = BangBangCrossings(p, theta0, t_end);
  const int n = static_cast<int>(crossings.size());
  ASSERT_GE(n, 50);
  // Each crossing's interval from the one before shrinks: the swings shorten.
  EXPECT_LT(crossings[n - 1] - crossings[n - 2], 0.5 * (crossings[1] - crossings[0]));
  dyn::MinimalOptions o;
  o.integrator.rtol = 1e-10;
  o.integrator.atol = 1e-10;
  const double scale = 0.5 * p.Kb * (theta0 - p.theta_b);  // the initial energy above theta_b (J)

  const dyn::MinimalSummary all = RunBangBang(p, theta0, t_end, o);
  std::printf("bang-bang with damping: %d crossings in %g s (the last %.3g s apart); defaults: %s\n", n, t_end,
              crossings[n - 1] - crossings[n - 2], dyn::FormatSummary(all).c_str());
  ASSERT_EQ(all.status, dyn::Status::kSuccess);
  EXPECT_EQ(all.switch_restarts, n);
  EXPECT_EQ(all.switches_through, 0);
  EXPECT_LT(all.max_energy_error, 1e-9 * scale);

  dyn::MinimalOptions capped = o;
  capped.max_switch_restarts = 20;
  const dyn::MinimalSummary cap = RunBangBang(p, theta0, t_end, capped);
  std::printf("  max_switch_restarts = 20: %s\n", dyn::FormatSummary(cap).c_str());
  ASSERT_EQ(cap.status, dyn::Status::kSuccess);
  EXPECT_EQ(cap.switch_restarts, 20);
  EXPECT_EQ(cap.switches_through, n - 20);
  EXPECT_NE(std::string(cap.message).find("max_switch_restarts"), std::string::npos);

  dyn::MinimalOptions spaced = o;
  spaced.switch_min_interval = 0.5;
  int restarted = 0, through = 0;
  double t_last = -1e300;
  for (double tc : crossings) {
    ASSERT_GT(std::abs(tc - t_last - spaced.switch_min_interval), 1e-6);  // no crossing on the fence
    if (tc - t_last >= spaced.switch_min_interval) {
      ++restarted;
      t_last = tc;
    } else {
      ++through;
    }
  }
  const dyn::MinimalSummary space = RunBangBang(p, theta0, t_end, spaced);
  std::printf("  switch_min_interval = 0.5 s: %s (closed form: %d restarted, %d through)\n",
              dyn::FormatSummary(space).c_str(), restarted, through);
  ASSERT_EQ(space.status, dyn::Status::kSuccess);
  EXPECT_EQ(space.switch_restarts, restarted);
  EXPECT_EQ(space.switches_through, through);
  EXPECT_GT(through, 0);
}

// Driven at constant speed omega (PrescribedDynamics, inverse dynamics: no free coordinate),
// the actuator holds the speed against the switched torque: lambda = -Q, and its work from
// theta0 is -T0 times the angle turned inside [theta_s, 2 pi) of each turn (the closed form);
// a restart per crossing.
TEST(Switches, DrivenWheelActuatorWorkWithRestarts) {
  ws::Params<double> p;  // T0 = 3, theta_s = 4
  const double theta0 = 0.5, omega = 3.0, t_end = 5.0;
  auto drive = dyn::MakeDrive(dyn::ConstantSpeedLaw{theta0, omega, 0.0});
  using Driven = dyn::PrescribedDynamics<M, 1, decltype(drive)>;
  static_assert(Driven::kHasSwitches, "the driven run sees the switches too");
  const double theta_end = theta0 + omega * t_end;
  double on = 0;
  int crossings = 0;
  for (int k = 0; k < 10; ++k) {
    const double lo = 2 * kPi * k + p.theta_s, hi = 2 * kPi * (k + 1);
    on += std::max(0.0, std::min(theta_end, hi) - std::max(theta0, lo));
    crossings += (lo > theta0 && lo < theta_end) + (hi > theta0 && hi < theta_end);
  }
  const double W_act_exact = -p.T0 * on;
  const int table_points = 3;  // the tent's 1, 2, 3 rad, passed in the first turn
  for (bool restart : {true, false}) {
    dyn::PrescribedOptions o;
    o.integrator.rtol = 1e-12;
    o.integrator.atol = 1e-12;
    o.restart_at_switches = restart;
    Driven sim(p, {0}, drive, dyn::NoForce(), o);
    ASSERT_TRUE(sim.Initialize(0.0, Driven::VecF()));
    dyn::PrescribedSummary summary;
    Driven::SampleT last;
    ASSERT_TRUE(sim.Simulate(0.0, Driven::VecF(), Driven::VecF(), t_end, [](const Driven::SampleT&) { return true; },
                             &summary, &last))
        << dyn::FormatSummary(summary);
    std::printf("driven wheel, restarts %s: W_act = %.15g, closed form %.15g, |dW| = %.3g, %d steps, %d restarts\n",
                restart ? "on " : "off", last.W_act, W_act_exact, std::abs(last.W_act - W_act_exact),
                summary.integrator.steps, summary.switch_restarts);
    if (restart) {
      EXPECT_EQ(summary.switch_restarts, crossings + table_points) << dyn::FormatSummary(summary);
      EXPECT_NEAR(last.W_act, W_act_exact, 1e-10 * std::abs(W_act_exact));
      EXPECT_NEAR(last.W_nc, -W_act_exact, 1e-10 * std::abs(W_act_exact));  // the load's work
    } else {
      EXPECT_EQ(summary.switch_restarts, 0);
    }
  }
}

}  // namespace
