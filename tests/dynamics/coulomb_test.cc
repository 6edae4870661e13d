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
//  - two inputs (two_pendulums_friction.yaml): not simulated, said so, the run bit for bit the
//    one with Coulomb friction switched off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "incline_friction.h"
#include "mechgen/dynamics/forward.h"
#include "pendulum.h"
#include "pendulum_friction.h"
#include "two_pendulums_friction.h"

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

// Several inputs: Coulomb friction is not simulated (the summary says so) and the run is the one
// with it switched off, to the last bit.
TEST(Coulomb, SeveralInputsAreNotSimulated) {
  using M2 = mech::two_pendulums_friction::Model;
  static_assert(!dyn::MinimalDynamics<M2>::kHasCoulomb, "two inputs: no stick and slip");
  Eigen::Vector2d q(0.0, -0.5), qd(0.0, 1.0);
  std::vector<dyn::Sample<M2>> runs[2];
  for (int off = 0; off < 2; ++off) {
    dyn::MinimalOptions o;
    o.sample_dt = 0.05;
    o.coulomb.enabled = off == 0;
    dyn::MinimalDynamics<M2> sim(mech::two_pendulums_friction::Params<double>(), o);
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
    EXPECT_EQ(std::string(s.message), off == 0 ? "Coulomb friction is not simulated with several inputs" : "");
  }
  ASSERT_EQ(runs[0].size(), runs[1].size());
  for (size_t i = 0; i < runs[0].size(); ++i) {
    EXPECT_EQ(runs[0][i].q, runs[1][i].q) << i;
    EXPECT_EQ(runs[0][i].qd, runs[1][i].qd) << i;
  }
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
