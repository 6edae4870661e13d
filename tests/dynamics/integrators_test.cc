// The integrators on problems with closed-form solutions: y' = -y and the harmonic
// oscillator. Orders are measured, not assumed: with fixed steps (h_initial, rtol huge so that
// every step is accepted... no: with h_max forcing the step) the global error must fall like
// h^5 (Dopri5) and h^8 (Dop853); the dense output like h^5 / h^8 too (local order 5 / 8 of
// the continuous extensions = global order 4+1 and 7+1 at interior points); the adaptive
// control must meet a tolerance; failures of f must end in a status.
#include <array>
#include <cmath>

#include <gtest/gtest.h>

#include "mechgen/dynamics/integrators.h"
#include "mechgen/dynamics/simulator.h"

namespace {

using mechgen::dynamics::Dop853;
using mechgen::dynamics::Dopri5;
using mechgen::dynamics::IntegratorOptions;
using mechgen::dynamics::IntegratorStatus;
using mechgen::dynamics::IntegratorSummary;

using State1 = Eigen::Matrix<double, 1, 1>;
using State2 = Eigen::Matrix<double, 2, 1>;

// y'' = -w^2 y as (y, y'): y = cos(w t).
constexpr double kW = 2.0;
auto oscillator = [](double /*t*/, const State2& y, State2* dy) {
  (*dy) << y(1), -kW * kW * y(0);
  return true;
};

// Fixed steps h: every step accepted (tolerances loose), h_max = h_initial = h.
IntegratorOptions Fixed(double h) {
  IntegratorOptions o;
  o.rtol = 1e3;
  o.atol = 1e3;
  o.h_initial = h;
  o.h_max = h;
  return o;
}

template <class Integrator>
double GlobalError(double h, double* dense_error) {
  Integrator integrator(Fixed(h));
  auto f = oscillator;
  State2 y0(1, 0);
  double dense_max = 0;
  IntegratorSummary summary;
  State2 y_end;
  const bool ok = mechgen::dynamics::Integrate(
      &integrator, f, 0.0, y0, 2.0,
      [&](Integrator& in) {
        // Dense value inside the step, at a third of it.
        const double t = in.t_prev() + (in.t() - in.t_prev()) / 3;
        State2 y;
        EXPECT_TRUE(in.Dense(f, t, &y));
        dense_max = std::max(dense_max, std::abs(y(0) - std::cos(kW * t)));
        return true;
      },
      &y_end, &summary);
  EXPECT_TRUE(ok);
  EXPECT_EQ(summary.rejected, 0);
  *dense_error = dense_max;
  return std::abs(y_end(0) - std::cos(kW * 2.0)) + std::abs(y_end(1) + kW * std::sin(kW * 2.0));
}

template <class Integrator>
void CheckOrder(double h, double expected_order, double expected_dense_order) {
  double d1, d2;
  const double e1 = GlobalError<Integrator>(h, &d1);
  const double e2 = GlobalError<Integrator>(h / 2, &d2);
  const double order = std::log2(e1 / e2);
  const double dense_order = std::log2(d1 / d2);
  EXPECT_NEAR(order, expected_order, 0.3) << "errors " << e1 << " " << e2;
  EXPECT_GT(dense_order, expected_dense_order - 0.3) << "dense errors " << d1 << " " << d2;
}

TEST(Integrators, Dopri5IsOfOrderFiveWithDenseOutputOfOrderFour) {
  // Dense output: local error O(h^5) of the order-4 continuous extension.
  CheckOrder<Dopri5<2>>(0.1, 5.0, 5.0 - 0.2);
}

TEST(Integrators, Dop853IsOfOrderEightWithDenseOutputOfOrderSeven) {
  // Large steps so that the errors stay far above round-off.
  CheckOrder<Dop853<2>>(0.25, 8.0, 8.0 - 0.2);
}

template <class Integrator>
void CheckExponentialDecay(double rtol) {
  IntegratorOptions o;
  o.rtol = rtol;
  o.atol = 1e-14;
  Integrator integrator(o);
  auto f = [](double, const State1& y, State1* dy) {
    *dy = -y;
    return true;
  };
  State1 y0(1.0), y1;
  IntegratorSummary s;
  ASSERT_TRUE(mechgen::dynamics::Integrate(&integrator, f, 0.0, y0, 5.0, &y1, &s))
      << mechgen::dynamics::FormatSummary(s);
  EXPECT_EQ(s.status, IntegratorStatus::kSuccess);
  EXPECT_NEAR(s.t, 5.0, 0.0);
  // Global error within a modest multiple of the tolerance (y <= 1, 5 time constants).
  EXPECT_LT(std::abs(y1(0) - std::exp(-5.0)), 50 * rtol);
  EXPECT_GT(s.steps, 0);
  EXPECT_GE(s.rhs_evaluations, s.steps);
}

TEST(Integrators, AdaptiveStepsMeetTheTolerance) {
  for (double rtol : {1e-4, 1e-7, 1e-10}) {
    CheckExponentialDecay<Dopri5<1>>(rtol);
    CheckExponentialDecay<Dop853<1>>(rtol);
  }
}

TEST(Integrators, Dop853NeedsFewerEvaluationsAtTightTolerance) {
  IntegratorOptions o;
  o.rtol = 1e-11;
  o.atol = 1e-13;
  auto f = oscillator;
  State2 y0(1, 0), y1;
  IntegratorSummary s5, s8;
  Dopri5<2> a(o);
  Dop853<2> b(o);
  ASSERT_TRUE(mechgen::dynamics::Integrate(&a, f, 0.0, y0, 10.0, &y1, &s5));
  EXPECT_NEAR(y1(0), std::cos(kW * 10), 1e-8);
  ASSERT_TRUE(mechgen::dynamics::Integrate(&b, f, 0.0, y0, 10.0, &y1, &s8));
  EXPECT_NEAR(y1(0), std::cos(kW * 10), 1e-8);
  EXPECT_LT(s8.rhs_evaluations, s5.rhs_evaluations);
}

TEST(Integrators, BackwardIntegrationReturnsToTheStart) {
  IntegratorOptions o;
  o.rtol = 1e-12;
  o.atol = 1e-14;
  auto f = oscillator;
  State2 y0(1, 0), y1, y2;
  IntegratorSummary s;
  Dop853<2> in(o);
  ASSERT_TRUE(mechgen::dynamics::Integrate(&in, f, 0.0, y0, 3.0, &y1, &s));
  ASSERT_TRUE(mechgen::dynamics::Integrate(&in, f, 3.0, y1, 0.0, &y2, &s));
  EXPECT_NEAR(y2(0), 1.0, 1e-9);
  EXPECT_NEAR(y2(1), 0.0, 1e-9);
}

TEST(Integrators, FailingRightHandSideIsAStatus) {
  // f fails beyond t = 1: the integrator shrinks the step down to h_min and reports.
  auto f = [](double t, const State1& y, State1* dy) {
    *dy = -y;
    return t < 1.0;
  };
  IntegratorOptions o;
  o.h_min = 1e-9;
  Dopri5<1> in(o);
  State1 y0(1.0), y1;
  IntegratorSummary s;
  EXPECT_FALSE(mechgen::dynamics::Integrate(&in, f, 0.0, y0, 2.0, &y1, &s));
  EXPECT_EQ(s.status, IntegratorStatus::kRhsFailed);
  EXPECT_LT(s.t, 1.0);
  EXPECT_GT(s.t, 1.0 - 1e-6);
  EXPECT_TRUE(std::isfinite(y1(0)));
}

TEST(Integrators, InvalidOptionsAreReported) {
  IntegratorOptions o;
  o.rtol = -1;
  std::string error;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("rtol"), std::string::npos);
  Dopri5<1> in(o);
  auto f = [](double, const State1& y, State1* dy) {
    *dy = -y;
    return true;
  };
  State1 y0(1.0), y1;
  IntegratorSummary s;
  EXPECT_FALSE(mechgen::dynamics::Integrate(&in, f, 0.0, y0, 1.0, &y1, &s));
  EXPECT_EQ(s.status, IntegratorStatus::kInvalidOptions);
}

TEST(Integrators, MaxStepsIsAStatus) {
  IntegratorOptions o;
  o.max_steps = 5;
  o.rtol = 1e-12;
  Dop853<2> in(o);
  auto f = oscillator;
  State2 y0(1, 0), y1;
  IntegratorSummary s;
  EXPECT_FALSE(mechgen::dynamics::Integrate(&in, f, 0.0, y0, 100.0, &y1, &s));
  EXPECT_EQ(s.status, IntegratorStatus::kMaxSteps);
}

// ---- The simulator's witness functions (dynamics/witness/), each against a closed form ----

namespace witness = mechgen::dynamics::witness;

// A sample as the witnesses read it (the fields of dynamics' SampleT they use).
struct WitnessSample {
  double t = 0, rcond = 1, det = 1;
  State1 q = State1::Zero(), qd = State1::Zero(), phi = State1::Zero();
};

TEST(Witnesses, RootFinderLocatesASignChangeByIllinois) {
  // cos t on [1, 2]: the root pi/2, superlinearly (Illinois: far fewer than bisection's 40).
  int calls = 0;
  auto g = [&](double t, double* v) {
    ++calls;
    *v = std::cos(t);
    return true;
  };
  double t_root = 0;
  ASSERT_TRUE(witness::LocateRoot(1.0, 2.0, std::cos(1.0), std::cos(2.0), 1e-13, witness::Crossing::kSignChange, g,
                                  &t_root));
  EXPECT_NEAR(t_root, std::acos(0.0), 2e-13);
  EXPECT_LT(calls, 15);
  // A linear witness: the first secant is its exact zero, which kSignChange returns at once;
  // kFallsToZero keeps bracketing (g <= 0 is beyond) and returns the far end, still 1.
  auto line = [&](double t, double* v) {
    ++calls;
    *v = 1 - t;
    return true;
  };
  calls = 0;
  ASSERT_TRUE(witness::LocateRoot(0.0, 2.0, 1.0, -1.0, 1e-12, witness::Crossing::kSignChange, line, &t_root));
  EXPECT_EQ(t_root, 1.0);
  EXPECT_EQ(calls, 1);
  ASSERT_TRUE(witness::LocateRoot(0.0, 2.0, 1.0, -1.0, 1e-12, witness::Crossing::kFallsToZero, line, &t_root));
  EXPECT_EQ(t_root, 1.0);
  // A witness that cannot be evaluated: false, and the far end.
  auto fails = [](double, double*) { return false; };
  EXPECT_FALSE(witness::LocateRoot(0.0, 2.0, 1.0, -1.0, 1e-12, witness::Crossing::kSignChange, fails, &t_root));
  EXPECT_EQ(t_root, 2.0);
}

TEST(Witnesses, BisectionLocatesADecision) {
  double ta = 0, tb = 1;
  ASSERT_TRUE(witness::LocateChange(&ta, &tb, 1e-12, [](double t) {
    return t < 0.3 ? witness::Side::kBefore : witness::Side::kAfter;
  }));
  EXPECT_LT(ta, 0.3);
  EXPECT_GE(tb, 0.3);
  EXPECT_LE(tb - ta, 1e-12);
  double t_failed = -1;
  ta = 0, tb = 1;
  EXPECT_FALSE(witness::LocateChange(&ta, &tb, 1e-12, [](double) { return witness::Side::kFailed; }, &t_failed));
  EXPECT_EQ(t_failed, 0.5);
}

TEST(Witnesses, DeadPointFiresBelowMinRcondOrWhereDetChangesSign) {
  // A branch point at t* = 0.37: 1/cond = |t - t*|, det = t* - t. The witness' value is
  // (t* - t) - min_rcond on both sides: its root t* - min_rcond.
  const double ts = 0.37, min_rcond = 1e-9;
  auto at = [&](double t) {
    WitnessSample s;
    s.t = t;
    s.rcond = std::abs(t - ts);
    s.det = ts - t;
    return s;
  };
  witness::DeadPointWitness w(min_rcond, 1e-3, 3);
  double ga = 0, gb = 0;
  EXPECT_EQ(w.Check(at(0.1), at(0.2), &ga, &gb), witness::DeadPointWitness::Found::kNone);
  ASSERT_EQ(w.Check(at(0.3), at(0.5), &ga, &gb), witness::DeadPointWitness::Found::kCrossed);
  EXPECT_EQ(ga, std::abs(0.3 - ts) - min_rcond);
  EXPECT_EQ(gb, -std::abs(0.5 - ts) - min_rcond);
  const double t_root = witness::LocateOnSamples<WitnessSample>(0.3, 0.5, ga, gb, 1e-14, w, [&](double t, WitnessSample* s) {
    *s = at(t);
    return true;
  });
  EXPECT_NEAR(t_root, ts - min_rcond, 1e-14);
  // The approach: three falling steps in a row below approach_rcond fire it; a rise resets.
  auto rc = [](double r) {
    WitnessSample s;
    s.rcond = r;
    return s;
  };
  witness::DeadPointWitness a(min_rcond, 1e-3, 3);
  EXPECT_EQ(a.Check(rc(6e-4), rc(5e-4), &ga, &gb), witness::DeadPointWitness::Found::kNone);
  EXPECT_EQ(a.Check(rc(5e-4), rc(4e-4), &ga, &gb), witness::DeadPointWitness::Found::kNone);
  EXPECT_EQ(a.Check(rc(4e-4), rc(4.5e-4), &ga, &gb), witness::DeadPointWitness::Found::kNone);  // rose
  EXPECT_EQ(a.Check(rc(4.5e-4), rc(3e-4), &ga, &gb), witness::DeadPointWitness::Found::kNone);
  EXPECT_EQ(a.Check(rc(3e-4), rc(2e-4), &ga, &gb), witness::DeadPointWitness::Found::kNone);
  EXPECT_EQ(a.Check(rc(2e-4), rc(1e-4), &ga, &gb), witness::DeadPointWitness::Found::kApproached);
}

TEST(Witnesses, SpeedZeroAndTheUsersEventAtTheirClosedFormRoots) {
  // qd = cos t: zero at pi/2; the user's g = q - 1/2 with q = t^2: zero at sqrt(1/2).
  auto at = [](double t) {
    WitnessSample s;
    s.t = t;
    s.qd(0) = std::cos(t);
    s.q(0) = t * t;
    return s;
  };
  auto dense = [&](double t, WitnessSample* s) {
    *s = at(t);
    return true;
  };
  witness::SpeedZeroWitness speed;
  double ga = 0, gb = 0;
  EXPECT_FALSE(speed.Fires(at(0.5), at(1.0), &ga, &gb));
  ASSERT_TRUE(speed.Fires(at(1.0), at(2.0), &ga, &gb));
  EXPECT_NEAR(witness::LocateOnSamples<WitnessSample>(1.0, 2.0, ga, gb, 1e-14, speed, dense), std::acos(0.0), 1e-14);
  auto g = [](double, const State1& q, const State1&, const State1&) { return q(0) - 0.5; };
  witness::UserWitness<decltype(g)> user(g);
  user.Reset(at(0.2));
  EXPECT_FALSE(user.Fires(at(0.2), at(0.5), &ga, &gb));
  ASSERT_TRUE(user.Fires(at(0.5), at(0.9), &ga, &gb));
  EXPECT_EQ(ga, 0.25 - 0.5);
  EXPECT_NEAR(witness::LocateOnSamples<WitnessSample>(0.5, 0.9, ga, gb, 1e-14, user, dense), std::sqrt(0.5), 1e-14);
  EXPECT_FALSE(user.Fires(at(0.9), at(1.0), &ga, &gb));  // no change since 0.9
}

TEST(Witnesses, SwitchIsBracketedWithTheNewSidesModes) {
  using Modes = std::array<int, 2>;
  // Two step loads switching at 0.25 and 0.6: the earliest change is the one bracketed.
  auto modes_at = [](double t, Modes* m) {
    *m = {t >= 0.25 ? 1 : 0, t >= 0.6 ? 1 : 0};
    return true;
  };
  double ta = 0, tb = 0;
  Modes modes_b{};
  ASSERT_TRUE(witness::LocateSwitch(0.0, 1.0, 1e-12, Modes{0, 0}, Modes{1, 1}, modes_at, &ta, &tb, &modes_b));
  EXPECT_LT(ta, 0.25);
  EXPECT_GE(tb, 0.25);
  EXPECT_LE(tb - ta, 1e-12);
  EXPECT_EQ(modes_b, (Modes{1, 0}));
  // sign(t - 1/2), 0 at exactly 1/2 (zero width): the new side is the one beyond, +1.
  using Mode = std::array<int, 1>;
  auto sign_at = [](double t, Mode* m) {
    *m = {t > 0.5 ? 1 : (t < 0.5 ? -1 : 0)};
    return true;
  };
  Mode mode_b{};
  ASSERT_TRUE(witness::LocateSwitch(0.0, 1.0, 1e-12, Mode{-1}, Mode{1}, sign_at, &ta, &tb, &mode_b));
  EXPECT_EQ(mode_b, (Mode{1}));
  EXPECT_GT(tb, 0.5);
  EXPECT_LE(tb - 0.5, 2e-12);
}

TEST(Witnesses, StickSlipStopBreakawayAndJointMargins) {
  // The stop: e qd = cos t (e = 1) falls to zero at pi/2; a slip that did not get going
  // (e qd <= 0 at the start) stops at the step's start.
  auto speed = [](double t, double* g) {
    *g = std::cos(t);
    return true;
  };
  double t_stop = 0;
  ASSERT_TRUE(witness::LocateSlipStop(1.0, 2.0, std::cos(1.0), std::cos(2.0), 1e-13, speed, &t_stop));
  EXPECT_NEAR(t_stop, std::acos(0.0), 1e-13);
  EXPECT_GE(t_stop, std::acos(0.0) - 1e-15);  // on the stopped side (g <= 0)
  ASSERT_TRUE(witness::LocateSlipStop(1.0, 2.0, 0.0, -1.0, 1e-13, speed, &t_stop));
  EXPECT_EQ(t_stop, 1.0);
  // The breakaway: the load exceeds the bound on (0.3, 0.6) only, slipping along -1 there.
  auto decide = [](double t, bool* stuck, double* e) {
    *stuck = !(t > 0.3 && t < 0.6);
    *e = *stuck ? 1.0 : -1.0;
    return true;
  };
  double t_break = 0, e = 0, t_failed = 0;
  // The step's end slips: found.
  EXPECT_EQ(witness::LocateBreakaway(0.0, 0.5, 1e300, 1e-12, decide, &t_break, &e, &t_failed),
            witness::Found::kTransition);
  EXPECT_GE(t_break, 0.3);
  EXPECT_LE(t_break - 0.3, 1e-12);
  EXPECT_EQ(e, -1.0);
  // Stuck again at the end: found only where a stage saw it (t_seen = 0.45).
  EXPECT_EQ(witness::LocateBreakaway(0.0, 1.0, 1e300, 1e-12, decide, &t_break, &e, &t_failed), witness::Found::kNone);
  EXPECT_EQ(witness::LocateBreakaway(0.0, 1.0, 0.45, 1e-12, decide, &t_break, &e, &t_failed),
            witness::Found::kTransition);
  EXPECT_NEAR(t_break, 0.3, 1e-12);
  // Several inputs: the least margin 0.7 - t, not positive from 0.7 on.
  auto margin = [](double t, double* g) {
    *g = 0.7 - t;
    return true;
  };
  double t_change = 0;
  EXPECT_EQ(witness::LocateJointChange(0.0, 0.5, 0.2, 1e300, 1e-12, margin, &t_change, &t_failed), witness::Found::kNone);
  EXPECT_EQ(witness::LocateJointChange(0.0, 1.0, -0.3, 1e300, 1e-12, margin, &t_change, &t_failed),
            witness::Found::kTransition);
  EXPECT_NEAR(t_change, 0.7, 1e-12);
  EXPECT_GE(t_change, 0.7);
  // A failing decision says where.
  auto fails = [](double, bool*, double*) { return false; };
  EXPECT_EQ(witness::LocateBreakaway(0.0, 1.0, 1e300, 1e-12, fails, &t_break, &e, &t_failed), witness::Found::kFailed);
  EXPECT_EQ(t_failed, 1.0);
}

TEST(Witnesses, SteadyStateFiresWhenTheCycleMeanSpeedSettled) {
  // q = w t sampled every 0.01 s: every cycle lasts 2 pi / w, so the changes of the mean speed
  // are 0 from the second timed cycle on; N = 2 of them at the fourth crossing.
  const double w = 3.0, dt = 0.01;
  mechgen::dynamics::SteadyStateOptions o;
  o.enabled = true;
  mechgen::dynamics::SteadyStateDetector d;
  mechgen::dynamics::SteadyStateSummary s;
  d.Start(o, 0.0, 0.0);
  double t_steady = -1;
  for (int k = 1; k < 10000 && t_steady < 0; ++k) {
    if (d.Add(k * dt, w * k * dt, &s)) t_steady = k * dt;
  }
  const double period = 2 * mechgen::kPi / w;
  ASSERT_TRUE(s.steady);
  EXPECT_EQ(s.crossings, 4);
  EXPECT_EQ(s.cycles, 3);
  EXPECT_NEAR(s.period, period, 1e-12);
  EXPECT_NEAR(s.mean_speed, w, 1e-12);
  EXPECT_GE(t_steady, 4 * period - 1e-12);
  EXPECT_LT(t_steady, 4 * period + dt);
}

}  // namespace
