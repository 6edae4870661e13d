// Steady-state detection in the one simulator (dynamics/simulator.h: SteadyStateOptions,
// SteadyStateSummary), on the generated compound pendulum (tests/dynamics/models/pendulum.yaml).
//
// Oracles, each independent of the simulator:
//  - a rotor driven by a constant torque T against a viscous damper c (the pendulum with g = 0
//    and that load): I_O w' = T - c w has the closed form w(t) = w_inf + (w0 - w_inf) e^(-t/tau),
//    theta(t) = theta0 + w_inf t + (w0 - w_inf) tau (1 - e^(-t/tau)), w_inf = T / c,
//    tau = I_O / c. The crossing times of theta0 + 2 pi k, found here by Newton on the closed
//    form, give the cycle-mean speeds and the cycle at which the definition holds first; the
//    detector must stop there, with that period, and its mean speed must be w_inf to within
//    the tolerance;
//  - a pendulum revolving under gravity without losses (energy conserved): its motion is
//    exactly periodic, with the period P = integral over a turn of dtheta / w(theta),
//    w(theta)^2 = w0^2 - 2 m g lc (sin theta - sin theta0) / I_O, by the trapezoidal rule
//    (exponentially accurate for a smooth periodic integrand); it is steady after N + 1 cycles;
//  - the rotor driven backwards is the mirror image: the same cycles and periods;
//  - runs that never become steady say so: an oscillating pendulum (it passes its start level
//    back and forth, which completes no cycle) and the rotor stopped before it settles (its last change, from the closed form, above
//    the tolerance).
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "mechgen/dynamics/forward.h"
#include "pendulum.h"

namespace {

namespace dyn = mechgen::dynamics;
using M = mech::pendulum::Model;
constexpr double kPi = 3.14159265358979323846;

/// T - c qd on the one input: a constant drive torque and a viscous damper.
struct TorqueAndDamper {
  double T = 0, c = 0;
  template <class VecQ, class MatK>
  void operator()(double /*t*/, const VecQ& /*q*/, const VecQ& qd, const MatK& /*K*/, VecQ* Q) const {
    (*Q)(0) = T - c * qd(0);
  }
};
using Rotor = dyn::MinimalDynamics<M, dyn::Dopri5, TorqueAndDamper>;
using Free = dyn::MinimalDynamics<M>;

struct RunResult {
  dyn::MinimalSummary summary;
  std::vector<double> t;             // the samples the observer saw
  std::vector<int> cycles_seen;      // summary.steady.cycles when the observer saw each sample
  bool steady_seen_by_observer = false;
};

template <class Sim, class Params, class Load>
RunResult Simulate(const Params& p, const Load& load, double theta0, double omega0, double t_end,
             const dyn::SteadyStateOptions& steady) {
  dyn::MinimalOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-12;
  o.sample_dt = 1e-3;
  o.steady = steady;
  Sim sim(p, o, load);
  typename Sim::VecQ q0, qd0;
  q0(0) = theta0;
  qd0(0) = omega0;
  RunResult run;
  EXPECT_TRUE(sim.Initialize(q0));
  sim.Simulate(0.0, q0, qd0, t_end, [&](const auto& s) {
    run.t.push_back(s.t);
    run.cycles_seen.push_back(run.summary.steady.cycles);
    run.steady_seen_by_observer = run.summary.steady.steady;
    return true;
  }, &run.summary);
  return run;
}

/// The damped driven rotor in closed form.
struct ClosedFormRotor {
  double I, T, c, w0;
  double w_inf() const { return T / c; }
  double tau() const { return I / c; }
  double Angle(double t) const { return w_inf() * t + (w0 - w_inf()) * tau() * (1 - std::exp(-t / tau())); }
  double Speed(double t) const { return w_inf() + (w0 - w_inf()) * std::exp(-t / tau()); }
  /// The time at which the angle has advanced by 2 pi k (Newton; the speed stays > 0).
  double Crossing(int k) const {
    double t = 2 * kPi * k / w_inf();
    for (int it = 0; it < 60; ++it) t -= (Angle(t) - 2 * kPi * k) / Speed(t);
    return t;
  }
};

/// The definition of simulator.h applied to exact crossing times t[1], t[2], ...: the first
/// cycle n (counted from 1, cycle n between crossings n and n + 1) after which the last
/// `consecutive` changes of the mean speed are all below tolerance times w_n; also the
/// smallest relative margin |change - tol w_n| / (tol w_n) of the checks that decide it.
struct Verdict {
  int cycle = -1;
  double margin = 0;
};
Verdict Definition(const std::vector<double>& t_cross, double tolerance, int consecutive) {
  std::vector<double> w;
  for (size_t k = 1; k < t_cross.size(); ++k) w.push_back(2 * kPi / (t_cross[k] - t_cross[k - 1]));
  Verdict v;
  v.margin = 1e300;
  for (int n = consecutive + 1; n <= static_cast<int>(w.size()); ++n) {
    bool all = true;
    for (int i = n - consecutive + 1; i <= n; ++i) {
      const double change = std::abs(w[i - 1] - w[i - 2]), bound = tolerance * w[n - 1];
      v.margin = std::min(v.margin, std::abs(change - bound) / bound);
      all = all && change < bound;
    }
    if (all) {
      v.cycle = n;
      return v;
    }
  }
  return v;
}

TEST(SteadyState, DampedDrivenRotorStopsAtTheCycleTheClosedFormGives) {
  mech::pendulum::Params<double> p;
  p.g = 0;
  const TorqueAndDamper load{2.0, 0.5};
  const ClosedFormRotor exact{p.J + p.m * p.lc * p.lc, load.T, load.c, 1.0};
  dyn::SteadyStateOptions steady;
  steady.enabled = true;
  steady.tolerance = 1e-3;
  steady.consecutive = 2;
  std::vector<double> t_cross{0.0};  // index k: the k-th crossing (index 0 unused)
  for (int k = 1; k <= 40; ++k) t_cross.push_back(exact.Crossing(k));
  const std::vector<double> crossings(t_cross.begin() + 1, t_cross.end());
  const Verdict v = Definition(crossings, steady.tolerance, steady.consecutive);
  ASSERT_GT(v.cycle, 3);
  ASSERT_GT(v.margin, 0.01);  // no check within 1 % of its bound: integration error cannot flip it

  const RunResult run = Simulate<Rotor>(p, load, 0.3, exact.w0, 60.0, steady);
  const auto& s = run.summary.steady;
  ASSERT_EQ(run.summary.status, dyn::Status::kStoppedByEvent) << run.summary.message;
  EXPECT_EQ(run.summary.event, dyn::Event::kSteadyState);
  EXPECT_TRUE(s.steady);
  EXPECT_EQ(s.cycles, v.cycle);
  EXPECT_EQ(s.crossings, v.cycle + 1);
  // Cycle n ends at crossing n + 1.
  EXPECT_NEAR(s.t_crossing, crossings[v.cycle], 1e-8);
  EXPECT_NEAR(s.period, crossings[v.cycle] - crossings[v.cycle - 1], 1e-8);
  EXPECT_NEAR(s.mean_speed, 2 * kPi / s.period, 1e-15 * s.mean_speed);
  const double w_n = 2 * kPi / (crossings[v.cycle] - crossings[v.cycle - 1]);
  const double w_prev = 2 * kPi / (crossings[v.cycle - 1] - crossings[v.cycle - 2]);
  EXPECT_NEAR(s.last_change, std::abs(w_n - w_prev) / w_n, 1e-8);
  EXPECT_LT(s.last_change, steady.tolerance);
  // The steady state of the closed form: w_inf = T / c, reached to within the tolerance.
  EXPECT_NEAR(s.mean_speed, exact.w_inf(), 2 * steady.tolerance * exact.w_inf());
  // The run stopped at the sample that showed it, which the observer saw with the summary.
  EXPECT_EQ(s.t_steady, run.summary.t_end);
  EXPECT_EQ(run.t.back(), s.t_steady);
  EXPECT_TRUE(run.steady_seen_by_observer);
  EXPECT_GT(s.t_steady, crossings[v.cycle]);
  EXPECT_LT(s.t_steady, crossings[v.cycle] + 2e-3);  // within the sample spacing of it
  // The observer saw the cycle count rise one cycle at a time.
  for (size_t i = 1; i < run.cycles_seen.size(); ++i) {
    EXPECT_GE(run.cycles_seen[i], run.cycles_seen[i - 1]);
    EXPECT_LE(run.cycles_seen[i], run.cycles_seen[i - 1] + 1);
  }
}

TEST(SteadyState, RotorDrivenBackwardsIsTheMirrorImage) {
  mech::pendulum::Params<double> p;
  p.g = 0;
  dyn::SteadyStateOptions steady;
  steady.enabled = true;
  steady.tolerance = 1e-3;
  const RunResult forward = Simulate<Rotor>(p, TorqueAndDamper{2.0, 0.5}, 0.3, 1.0, 60.0, steady);
  const RunResult backward = Simulate<Rotor>(p, TorqueAndDamper{-2.0, 0.5}, 0.3, -1.0, 60.0, steady);
  const auto &f = forward.summary.steady, &b = backward.summary.steady;
  ASSERT_TRUE(f.steady);
  ASSERT_TRUE(b.steady);
  EXPECT_EQ(b.crossings, f.crossings);
  EXPECT_EQ(b.cycles, f.cycles);
  EXPECT_NEAR(b.t_crossing, f.t_crossing, 1e-8);
  EXPECT_NEAR(b.period, f.period, 1e-8);
  EXPECT_NEAR(b.mean_speed, f.mean_speed, 1e-7);
  EXPECT_NEAR(b.last_change, f.last_change, 1e-8);
}

TEST(SteadyState, ConservativeRevolvingPendulumIsSteadyAfterNPlusOneCyclesWithItsPeriod) {
  const mech::pendulum::Params<double> p;
  const double I = p.J + p.m * p.lc * p.lc, theta0 = -kPi / 2, w0 = 9.0;
  auto w = [&](double th) {
    return std::sqrt(w0 * w0 - 2 * p.m * p.g * p.lc * (std::sin(th) - std::sin(theta0)) / I);
  };
  ASSERT_GT(w0 * w0 * I / 2, 2 * p.m * p.g * p.lc);  // it goes over the top
  const int n = 4000;
  double period = 0;
  for (int i = 0; i < n; ++i) period += (2 * kPi / n) / w(theta0 + 2 * kPi * i / n);
  dyn::SteadyStateOptions steady;
  steady.enabled = true;
  steady.tolerance = 1e-6;
  steady.consecutive = 3;
  const RunResult run = Simulate<Free>(p, dyn::NoLoad(), theta0, w0, 100.0, steady);
  const auto& s = run.summary.steady;
  ASSERT_EQ(run.summary.status, dyn::Status::kStoppedByEvent) << run.summary.message;
  EXPECT_TRUE(s.steady);
  EXPECT_EQ(s.cycles, steady.consecutive + 1);
  EXPECT_NEAR(s.period, period, 1e-8 * period);
  EXPECT_NEAR(s.mean_speed, 2 * kPi / period, 1e-8 * s.mean_speed);
  EXPECT_LT(s.last_change, 1e-8);
  // The first crossing is one period after the start (the start is a level, not a crossing).
  EXPECT_NEAR(s.t_crossing, (steady.consecutive + 2) * period, 1e-7);
}

TEST(SteadyState, RunsThatNeverSettleSaySo) {
  dyn::SteadyStateOptions steady;
  steady.enabled = true;
  steady.tolerance = 1e-3;
  {
    // An oscillating pendulum passes only its start level theta0, back and forth: never a
    // crossing of another level, no cycle.
    const mech::pendulum::Params<double> p;
    const RunResult run = Simulate<Free>(p, dyn::NoLoad(), -kPi / 2, 3.0, 10.0, steady);
    const auto& s = run.summary.steady;
    EXPECT_EQ(run.summary.status, dyn::Status::kSuccess) << run.summary.message;
    EXPECT_EQ(run.summary.event, dyn::Event::kNone);
    EXPECT_FALSE(s.steady);
    EXPECT_EQ(s.crossings, 0);
    EXPECT_EQ(s.cycles, 0);
    EXPECT_TRUE(std::isnan(s.period));
    EXPECT_TRUE(std::isnan(s.last_change));
    EXPECT_TRUE(std::isnan(s.t_steady));
  }
  {
    // The damped driven rotor, stopped after 8 s: still speeding up by more than the tolerance.
    mech::pendulum::Params<double> p;
    p.g = 0;
    const TorqueAndDamper load{2.0, 0.5};
    const ClosedFormRotor exact{p.J + p.m * p.lc * p.lc, load.T, load.c, 1.0};
    const RunResult run = Simulate<Rotor>(p, load, 0.3, exact.w0, 8.0, steady);
    const auto& s = run.summary.steady;
    EXPECT_EQ(run.summary.status, dyn::Status::kSuccess) << run.summary.message;
    EXPECT_FALSE(s.steady);
    std::vector<double> crossings;
    for (int k = 1; exact.Crossing(k) < 8.0; ++k) crossings.push_back(exact.Crossing(k));
    ASSERT_GE(crossings.size(), 3u);
    EXPECT_EQ(s.crossings, static_cast<int>(crossings.size()));
    EXPECT_EQ(s.cycles, static_cast<int>(crossings.size()) - 1);
    const size_t m = crossings.size();
    const double w_n = 2 * kPi / (crossings[m - 1] - crossings[m - 2]);
    const double w_prev = 2 * kPi / (crossings[m - 2] - crossings[m - 3]);
    EXPECT_NEAR(s.last_change, std::abs(w_n - w_prev) / w_n, 1e-8);
    EXPECT_GT(s.last_change, steady.tolerance);
    EXPECT_TRUE(std::isnan(s.t_steady));
  }
}

TEST(SteadyState, DisabledOrInvalidOptions) {
  const mech::pendulum::Params<double> p;
  dyn::SteadyStateOptions steady;  // off: nothing counted, the run goes to t_end
  {
    const RunResult run = Simulate<Free>(p, dyn::NoLoad(), -kPi / 2, 9.0, 5.0, steady);
    EXPECT_EQ(run.summary.status, dyn::Status::kSuccess);
    EXPECT_EQ(run.summary.steady.crossings, 0);
    EXPECT_FALSE(run.summary.steady.steady);
  }
  steady.enabled = true;
  for (int bad = 0; bad < 4; ++bad) {
    dyn::SteadyStateOptions o = steady;
    if (bad == 0) o.coordinate = 1;  // the pendulum has one input
    if (bad == 1) o.cycle = 0;
    if (bad == 2) o.tolerance = std::nan("");
    if (bad == 3) o.consecutive = 17;
    const RunResult run = Simulate<Free>(p, dyn::NoLoad(), -kPi / 2, 9.0, 5.0, o);
    EXPECT_EQ(run.summary.status, dyn::Status::kInvalidInput) << bad;
    EXPECT_TRUE(run.t.empty()) << bad;
  }
}

}  // namespace
