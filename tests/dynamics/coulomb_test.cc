// Coulomb friction in the free simulation, with stick and slip (issue 26; dynamics/friction.h,
// the transitions of dynamics/simulator.h), against oracles independent of the runtime:
//  - a block on an incline (tests/dynamics/models/incline_friction.yaml: a slider under
//    gravity, friction mu on the normal force m g cos alpha): released at rest it slides with
//    s'' = -g (sin alpha - mu cos alpha) exactly when tan alpha > mu and stays put otherwise;
//    launched up the slope at v0 it decelerates at g (sin alpha + mu cos alpha), stops at
//    t1 = v0 / that at s1 = v0^2 / (2 that), then slides back or sticks by tan alpha vs mu;
//  - the block on a level track pushed by F0 sin(w t): stuck while |F| <= mu m g, slipping with
//    v(t) = F0 / (m w) (cos(w t_b) - cos(w t)) - mu g (t - t_b) from a breakaway t_b, every
//    transition time from these closed forms (roots by bisection here), and exactly as many
//    transitions as they give (no chattering);
//  - a compound pendulum with pin friction (pendulum_friction.yaml: the friction circle mu r
//    on the pin force, which depends on the motion): the friction torque against mu r |F_O|
//    with F_O = m (a_G - g) by the free body of the arm, the energy non-increasing, the
//    energy lost equal to the integral of the friction torque times the angular velocity
//    (a trapezoid over the samples, not the runtime's W), and at rest at an angle where
//    |m g lc cos theta| <= mu r m g (the pin force at rest is the weight);
//  - mu = 0: the run is the frictionless pendulum's (pendulum.yaml) to the last bit;
//  - two inputs (two_pendulums_friction.yaml, friction at both pins): the coupled run equals
//    two single-pendulum runs, one pendulum stuck while the other swings; all mu = 0: the
//    frictionless run to the last bit; a joint whose relative motion combines both inputs (a
//    wrapper of the kinetostatics) ends the run at its relative rest with a status naming it;
//  - a brief breakaway inside one stuck step, seen by its stages, at the closed-form time;
//  - the slider-crank with friction at every joint (slider_crank_coulomb.yaml) driven both
//    ways against the Newton-Euler balance of its links, and running free on a 720 deg gas
//    load written in the model, against the energy balance;
//  - several inputs through the model view (issue 43: MinimalDynamics<ViewModel> of the
//    runtime compiled once, on the two pendulums' view): every sample, the summary and each
//    joint's mode the fixed-size instantiation's, to the bit;
//  - driven runs (prescribed.h): the motor torque of a pendulum at constant speed and through a
//    rest-to-rest move by the free body of the arm with the friction torque mu r |F_O| and by
//    the energy balance (motor work = dE + friction work), the block's actuator force on the
//    incline in closed form, mu = 0 bit for bit the frictionless run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <tuple>
#include <vector>

#include "incline_friction.h"
#include "mechgen/core/view_runtime.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/prescribed.h"
#include "pendulum.h"
#include "pendulum_friction.h"
#include "slider_crank_coulomb.h"
#include "two_pendulums_friction.h"

namespace mech::two_pendulums_friction {
const mechgen::ModelView& View();  // (its generated two_pendulums_friction_view.cc)
}

namespace {

namespace dyn = mechgen::dynamics;
constexpr double kPi = 3.14159265358979323846;

using Incline = mech::incline_friction::Model;
using Pendulum = mech::pendulum_friction::Model;
static_assert(dyn::MinimalDynamics<Incline>::kHasCoulomb, "the incline's slide has Coulomb friction");
static_assert(dyn::MinimalDynamics<Pendulum>::kHasCoulomb, "the pendulum's pin has Coulomb friction");

template <class M>
struct Run {
  dyn::MinimalSummary summary;
  std::vector<dyn::Sample<M>> samples;
};

template <class M>
Run<M> Simulate(const typename M::template ParamsT<double>& p,
                double q0,
                double qd0,
                double t_end,
                double dt,
                double rtol = 1e-11) {
  dyn::MinimalOptions o;
  o.integrator.rtol = rtol;
  o.integrator.atol = 1e-13;
  o.sample_dt = dt;
  dyn::MinimalDynamics<M> sim(p, o);
  Eigen::Matrix<double, 1, 1> q, qd;
  q(0) = q0;
  qd(0) = qd0;
  Run<M> r;
  EXPECT_TRUE(sim.Initialize(q));
  sim.Simulate(
      0.0, q, qd, t_end,
      [&](const dyn::Sample<M>& s) {
        r.samples.push_back(s);
        return true;
      },
      &r.summary);
  return r;
}

/// The times at which the stuck flag changes (the sample handed out at each transition).
template <class M>
std::vector<double> Transitions(const Run<M>& r) {
  std::vector<double> t;
  for (size_t i = 1; i < r.samples.size(); ++i)
    if (r.samples[i].stuck != r.samples[i - 1].stuck) t.push_back(r.samples[i].t);
  return t;
}

TEST(Coulomb, BlockSlidesDownWhenTanAlphaExceedsMu) {
  mech::incline_friction::Params<double> p;
  p.alpha = 30 * kPi / 180;
  p.mu = 0.3;
  ASSERT_GT(std::tan(p.alpha), p.mu);
  const auto r = Simulate<Incline>(p, 0.0, 0.0, 2.0, 0.01);
  ASSERT_EQ(r.summary.status, dyn::Status::kSuccess) << dyn::FormatSummary(r.summary);
  EXPECT_TRUE(r.summary.coulomb);
  EXPECT_EQ(r.summary.stick_intervals, 0);
  const double a = -p.g * (std::sin(p.alpha) - p.mu * std::cos(p.alpha));
  for (const auto& s : r.samples) {
    EXPECT_NEAR(s.q(0), 0.5 * a * s.t * s.t, 1e-12 + 1e-10 * std::abs(s.q(0))) << s.t;
    EXPECT_NEAR(s.qd(0), a * s.t, 1e-12 + 1e-10 * std::abs(s.qd(0))) << s.t;
    EXPECT_NEAR(s.qdd(0), a, 1e-12) << s.t;
    // Friction up the slope (+u) on the block sliding down: mu m g cos alpha.
    EXPECT_NEAR(s.friction(0), p.mu * p.m * p.g * std::cos(p.alpha), 1e-12) << s.t;
    EXPECT_FALSE(s.stuck);
  }
}

TEST(Coulomb, BlockStaysWhenTanAlphaIsAtMostMu) {
  mech::incline_friction::Params<double> p;
  p.alpha = 10 * kPi / 180;
  p.mu = 0.3;
  ASSERT_LE(std::tan(p.alpha), p.mu);
  const auto r = Simulate<Incline>(p, 0.25, 0.0, 5.0, 0.1);
  ASSERT_EQ(r.summary.status, dyn::Status::kSuccess) << dyn::FormatSummary(r.summary);
  EXPECT_EQ(r.summary.stick_intervals, 1);
  EXPECT_EQ(r.summary.friction_transitions, 0);
  EXPECT_DOUBLE_EQ(r.summary.time_stuck, 5.0);
  ASSERT_EQ(r.samples.size(), 51u);
  for (const auto& s : r.samples) {
    EXPECT_EQ(s.q(0), 0.25);  // not a drift of a bit
    EXPECT_EQ(s.qd(0), 0.0);
    EXPECT_TRUE(s.stuck);
    // Static friction holds the weight's component along the slope: m g sin alpha up it.
    EXPECT_NEAR(s.friction(0), p.m * p.g * std::sin(p.alpha), 1e-12);
  }
}

// Launched up the slope at v0: decelerates at g (sin + mu cos), stops at t1, then slides back
// (tan alpha > mu) or sticks (tan alpha <= mu).
void LaunchedUp(double mu, bool slides_back) {
  mech::incline_friction::Params<double> p;
  p.alpha = 30 * kPi / 180;
  p.mu = mu;
  ASSERT_EQ(std::tan(p.alpha) > p.mu, slides_back);
  const double v0 = 3.0;
  const double a_up = p.g * (std::sin(p.alpha) + p.mu * std::cos(p.alpha));
  const double a_down = -p.g * (std::sin(p.alpha) - p.mu * std::cos(p.alpha));
  const double t1 = v0 / a_up, s1 = v0 * v0 / (2 * a_up);
  const auto r = Simulate<Incline>(p, 0.0, v0, 2.0, 0.01);
  ASSERT_EQ(r.summary.status, dyn::Status::kSuccess) << dyn::FormatSummary(r.summary);
  for (const auto& s : r.samples) {
    double s_ref, v_ref;
    if (s.t <= t1) {
      s_ref = v0 * s.t - 0.5 * a_up * s.t * s.t;
      v_ref = v0 - a_up * s.t;
    } else if (slides_back) {
      s_ref = s1 + 0.5 * a_down * (s.t - t1) * (s.t - t1);
      v_ref = a_down * (s.t - t1);
    } else {
      s_ref = s1;
      v_ref = 0;
    }
    EXPECT_NEAR(s.q(0), s_ref, 1e-9) << s.t;
    EXPECT_NEAR(s.qd(0), v_ref, 1e-9) << s.t;
  }
  if (slides_back) {
    EXPECT_EQ(r.summary.stick_intervals, 0);
    // The turn is a transition sample of its own, at t1: the last sample moving up, then down.
    bool found = false;
    for (const auto& s : r.samples)
      if (std::abs(s.t - t1) < 1e-10) found = true;
    EXPECT_TRUE(found) << "no sample at the stop t1 = " << t1;
  } else {
    const auto t = Transitions(r);
    ASSERT_EQ(t.size(), 1u);
    EXPECT_NEAR(t[0], t1, 1e-10);
    EXPECT_NEAR(r.summary.last_stick_start, t1, 1e-10);
    EXPECT_NEAR(r.summary.time_stuck, 2.0 - t1, 1e-10);
    EXPECT_EQ(r.summary.stick_intervals, 1);
    EXPECT_NEAR(r.samples.back().q(0), s1, 1e-10);
    EXPECT_EQ(r.samples.back().qd(0), 0.0);
  }
}

TEST(Coulomb, BlockLaunchedUpSlidesBack) { LaunchedUp(0.3, true); }
TEST(Coulomb, BlockLaunchedUpSticks) { LaunchedUp(0.7, false); }

// A level track (alpha = 0), the push F0 sin(w t), bound mu m g: every transition time from
// the closed forms, and no others.
TEST(Coulomb, PushedBlockSticksAndSlipsWithoutChattering) {
  mech::incline_friction::Params<double> p;
  p.alpha = 0;
  p.mu = 0.3;
  p.F0 = 10;
  p.w = 2;
  const double B = p.mu * p.m * p.g;
  ASSERT_LT(B, p.F0);
  const double t_end = 12;
  // The oracle: from rest, stuck until |F0 sin(w t)| > B, then v(t) in closed form to its zero.
  std::vector<double> oracle;
  double t = 0;
  const double beta = std::asin(B / p.F0);
  for (int k = 0; k < 20; ++k) {
    // The next breakaway after t: w t in (k' pi + beta, k' pi + pi - beta) for some k'.
    double tb = std::numeric_limits<double>::infinity();
    for (int kk = 0; kk < 40 && !(tb < t_end); ++kk) {
      const double lo = (kk * kPi + beta) / p.w, hi = (kk * kPi + kPi - beta) / p.w;
      if (hi > t) tb = std::max(lo, t);
    }
    if (!(tb < t_end)) break;
    const double e = std::sin(p.w * tb) > 0 ? 1.0 : -1.0;
    auto v = [&](double tt) {
      return p.F0 / (p.m * p.w) * (std::cos(p.w * tb) - std::cos(p.w * tt)) - e * p.mu * p.g * (tt - tb);
    };
    // Its stop: the first zero of v after tb (e v > 0 after tb: it starts as e F0 w
    // cos(w tb) (t - tb)^2 / (2 m), some 4e-6 m/s 1 ms on; a scan, then bisection).
    double ta = tb + 1e-3, tz = ta;
    while (e * v(tz) > 0 && tz < t_end + 10) tz += 1e-3;
    ta = tz - 1e-3;
    for (int it = 0; it < 100; ++it) {
      const double tm = 0.5 * (ta + tz);
      (e * v(tm) > 0 ? ta : tz) = tm;
    }
    oracle.push_back(tb);
    if (tz >= t_end) break;
    oracle.push_back(tz);
    t = tz;
  }
  ASSERT_GE(oracle.size(), 6u);
  const auto r = Simulate<Incline>(p, 0.0, 0.0, t_end, 0.01);
  ASSERT_EQ(r.summary.status, dyn::Status::kSuccess) << dyn::FormatSummary(r.summary);
  EXPECT_EQ(r.summary.chattering, 0);
  const auto got = Transitions(r);
  ASSERT_EQ(got.size(), oracle.size());
  double worst = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_NEAR(got[i], oracle[i], 1e-8) << i;
    worst = std::max(worst, std::abs(got[i] - oracle[i]));
  }
  std::printf("pushed block: %zu transitions, max |t - t_oracle| = %.3g s; %s\n", got.size(), worst,
              dyn::FormatSummary(r.summary).c_str());
  EXPECT_EQ(r.summary.friction_transitions, static_cast<int>(oracle.size()));
  // While stuck the position does not move; while slipping the friction is the bound.
  for (size_t i = 1; i < r.samples.size(); ++i) {
    const auto& s = r.samples[i];
    if (s.stuck && r.samples[i - 1].stuck) {
      EXPECT_EQ(s.q(0), r.samples[i - 1].q(0));
    }
    if (s.stuck) {
      EXPECT_LE(std::abs(s.friction(0)), B * (1 + 1e-12));
    } else {
      EXPECT_NEAR(std::abs(s.friction(0)), B, 1e-12);
    }
  }
}

// A breakaway shorter than a stuck step: the block on a level track stuck from rest while the
// push F0 sin(w t) stays below the bound B = mu m g, every step's end sampled (sample_dt = 0)
// and no stick_step, so the stuck steps grow tenfold each (nothing moves) and one of them
// spans the whole window where |F| > B; its stages see the breakaway, which is located at
// t_b = asin(B / F0) / w (closed form) although the step's end is stuck again.
TEST(Coulomb, BriefBreakawayWithinAStuckStep) {
  mech::incline_friction::Params<double> p;
  p.alpha = 0;
  p.mu = 0.3;
  p.F0 = 6.5;
  p.w = 2;
  const double B = p.mu * p.m * p.g;
  const double t_b = std::asin(B / p.F0) / p.w;
  dyn::MinimalOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-13;
  o.sample_dt = 0;
  dyn::MinimalDynamics<Incline> sim(p, o);
  Eigen::Matrix<double, 1, 1> q, qd;
  q(0) = 0;
  qd(0) = 0;
  ASSERT_TRUE(sim.Initialize(q));
  std::vector<dyn::Sample<Incline>> samples;
  dyn::MinimalSummary s;
  sim.Simulate(
      0.0, q, qd, 1.2,
      [&](const dyn::Sample<Incline>& x) {
        samples.push_back(x);
        return true;
      },
      &s);
  ASSERT_EQ(s.status, dyn::Status::kSuccess) << dyn::FormatSummary(s);
  // The stuck steps from rest: 1e-6, then tenfold, so the one from 0.111 s ends at 1.111 s,
  // past the window (t_b, (pi - asin(B / F0)) / w = 1.004 s) and stuck again there: only its
  // stages (at 0.2, 0.3, 0.8, 0.89 of it) see |F| > B. The transition's row follows that step's
  // start directly.
  ::Run<Incline> r;
  r.samples = samples;
  const auto t = Transitions(r);
  ASSERT_GE(t.size(), 1u) << "the breakaway was missed";
  EXPECT_NEAR(t[0], t_b, 1e-9);
  size_t i_b = 0;
  while (samples[i_b].t < t[0]) ++i_b;
  const double t_step = samples[i_b - 1].t;
  std::printf("brief breakaway: at %.12g s (closed form %.12g s), in the stuck step from %.9g s\n", t[0], t_b, t_step);
  EXPECT_LT(t_step, 0.12);
  EXPECT_GT(t_step + 10 * (t_step - samples[i_b - 2].t), (kPi - std::asin(B / p.F0)) / p.w);
}

// The chattering guard: transitions closer than CoulombOptions::min_interval end the run after
// max_chattering of them (here every transition of the pushed block counts), with a status and
// a message, never a loop without end; every sample finite.
TEST(Coulomb, ChatteringGuardEndsTheRun) {
  mech::incline_friction::Params<double> p;
  p.alpha = 0;
  p.F0 = 10;
  dyn::MinimalOptions o;
  o.sample_dt = 0.01;
  o.coulomb.min_interval = 100;
  o.coulomb.max_chattering = 2;
  dyn::MinimalDynamics<Incline> sim(p, o);
  Eigen::Matrix<double, 1, 1> q, qd;
  q(0) = 0;
  qd(0) = 0;
  ASSERT_TRUE(sim.Initialize(q));
  dyn::MinimalSummary s;
  int samples = 0;
  bool finite = true;
  sim.Simulate(
      0.0, q, qd, 12.0,
      [&](const dyn::Sample<Incline>& x) {
        ++samples;
        finite = finite && x.q.allFinite() && x.qd.allFinite() && x.friction.allFinite();
        return true;
      },
      &s);
  EXPECT_EQ(s.status, dyn::Status::kFrictionFailed);
  EXPECT_EQ(s.chattering, 2);
  EXPECT_EQ(s.friction_transitions, 3);  // the first has no transition before it
  EXPECT_NE(std::string(s.message).find("chattering"), std::string::npos) << s.message;
  EXPECT_TRUE(finite);
  EXPECT_LT(s.t_end, 12.0);
}

// Friction near jamming: a pin friction circle so large (mu r m lc = 6 > I_O = 1.01) that the
// fixed-point iteration of the slip's friction torque on the pin force does not contract: a
// status (kFrictionFailed) with a message, never a NaN.
TEST(Coulomb, JammingIsAStatus) {
  mech::pendulum_friction::Params<double> p;
  p.mu = 1;
  p.r = 5;
  const auto r = Simulate<Pendulum>(p, -kPi / 2, 3.0, 1.0, 0.01);
  EXPECT_EQ(r.summary.status, dyn::Status::kFrictionFailed) << dyn::FormatSummary(r.summary);
  EXPECT_NE(std::string(r.summary.message).find("did not converge"), std::string::npos) << r.summary.message;
  for (const auto& s : r.samples) EXPECT_TRUE(s.q.allFinite() && s.qd.allFinite() && s.friction.allFinite());
}

// The pendulum with pin friction: the friction torque from the free body of the arm, the
// energy's decrease and balance, and the angle it comes to rest at.
TEST(Coulomb, PendulumWithPinFriction) {
  mech::pendulum_friction::Params<double> p;
  p.r = 0.1;  // mu r = 0.02 m: at rest within some 30 s
  const double dt = 5e-4;
  const auto r = Simulate<Pendulum>(p, 0.0, 0.0, 60.0, dt);
  ASSERT_EQ(r.summary.status, dyn::Status::kSuccess) << dyn::FormatSummary(r.summary);
  const auto& last = r.samples.back();
  ASSERT_TRUE(last.stuck) << "the pendulum did not come to rest in 60 s";
  EXPECT_EQ(r.summary.stick_intervals, 1);
  // At rest the pin force is the weight: it holds where |m g lc cos theta| <= mu r m g ...
  EXPECT_LE(std::abs(p.m * p.g * p.lc * std::cos(last.q(0))), p.mu * p.r * p.m * p.g * (1 + 1e-12));
  // ... and it did not stop where it started or at the bottom by accident.
  EXPECT_GT(std::abs(std::cos(last.q(0))), 1e-4);
  const double E0 = r.samples.front().E;
  double dissipated = 0, max_rise = 0;
  int checked = 0;
  for (size_t i = 0; i < r.samples.size(); ++i) {
    const auto& s = r.samples[i];
    const double th = s.q(0), w = s.qd(0), al = s.qdd(0);
    if (!s.stuck && i % 50 == 0) {
      // The free body of the arm: F_O = m (a_G - g) with a_G = lc (alpha (-sin, cos) -
      // w^2 (cos, sin)); the friction torque opposes w at mu r |F_O|.
      const double ax = p.lc * (-al * std::sin(th) - w * w * std::cos(th));
      const double ay = p.lc * (al * std::cos(th) - w * w * std::sin(th));
      const double F = p.m * std::hypot(ax, ay + p.g);
      if (w != 0) {
        EXPECT_NEAR(s.friction(0), -(w > 0 ? 1 : -1) * p.mu * p.r * F, 1e-11 * p.m * p.g) << s.t;
        ++checked;
      }
      // The equation of motion by hand: I_O alpha = -m g lc cos theta + f.
      EXPECT_NEAR((p.J + p.m * p.lc * p.lc) * al, -p.m * p.g * p.lc * std::cos(th) + s.friction(0), 1e-10) << s.t;
    }
    if (i > 0) {
      const auto& a = r.samples[i - 1];
      max_rise = std::max(max_rise, s.E - a.E);
      // The power of the friction torque, f times the relative angular velocity (trapezoid).
      dissipated -= 0.5 * (a.friction(0) * a.qd(0) + s.friction(0) * s.qd(0)) * (s.t - a.t);
    }
  }
  EXPECT_GT(checked, 100);
  std::printf(
      "pendulum: at rest at theta = %.9g rad (|cos| %.4g <= mu r / lc = %.4g) from t = %.9g s; "
      "E0 - E = %.12g J, trapezoid of f w = %.12g J, -W = %.12g J; %s\n",
      last.q(0), std::abs(std::cos(last.q(0))), p.mu * p.r / p.lc, r.summary.last_stick_start, E0 - last.E, dissipated,
      -last.W, dyn::FormatSummary(r.summary).c_str());
  EXPECT_LE(max_rise, 1e-9 * E0 + 1e-9);  // E non-increasing (to the integration's tolerance)
  const double lost = E0 - last.E;
  EXPECT_GT(lost, 0.5);
  // The trapezoid's own error (dt^2 / 12 times the power's second derivative) is ~1e-7 of it.
  EXPECT_NEAR(lost, dissipated, 1e-5 * lost);
  // The runtime's W, the integral of P_nc (the friction's power here) to the integration's
  // tolerance: T + V - W stays E0.
  EXPECT_NEAR(-last.W, dissipated, 1e-5 * lost);
  EXPECT_LT(r.summary.max_energy_error, 1e-8 * std::abs(E0) + 1e-8);
}

// mu = 0: the frictionless pendulum's run to the last bit (friction on, but no Coulomb gain).
TEST(Coulomb, ZeroMuIsTheFrictionlessRun) {
  mech::pendulum_friction::Params<double> pf;
  pf.mu = 0;
  mech::pendulum::Params<double> p0;
  ASSERT_EQ(p0.l, pf.l);
  ASSERT_EQ(p0.lc, pf.lc);
  ASSERT_EQ(p0.m, pf.m);
  ASSERT_EQ(p0.J, pf.J);
  ASSERT_EQ(p0.g, pf.g);
  const auto rf = Simulate<Pendulum>(pf, 0.3, 0.0, 5.0, 0.01);
  const auto r0 = Simulate<mech::pendulum::Model>(p0, 0.3, 0.0, 5.0, 0.01);
  EXPECT_FALSE(rf.summary.coulomb);
  ASSERT_EQ(rf.samples.size(), r0.samples.size());
  for (size_t i = 0; i < rf.samples.size(); ++i) {
    EXPECT_EQ(rf.samples[i].t, r0.samples[i].t);
    EXPECT_EQ(rf.samples[i].q(0), r0.samples[i].q(0)) << i;
    EXPECT_EQ(rf.samples[i].qd(0), r0.samples[i].qd(0)) << i;
  }
}

// Several inputs (two_pendulums_friction.yaml: two uncoupled pendulums, pin friction at both):
// each joint slips and sticks on its own, so the coupled run must be two single-pendulum runs
// (pendulum_friction.yaml with the same arm), themselves checked above against the free body
// and the energy balance. Pendulum 1 has a large friction circle and comes to rest within a
// few swings while pendulum 2 keeps swinging (mixed stick and slip: its input held while the
// other moves); both start at rest at the horizontal (the joint decision at t0 releases both).
TEST(Coulomb, SeveralInputsAreTwoSinglePendulums) {
  using M2 = mech::two_pendulums_friction::Model;
  static_assert(dyn::MinimalDynamics<M2>::kHasCoulomb, "two inputs: each joint its own mode");
  mech::two_pendulums_friction::Params<double> p2;
  p2.r = 0.2;    // mu r = 0.04 m at O1: at rest where |cos theta| <= 0.1
  p2.r2 = 0.01;  // mu2 r2 = 0.002 m at O2: swings on
  const double t_end = 12, dt = 0.01;
  mech::pendulum_friction::Params<double> p1;
  p1.lc = p2.lc;
  p1.m = p2.m;
  p1.J = p2.J;
  p1.g = p2.g;
  p1.mu = p2.mu;
  p1.r = p2.r;
  const double q10 = 0.0, q20 = 0.0;
  const auto single1 = Simulate<Pendulum>(p1, q10, 0.0, t_end, dt);
  p1.mu = p2.mu2;
  p1.r = p2.r2;
  const auto single2 = Simulate<Pendulum>(p1, q20, 0.0, t_end, dt);
  ASSERT_EQ(single1.summary.status, dyn::Status::kSuccess);
  ASSERT_EQ(single2.summary.status, dyn::Status::kSuccess);

  dyn::MinimalOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-13;
  o.sample_dt = dt;
  dyn::MinimalDynamics<M2> sim(p2, o);
  Eigen::Vector2d q(q10, q20), qd(0.0, 0.0);
  ASSERT_TRUE(sim.Initialize(q));
  std::vector<dyn::Sample<M2>> coupled;
  dyn::MinimalSummary s;
  sim.Simulate(
      0.0, q, qd, t_end,
      [&](const dyn::Sample<M2>& x) {
        coupled.push_back(x);
        return true;
      },
      &s);
  ASSERT_EQ(s.status, dyn::Status::kSuccess) << dyn::FormatSummary(s);
  EXPECT_TRUE(s.coulomb);
  std::printf("two pendulums: %s\n", dyn::FormatSummary(s).c_str());
  // The samples on the grid (the transitions' rows lie between) against the single runs'.
  auto on_grid = [&](const auto& samples) {
    std::vector<std::pair<double, std::array<double, 3>>> rows;
    for (const auto& x : samples) {
      const double k = std::round(x.t / dt);
      if (std::abs(x.t - k * dt) < 1e-12) rows.push_back({x.t, {x.q(0), x.qd(0), x.friction(0)}});
    }
    return rows;
  };
  const auto a = on_grid(single1.samples), b = on_grid(single2.samples);
  std::vector<std::pair<double, std::array<double, 3>>> c1, c2;
  for (const auto& x : coupled) {
    const double k = std::round(x.t / dt);
    if (std::abs(x.t - k * dt) >= 1e-12) continue;
    c1.push_back({x.t, {x.q(0), x.qd(0), x.friction(0)}});
    c2.push_back({x.t, {x.q(1), x.qd(1), x.friction(1)}});
  }
  ASSERT_EQ(c1.size(), a.size());
  ASSERT_EQ(c2.size(), b.size());
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(c1[i].first, a[i].first);
    for (int k = 0; k < 3; ++k) {
      const double tol = k == 2 ? 1e-6 : 1e-7;
      // A row within the event tolerance of a transition may sit on either side of it.
      EXPECT_NEAR(c1[i].second[k], a[i].second[k], tol) << "pendulum 1, t = " << a[i].first << ", " << k;
      EXPECT_NEAR(c2[i].second[k], b[i].second[k], tol) << "pendulum 2, t = " << b[i].first << ", " << k;
      if (k < 2)
        worst = std::max({worst, std::abs(c1[i].second[k] - a[i].second[k]), std::abs(c2[i].second[k] - b[i].second[k])});
    }
  }
  std::printf("two pendulums vs two single runs: max |q, qd difference| = %.3g\n", worst);
  // Pendulum 1 at rest (stuck) at the end, pendulum 2 still swinging; the rest angle holds.
  const auto& last = coupled.back();
  EXPECT_TRUE(last.joint_stuck[0]);
  EXPECT_FALSE(last.joint_stuck[1]);
  EXPECT_TRUE(single1.samples.back().stuck);
  EXPECT_NEAR(last.q(0), single1.samples.back().q(0), 1e-8);
  EXPECT_LE(std::abs(std::cos(last.q(0))), p2.mu * p2.r / p2.lc * (1 + 1e-12));
  // Its stick start, from the single run's summary.
  EXPECT_EQ(s.stick_intervals, single1.summary.stick_intervals + single2.summary.stick_intervals);
  EXPECT_NEAR(s.time_stuck, single1.summary.time_stuck + single2.summary.time_stuck, 1e-8);
  // While stuck, the held input does not move by a bit.
  for (size_t i = 1; i < coupled.size(); ++i)
    if (coupled[i].joint_stuck[0] && coupled[i - 1].joint_stuck[0]) {
      EXPECT_EQ(coupled[i].q(0), coupled[i - 1].q(0));
      EXPECT_EQ(coupled[i].qd(0), 0.0);
    }
}

// A joint whose relative motion combines two inputs: the two pendulums with the friction joint
// O1 made to see w1 + w2 (its K_rel row (1, 1), a wrapper of the generated kinetostatics: a
// pin between the arms' rotations, loaded by O1's pin force). It slips as any joint, but where
// its relative velocity reaches zero its stick is not simulated: the run ends with
// kFrictionFailed naming the joint, every sample before finite.
struct TwoPendulumsCoupledJoint : mech::two_pendulums_friction::Model {
  template <typename Scalar, class... Rest>
  static void Kinetostatics(const mech::two_pendulums_friction::Params<Scalar>& p,
                            const Eigen::Matrix<Scalar, 2, 1>& q, const Eigen::Matrix<Scalar, 0, 1>& phi,
                            const Eigen::Matrix<Scalar, 2, 1>& qd, const Eigen::Matrix<Scalar, 2, 1>& qdd,
                            const Scalar& t, const mech::two_pendulums_friction::Coefficients<Scalar>& c,
                            mech::two_pendulums_friction::Statics<Scalar>* out, Rest... rest) {
    // The friction loads' generalized forces through the wrapped K_rel: K_rel^T f on both.
    Eigen::Matrix<Scalar, 2, 1> f = Eigen::Matrix<Scalar, 2, 1>::Zero();
    if constexpr (sizeof...(Rest) > 0) {
      const auto* given = std::get<0>(std::make_tuple(rest...));
      if (given != nullptr) f = *given;
    }
    Eigen::Matrix<Scalar, 2, 1> f_own = f;
    mech::two_pendulums_friction::Model::Kinetostatics<Scalar>(p, q, phi, qd, qdd, t, c, out, &f_own);
    out->Q(1) += f(0);  // O1's load acts on the second input too
    out->drive(1) = -out->Q(1);
    out->K_rel(0, 1) = Scalar(1);
  }
};

TEST(Coulomb, SeveralInputsRefuseTheStickOfACombinedJoint) {
  using M2 = TwoPendulumsCoupledJoint;
  mech::two_pendulums_friction::Params<double> p;
  p.mu2 = 0;
  dyn::MinimalOptions o;
  o.sample_dt = 0.01;
  dyn::MinimalDynamics<M2> sim(p, o);
  Eigen::Vector2d q(0.0, -1.0), qd(2.0, 0.0);  // w1 + w2 = 2 at first
  ASSERT_TRUE(sim.Initialize(q));
  dyn::MinimalSummary s;
  bool finite = true;
  int samples = 0;
  sim.Simulate(
      0.0, q, qd, 5.0,
      [&](const dyn::Sample<M2>& x) {
        ++samples;
        finite = finite && x.q.allFinite() && x.qd.allFinite() && x.friction.allFinite();
        return true;
      },
      &s);
  EXPECT_EQ(s.status, dyn::Status::kFrictionFailed) << dyn::FormatSummary(s);
  EXPECT_EQ(std::string(s.friction_joint), "O1");
  EXPECT_NE(dyn::FormatSummary(s).find("(joint 'O1')"), std::string::npos) << dyn::FormatSummary(s);
  EXPECT_NE(std::string(s.message).find("not one input's alone"), std::string::npos) << s.message;
  std::printf("combined joint: %s\n", dyn::FormatSummary(s).c_str());
  EXPECT_GT(s.t_end, 0.0);
  EXPECT_LT(s.t_end, 5.0);
  EXPECT_GT(samples, 2);
  EXPECT_TRUE(finite);
}

// Several inputs with every coefficient 0: the run is the frictionless one to the last bit.
TEST(Coulomb, SeveralInputsZeroMuIsTheFrictionlessRun) {
  using M2 = mech::two_pendulums_friction::Model;
  Eigen::Vector2d q(0.0, -0.5), qd(0.0, 1.0);
  std::vector<dyn::Sample<M2>> runs[2];
  for (int off = 0; off < 2; ++off) {
    dyn::MinimalOptions o;
    o.sample_dt = 0.05;
    o.coulomb.enabled = off == 0;
    mech::two_pendulums_friction::Params<double> p;
    p.mu = 0;
    p.mu2 = 0;
    dyn::MinimalDynamics<M2> sim(p, o);
    ASSERT_TRUE(sim.Initialize(q));
    dyn::MinimalSummary s;
    sim.Simulate(
        0.0, q, qd, 2.0,
        [&](const dyn::Sample<M2>& x) {
          runs[off].push_back(x);
          return true;
        },
        &s);
    EXPECT_EQ(s.status, dyn::Status::kSuccess);
    EXPECT_FALSE(s.coulomb);
  }
  ASSERT_EQ(runs[0].size(), runs[1].size());
  for (size_t i = 0; i < runs[0].size(); ++i) {
    EXPECT_EQ(runs[0][i].q, runs[1][i].q) << i;
    EXPECT_EQ(runs[0][i].qd, runs[1][i].qd) << i;
  }
}

// Several inputs through the model view (issue 43): the runtime compiled once
// (MinimalDynamics<ViewModel>, mechgen_runtime_view) on the two pendulums' view against the
// fixed-size instantiation above (the oracle: SeveralInputsAreTwoSinglePendulums holds it to
// two single runs, themselves to the free body and the energy balance). The same generated
// functions and the same arithmetic (the reduced inertia's LDLT on fixed-size copies of the
// inputs' count; sums of two products): every sample (q, qd, qdd, Q, the friction loads, each
// joint's stuck flag, the energies), the summary's counts and figures, and the last sample,
// to the bit. Runs: pendulum 1 sticking while 2 swings (the first test's), both launched and
// coming to rest one after the other, and a start with one joint at relative rest and the
// other moving, with both integrators.
bool SameDouble(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
template <class A, class B>
bool SameEntries(const A& a, const B& b) {
  if (a.size() != b.size()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i)
    if (!SameDouble(a(i), b(i))) return false;
  return true;
}

template <template <int> class Method>
void ExpectTwoPendulumsViewSame(double r, double r2, const Eigen::Vector2d& q0, const Eigen::Vector2d& qd0,
                                double t_end, double dt) {
  using M2 = mech::two_pendulums_friction::Model;
  using mechgen::ModelCalls;
  using mechgen::ViewModel;
  using Fixed = dyn::MinimalDynamics<M2, Method>;
  using View = dyn::MinimalDynamics<ViewModel, Method>;
  SCOPED_TRACE("r = " + std::to_string(r) + ", r2 = " + std::to_string(r2) + ", q0 = (" + std::to_string(q0(0)) +
               ", " + std::to_string(q0(1)) + "), qd0 = (" + std::to_string(qd0(0)) + ", " +
               std::to_string(qd0(1)) + ")");
  const ViewModel model(mech::two_pendulums_friction::View());
  ASSERT_TRUE(mechgen::ViewCompatible(*model.view));
  mech::two_pendulums_friction::Params<double> p;
  p.r = r;
  p.r2 = r2;
  typename View::Params pv = ModelCalls<ViewModel>::DefaultParams(model);
  *ModelCalls<ViewModel>::FindParameter(model, &pv, "r") = r;
  *ModelCalls<ViewModel>::FindParameter(model, &pv, "r2") = r2;
  ModelCalls<ViewModel>::ParametersSet(model, &pv);
  dyn::MinimalOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-13;
  o.sample_dt = dt;
  Fixed fixed(p, o);
  View view(model, pv, o);
  const typename View::VecQ q0_view = q0, qd0_view = qd0;
  ASSERT_TRUE(fixed.Initialize(q0));
  ASSERT_TRUE(view.Initialize(q0_view));
  EXPECT_TRUE(view.SimulatesCoulomb(q0_view));
  std::vector<dyn::Sample<M2>> a;
  std::vector<dyn::Sample<ViewModel>> b;
  dyn::MinimalSummary sa, sb;
  dyn::Sample<M2> last_a;
  dyn::Sample<ViewModel> last_b;
  fixed.Simulate(
      0.0, q0, qd0, t_end,
      [&](const dyn::Sample<M2>& x) {
        a.push_back(x);
        return true;
      },
      &sa, &last_a);
  dyn::ViewSampleFn<View> observer = [&](const dyn::Sample<ViewModel>& x) {
    b.push_back(x);
    return true;
  };
  dyn::SimulateFree(&view, 0.0, q0_view, qd0_view, t_end, observer, &sb, &last_b);
  ASSERT_EQ(sa.status, dyn::Status::kSuccess) << dyn::FormatSummary(sa);
  EXPECT_TRUE(sa.coulomb);
  EXPECT_GE(sa.stick_intervals, 1) << dyn::FormatSummary(sa);  // (a run with stick and slip)
  EXPECT_EQ(dyn::FormatSummary(sa), dyn::FormatSummary(sb));  // every count and figure, as printed
  EXPECT_EQ(sa.coulomb, sb.coulomb);
  EXPECT_EQ(sa.friction_transitions, sb.friction_transitions);
  EXPECT_EQ(sa.stick_intervals, sb.stick_intervals);
  EXPECT_TRUE(SameDouble(sa.time_stuck, sb.time_stuck));
  EXPECT_EQ(sa.integrator.steps, sb.integrator.steps);
  EXPECT_EQ(sa.integrator.rhs_evaluations, sb.integrator.rhs_evaluations);
  ASSERT_EQ(a.size(), b.size());
  auto same = [](const auto& x, const auto& y) {
    return SameDouble(x.t, y.t) && SameEntries(x.q, y.q) && SameEntries(x.qd, y.qd) && SameEntries(x.qdd, y.qdd) &&
           SameEntries(x.Q, y.Q) && SameEntries(x.phi, y.phi) && SameEntries(x.friction, y.friction) &&
           SameDouble(x.T, y.T) && SameDouble(x.V, y.V) && SameDouble(x.W, y.W) && SameDouble(x.P_nc, y.P_nc) &&
           x.stuck == y.stuck && x.joint_stuck[0] == y.joint_stuck[0] && x.joint_stuck[1] == y.joint_stuck[1];
  };
  int mixed = 0;  // samples with one joint stuck and the other not
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_TRUE(same(a[i], b[i])) << "sample " << i << " at t = " << a[i].t << " (view t = " << b[i].t
                                  << "): q " << a[i].q.transpose() << " vs " << b[i].q.transpose() << ", friction "
                                  << a[i].friction.transpose() << " vs " << b[i].friction.transpose();
    if (a[i].joint_stuck[0] != a[i].joint_stuck[1]) ++mixed;
  }
  EXPECT_GT(mixed, 0);
  EXPECT_TRUE(same(last_a, last_b));
}

TEST(Coulomb, SeveralInputsThroughTheModelViewBitForBit) {
  // Pendulum 1 comes to rest while 2 swings on (SeveralInputsAreTwoSinglePendulums' run).
  ExpectTwoPendulumsViewSame<dyn::Dopri5>(0.2, 0.01, Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.0, 0.0), 6, 0.01);
  // Both launched: 2 stops first (the larger circle), then 1; joint 1 at relative rest at t0.
  ExpectTwoPendulumsViewSame<dyn::Dop853>(0.1, 0.3, Eigen::Vector2d(-0.4, 0.3), Eigen::Vector2d(0.0, 2.0), 5, 0.02);
  ExpectTwoPendulumsViewSame<dyn::Dopri5>(0.3, 0.15, Eigen::Vector2d(-0.4, 0.3), Eigen::Vector2d(3.0, -1.5), 5, 0);
}

// ---- driven runs (prescribed.h): the actuator force includes the joints' Coulomb friction ----
template <class M, class Law>
std::vector<dyn::PrescribedSample<M, 1>> Driven(const typename M::template ParamsT<double>& p, const Law& law,
                                                double t_end, double dt, dyn::PrescribedSummary* summary) {
  using Drive = dyn::Drive<Law>;
  dyn::PrescribedOptions o;
  o.integrator.rtol = 1e-11;
  o.integrator.atol = 1e-13;
  o.sample_dt = dt;
  dyn::PrescribedDynamics<M, 1, Drive> sim(p, {0}, Drive(law), dyn::NoForce(), o);
  std::vector<dyn::PrescribedSample<M, 1>> samples;
  EXPECT_TRUE(sim.Initialize(0.0, Eigen::Matrix<double, 0, 1>()));
  sim.Simulate(
      0.0, Eigen::Matrix<double, 0, 1>(), Eigen::Matrix<double, 0, 1>(), t_end,
      [&](const dyn::PrescribedSample<M, 1>& s) {
        samples.push_back(s);
        return true;
      },
      summary);
  return samples;
}

// The pendulum driven at a constant speed, then by a rest-to-rest move: the motor torque from
// the free body of the arm, lambda = I_O alpha + m g lc cos theta + sign(w) mu r |F_O| with
// F_O = m (a_G - g) (zero friction at rest: the documented choice, the motor holds the whole
// load), and the energy balance integral lambda w dt = dT + dV + integral |f| |w| dt
// (trapezoids over the samples, not the runtime's works).
TEST(Coulomb, DrivenPendulumMotorTorqueIncludesPinFriction) {
  mech::pendulum_friction::Params<double> p;
  p.r = 0.1;
  const double I_O = p.J + p.m * p.lc * p.lc;
  auto check = [&](const auto& samples, const char* what) {
    int checked = 0;
    double work = 0, dissipated = 0;
    for (size_t i = 0; i < samples.size(); ++i) {
      const auto& s = samples[i];
      const double th = s.q(0), w = s.qd(0), al = s.qdd(0);
      const double ax = p.lc * (-al * std::sin(th) - w * w * std::cos(th));
      const double ay = p.lc * (al * std::cos(th) - w * w * std::sin(th));
      const double F = p.m * std::hypot(ax, ay + p.g);
      const double sgn = w > 0 ? 1.0 : (w < 0 ? -1.0 : 0.0);
      const double lambda = I_O * al + p.m * p.g * p.lc * std::cos(th) + sgn * p.mu * p.r * F;
      EXPECT_NEAR(s.lambda(0), lambda, 1e-11 * (1 + std::abs(lambda))) << what << " t = " << s.t;
      EXPECT_NEAR(s.friction(0), -sgn * p.mu * p.r * F, 1e-12 * (1 + F)) << what << " t = " << s.t;
      ++checked;
      if (i > 0) {
        const auto& a = samples[i - 1];
        work += 0.5 * (a.lambda(0) * a.qd(0) + s.lambda(0) * s.qd(0)) * (s.t - a.t);
        dissipated += 0.5 * (std::abs(a.friction(0) * a.qd(0)) + std::abs(s.friction(0) * s.qd(0))) * (s.t - a.t);
      }
    }
    const double dE = samples.back().E - samples.front().E;
    std::printf("driven pendulum (%s): work %.12g J = dE %.12g J + friction %.12g J (residual %.3g)\n", what, work,
                dE, dissipated, work - dE - dissipated);
    EXPECT_GT(dissipated, 0.1);
    EXPECT_NEAR(work, dE + dissipated, 1e-5 * dissipated);
    // The runtime's balance: E - W_nc - W_act constant (W_nc holds the friction's work).
    EXPECT_NEAR(samples.back().W_nc, -dissipated, 1e-5 * dissipated);
    // (to the integration's tolerance, rtol 1e-11 per step: 1e-9 of the energies moved)
    EXPECT_NEAR(samples.back().Balance(), samples.front().Balance(), 1e-9 * (std::abs(work) + dissipated));
    EXPECT_GT(checked, 100);
  };
  dyn::PrescribedSummary summary;
  const auto spun = Driven<Pendulum>(p, dyn::ConstantSpeedLaw{-1.0, 3.0, 0.0}, 4.0, 1e-3, &summary);
  ASSERT_EQ(summary.status, dyn::Status::kSuccess) << dyn::FormatSummary(summary);
  EXPECT_TRUE(summary.coulomb);
  check(spun, "3 rad/s");
  dyn::RestToRestLaw move{-kPi / 2, kPi / 3, 0.2, 1.2, dyn::RestToRestLaw::Profile::kPoly345};
  const auto moved = Driven<Pendulum>(p, move, 1.5, 1e-3, &summary);
  ASSERT_EQ(summary.status, dyn::Status::kSuccess) << dyn::FormatSummary(summary);
  check(moved, "rest to rest");
  // At rest after the move: no friction, the motor holds the weight's moment exactly.
  const auto& end = moved.back();
  EXPECT_EQ(end.qd(0), 0.0);
  EXPECT_EQ(end.friction(0), 0.0);
  EXPECT_NEAR(end.lambda(0), p.m * p.g * p.lc * std::cos(kPi / 3), 1e-12);
}

// The block on the incline pushed up and down the slope at constant speeds by its actuator:
// lambda = m g sin alpha + sign(v) mu m g cos alpha (the slide's normal force is the weight's
// component, the friction opposes the motion).
TEST(Coulomb, DrivenBlockActuatorForce) {
  mech::incline_friction::Params<double> p;
  for (double v : {1.5, -0.5}) {
    dyn::PrescribedSummary summary;
    const auto samples = Driven<Incline>(p, dyn::ConstantSpeedLaw{0.0, v, 0.0}, 1.0, 0.01, &summary);
    ASSERT_EQ(summary.status, dyn::Status::kSuccess) << dyn::FormatSummary(summary);
    const double lambda = p.m * p.g * (std::sin(p.alpha) + (v > 0 ? 1 : -1) * p.mu * std::cos(p.alpha));
    for (const auto& s : samples) EXPECT_NEAR(s.lambda(0), lambda, 1e-12) << v << " t = " << s.t;
  }
}

// A closed loop: the slider-crank with friction at O, B, C (mu r on the pin forces) and the
// slide (mu_s |N|), gravity and a gas force P on the slider, its crank driven at a constant
// speed w (both ways). The oracle: the Newton-Euler balance of the crank, the rod and the
// slider by hand (slider-crank kinematics in closed form; unknowns F_O, F_B, F_C, N, the
// slide's moment and the motor torque: a 9 x 9 solve, iterated on the friction loads, which
// depend on the pin forces), and the energy balance: motor work = dE + the friction's work
// sum |f_J| |w_rel,J| (trapezoids over the samples).
TEST(Coulomb, DrivenSliderCrankAgainstFreeBodies) {
  using SC = mech::slider_crank_coulomb::Model;
  mech::slider_crank_coulomb::Params<double> p;
  p.P = 200;
  for (double w : {12.0, -7.0}) {
    dyn::PrescribedSummary summary;
    const double th0 = 30 * kPi / 180;
    const auto samples = Driven<SC>(p, dyn::ConstantSpeedLaw{th0, w, 0.0}, 2 * kPi / std::abs(w), 1e-3, &summary);
    ASSERT_EQ(summary.status, dyn::Status::kSuccess) << dyn::FormatSummary(summary);
    EXPECT_TRUE(summary.coulomb);
    double work = 0, dissipated = 0, prev_power = 0, prev_loss = 0, worst = 0;
    for (size_t i = 0; i < samples.size(); ++i) {
      const auto& s = samples[i];
      // Kinematics by hand: a sin th + b sin be = e; x = a cos th + b cos be.
      const double th = s.q(0), c = std::cos(th), sn = std::sin(th);
      const double be = std::asin((p.e - p.a * sn) / p.b), cb = std::cos(be), sb = std::sin(be);
      const double bd = -p.a * c * w / (p.b * cb);
      const double bdd = (p.a * sn * w * w + p.b * sb * bd * bd) / (p.b * cb);
      const double xd = -p.a * sn * w - p.b * sb * bd;
      const double xdd = -p.a * c * w * w - p.b * cb * bd * bd - p.b * sb * bdd;
      const Eigen::Vector2d rO(0, 0), rB(p.a * c, p.a * sn), rC(p.a * c + p.b * cb, p.e);
      const Eigen::Vector2d G1 = 0.5 * rB, G2 = 0.5 * (rB + rC);
      const Eigen::Vector2d aG1 = -0.5 * p.a * w * w * Eigen::Vector2d(c, sn);
      const Eigen::Vector2d aG2 = -p.a * w * w * Eigen::Vector2d(c, sn) +
                                  0.5 * p.b * (bdd * Eigen::Vector2d(-sb, cb) - bd * bd * Eigen::Vector2d(cb, sb));
      auto cross = [](const Eigen::Vector2d& r, int col_x, Eigen::Matrix<double, 9, 9>* A, int row, double sign) {
        (*A)(row, col_x) += -sign * r.y();
        (*A)(row, col_x + 1) += sign * r.x();
      };
      // Relative angular velocities (second link minus first): O crank, B rod - crank, C -rod.
      const double wO = w, wB = bd - w, wC = -bd;
      auto sgn = [](double v) { return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0); };
      double fO = 0, fB = 0, fC = 0, fs = 0;
      Eigen::Matrix<double, 9, 1> x = Eigen::Matrix<double, 9, 1>::Zero();
      for (int it = 0; it < 60; ++it) {
        // x = [F_Ox, F_Oy, F_Bx, F_By, F_Cx, F_Cy, N, M_s, lambda]
        Eigen::Matrix<double, 9, 9> A = Eigen::Matrix<double, 9, 9>::Zero();
        Eigen::Matrix<double, 9, 1> rhs;
        A(0, 0) = 1, A(0, 2) = -1, rhs(0) = p.m1 * aG1.x();
        A(1, 1) = 1, A(1, 3) = -1, rhs(1) = p.m1 * aG1.y() + p.m1 * p.g;
        cross(rO - G1, 0, &A, 2, 1), cross(rB - G1, 2, &A, 2, -1), A(2, 8) = 1, rhs(2) = -fO + fB;
        A(3, 2) = 1, A(3, 4) = -1, rhs(3) = p.m2 * aG2.x();
        A(4, 3) = 1, A(4, 5) = -1, rhs(4) = p.m2 * aG2.y() + p.m2 * p.g;
        cross(rB - G2, 2, &A, 5, 1), cross(rC - G2, 4, &A, 5, -1), rhs(5) = p.J2 * bdd - fB + fC;
        A(6, 4) = 1, rhs(6) = p.m3 * xdd - fs + p.P;
        A(7, 5) = 1, A(7, 6) = 1, rhs(7) = p.m3 * p.g;
        A(8, 7) = 1, rhs(8) = -fC;
        x = A.fullPivLu().solve(rhs);
        fO = -p.mu * p.r * std::hypot(x(0), x(1)) * sgn(wO);
        fB = -p.mu * p.r * std::hypot(x(2), x(3)) * sgn(wB);
        fC = -p.mu * p.r * std::hypot(x(4), x(5)) * sgn(wC);
        fs = -p.mu_s * std::abs(x(6)) * sgn(xd);
      }
      const double lambda = x(8);
      EXPECT_NEAR(s.lambda(0), lambda, 1e-9 * (1 + std::abs(lambda))) << "w " << w << " t = " << s.t;
      EXPECT_NEAR(s.friction(0), fO, 1e-10) << s.t;
      EXPECT_NEAR(s.friction(1), fB, 1e-10) << s.t;
      EXPECT_NEAR(s.friction(2), fC, 1e-10) << s.t;
      EXPECT_NEAR(s.friction(3), fs, 1e-9) << s.t;
      worst = std::max(worst, std::abs(s.lambda(0) - lambda));
      const double power = s.lambda(0) * w - p.P * -xd;  // the motor's and the gas force's (P along -x)
      const double loss = std::abs(fO * wO) + std::abs(fB * wB) + std::abs(fC * wC) + std::abs(fs * xd);
      if (i > 0) {
        const double dt = s.t - samples[i - 1].t;
        work += 0.5 * (power + prev_power) * dt;
        dissipated += 0.5 * (loss + prev_loss) * dt;
      }
      prev_power = power;
      prev_loss = loss;
    }
    const double dE = samples.back().E - samples.front().E;
    std::printf("driven slider-crank, w = %g rad/s: max |lambda - free bodies| = %.3g N m; a turn: work %.9g J = "
                "dE %.3g J + friction %.9g J (residual %.3g J)\n",
                w, worst, work, dE, dissipated, work - dE - dissipated);
    EXPECT_GT(dissipated, 1.0);
    // The trapezoids' error over 1 ms steps (the friction loads jump where a relative velocity
    // changes sign: one step's worth of error each) is ~1e-5 of the work.
    EXPECT_NEAR(work, dE + dissipated, 1e-4 * dissipated);
    EXPECT_NEAR(samples.back().Balance(), samples.front().Balance(), 1e-9 * (std::abs(work) + dissipated));
  }
}

// The engine's gas load with friction: the gas pressure written in the model over the 720 deg
// cycle (a table at mod(theta_crank, 4 pi), as tests/engine's engine_gas_expression), so that
// the reactions, and the friction on them, carry it (engine::GasLoad, a caller's load, cannot
// be simulated with friction). Free motion from rest just after firing TDC against a load
// torque; the oracle is the energy balance with the test's own pressure interpolation and
// slider-crank kinematics: dE = integral (M w - (P + A p(a)) x_dot - sum |f_J| |w_rel,J|) dt.
TEST(Coulomb, GasLoadWithFrictionEnergyBalance) {
  using SC = mech::slider_crank_coulomb::Model;
  mech::slider_crank_coulomb::Params<double> p;
  p.A = 4e-4;  // 1400 N at firing TDC, 2000 N at its peak
  p.M = -1.0;
  p.J1 = 0.1;  // a flywheel, to carry the crank through the other three strokes
  const double kDeg = kPi / 180;
  const std::vector<double> xa = {0, 15, 40, 90, 180, 190, 360, 540, 560, 630, 690, 720};
  const std::vector<double> ya = {3.5e6, 5.0e6, 3.0e6, 1.2e6, 3.0e5, 5.0e4, 1.0e4, -2.0e4, 0, 1.5e5, 8.0e5, 3.5e6};
  auto pressure = [&](double th) {
    double a = std::fmod(th, 4 * kPi);
    if (a < 0) a += 4 * kPi;
    for (size_t i = 0; i + 1 < xa.size(); ++i)
      if (a <= xa[i + 1] * kDeg) return ya[i] + (ya[i + 1] - ya[i]) * (a - xa[i] * kDeg) / ((xa[i + 1] - xa[i]) * kDeg);
    return ya.back();
  };
  const double dt = 1e-4;
  const auto r = Simulate<SC>(p, 10 * kDeg, 0.0, 1.0, dt);
  ASSERT_EQ(r.summary.status, dyn::Status::kSuccess) << dyn::FormatSummary(r.summary);
  EXPECT_TRUE(r.summary.coulomb);
  double work = 0, dissipated = 0, prev_power = 0, prev_loss = 0;
  for (size_t i = 0; i < r.samples.size(); ++i) {
    const auto& s = r.samples[i];
    const double th = s.q(0), w = s.qd(0), c = std::cos(th), sn = std::sin(th);
    const double be = std::asin((p.e - p.a * sn) / p.b);
    const double bd = -p.a * c * w / (p.b * std::cos(be));
    const double xd = -p.a * sn * w - p.b * std::sin(be) * bd;
    const double power = p.M * w - (p.P + p.A * pressure(th)) * xd;
    const double loss = std::abs(s.friction(0) * w) + std::abs(s.friction(1) * (bd - w)) +
                        std::abs(s.friction(2) * bd) + std::abs(s.friction(3) * xd);
    if (i > 0) {
      const double h = s.t - r.samples[i - 1].t;
      work += 0.5 * (power + prev_power) * h;
      dissipated += 0.5 * (loss + prev_loss) * h;
    }
    prev_power = power;
    prev_loss = loss;
  }
  const double dE = r.samples.back().E - r.samples.front().E;
  std::printf("gas load with friction: crank at %.6g rad after 1 s; dE %.9g J = work %.9g J - friction %.9g J "
              "(residual %.3g J); %s\n",
              r.samples.back().q(0), dE, work, dissipated, dE - work + dissipated, dyn::FormatSummary(r.summary).c_str());
  EXPECT_GT(dissipated, 0.5);
  EXPECT_GT(r.samples.back().q(0), 4 * kPi);  // it ran a cycle at least
  EXPECT_NEAR(dE, work - dissipated, 1e-4 * (std::abs(work) + dissipated));
  // The runtime's W (the integral of P_nc: the torque's, the gas force's and the friction's).
  EXPECT_NEAR(r.samples.back().W, work - dissipated, 1e-4 * (std::abs(work) + dissipated));
}

// Every coefficient 0: the driven run is the frictionless pendulum's to the last bit; and a
// driven run with free inputs leaves the friction out and says so.
TEST(Coulomb, DrivenZeroMuAndFreeInputs) {
  mech::pendulum_friction::Params<double> pf;
  pf.mu = 0;
  mech::pendulum::Params<double> p0;
  dyn::PrescribedSummary sf, s0;
  const dyn::ConstantSpeedLaw law{0.3, 2.0, 0.0};
  const auto rf = Driven<Pendulum>(pf, law, 2.0, 0.01, &sf);
  const auto r0 = Driven<mech::pendulum::Model>(p0, law, 2.0, 0.01, &s0);
  EXPECT_FALSE(sf.coulomb);
  ASSERT_EQ(rf.size(), r0.size());
  for (size_t i = 0; i < rf.size(); ++i) {
    EXPECT_EQ(rf[i].t, r0[i].t);
    EXPECT_EQ(rf[i].lambda(0), r0[i].lambda(0)) << i;
    EXPECT_EQ(rf[i].W_act, r0[i].W_act) << i;
  }
  using M2 = mech::two_pendulums_friction::Model;
  using Drive = dyn::Drive<dyn::ConstantSpeedLaw>;
  static_assert(!dyn::PrescribedDynamics<M2, 1, Drive>::kHasDrivenFriction, "a free input");
  dyn::PrescribedDynamics<M2, 1, Drive> sim(mech::two_pendulums_friction::Params<double>(), {0}, Drive(law));
  Eigen::Matrix<double, 1, 1> qf(-0.5), qdf(0.0);
  ASSERT_TRUE(sim.Initialize(0.0, qf));
  dyn::PrescribedSummary s;
  sim.Simulate(0.0, qf, qdf, 0.5, [](const auto&) { return true; }, &s);
  EXPECT_EQ(s.status, dyn::Status::kSuccess);
  EXPECT_FALSE(s.coulomb);
  EXPECT_EQ(std::string(s.message), "Coulomb friction is not simulated in a driven run with free inputs");
}

// Coulomb friction switched off: the friction joints' coefficient is ignored (viscous and
// frictionless dynamics only), the pendulum swings without loss.
TEST(Coulomb, SwitchedOff) {
  mech::pendulum_friction::Params<double> p;
  dyn::MinimalOptions o;
  o.coulomb.enabled = false;
  o.sample_dt = 0.01;
  dyn::MinimalDynamics<Pendulum> sim(p, o);
  Eigen::Matrix<double, 1, 1> q, qd;
  q(0) = 0;
  qd(0) = 0;
  ASSERT_TRUE(sim.Initialize(q));
  dyn::MinimalSummary s;
  dyn::Sample<Pendulum> last;
  sim.Simulate(
      0.0, q, qd, 3.0, [](const dyn::Sample<Pendulum>&) { return true; }, &s, &last);
  EXPECT_FALSE(s.coulomb);
  EXPECT_NEAR(last.E, -0.0, 1e-6);  // E0 = 0 at the horizontal, from rest
  EXPECT_EQ(last.friction(0), 0.0);
}

}  // namespace
