// The integrators on problems with closed-form solutions: y' = -y and the harmonic
// oscillator. Orders are measured, not assumed: with fixed steps (h_initial, rtol huge so that
// every step is accepted... no: with h_max forcing the step) the global error must fall like
// h^5 (Dopri5) and h^8 (Dop853); the dense output like h^5 / h^8 too (local order 5 / 8 of
// the continuous extensions = global order 4+1 and 7+1 at interior points); the adaptive
// control must meet a tolerance; failures of f must end in a status.
#include <cmath>

#include <gtest/gtest.h>

#include "mechgen/dynamics/integrators.h"

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

}  // namespace
