// Coulomb friction's hot paths must not touch the heap either (issue 26): a whole
// MinimalDynamics::Simulate with stick and slip — the slip's fixed-point iteration on the
// kinetostatics, the decisions at rest, the located transitions and restarts, the samples —
// with both integrators, on the pushed block (stick, slip, stick ...) and the pendulum with pin
// friction (reversals, then at rest); with several inputs on two pendulums (each joint its own
// mode, one stuck while the other swings); and a driven run's friction (PrescribedDynamics: the
// slider-crank with friction at every joint at a constant crank speed). This binary counts global operator new and builds with
// EIGEN_RUNTIME_NO_MALLOC (Eigen asserts if it would allocate while malloc is disallowed).
#define EIGEN_RUNTIME_NO_MALLOC
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "incline_friction.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/prescribed.h"
#include "pendulum_friction.h"
#include "slider_crank_coulomb.h"
#include "two_pendulums_friction.h"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

// The replacements, as in no_allocation_test.cc: one out-of-line malloc/free pair, the other
// forms forwarding to it.
[[gnu::noinline]] void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return ::operator new(size); }
[[gnu::noinline]] void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { ::operator delete(p); }
void operator delete(void* p, std::size_t) noexcept { ::operator delete(p); }
void operator delete[](void* p, std::size_t) noexcept { ::operator delete(p); }

namespace {

using Vec1 = Eigen::Matrix<double, 1, 1>;

template <class M, template <int> class Method>
void SimulateWithoutAllocation(const typename M::template ParamsT<double>& p, double q0, double t_end) {
  mechgen::dynamics::MinimalOptions o;
  o.integrator.rtol = 1e-9;
  o.sample_dt = 0.01;
  mechgen::dynamics::MinimalDynamics<M, Method> sim(p, o);
  ASSERT_TRUE(sim.Initialize(Vec1(q0)));
  mechgen::dynamics::MinimalSummary summary;
  double sum = 0;
  const long before = g_allocations.load();
  Eigen::internal::set_is_malloc_allowed(false);
  const bool ok = sim.Simulate(0.0, Vec1(q0), Vec1(0.0), t_end,
                               [&](const auto& s) {
                                 sum += s.q(0) + s.friction(0);
                                 return true;
                               },
                               &summary);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(ok) << mechgen::dynamics::FormatSummary(summary);
  EXPECT_TRUE(summary.coulomb);
  EXPECT_GE(summary.friction_transitions, 4);
  EXPECT_GE(summary.stick_intervals, 1);
  EXPECT_TRUE(std::isfinite(sum));
}

TEST(CoulombNoAllocation, PushedBlock) {
  mech::incline_friction::Params<double> p;
  p.alpha = 0;
  p.F0 = 10;
  SimulateWithoutAllocation<mech::incline_friction::Model, mechgen::dynamics::Dopri5>(p, 0.0, 6.0);
  SimulateWithoutAllocation<mech::incline_friction::Model, mechgen::dynamics::Dop853>(p, 0.0, 6.0);
}

TEST(CoulombNoAllocation, PendulumWithPinFriction) {
  mech::pendulum_friction::Params<double> p;
  p.r = 0.3;  // at rest within a few seconds
  SimulateWithoutAllocation<mech::pendulum_friction::Model, mechgen::dynamics::Dopri5>(p, 0.0, 20.0);
  SimulateWithoutAllocation<mech::pendulum_friction::Model, mechgen::dynamics::Dop853>(p, 0.0, 20.0);
}

TEST(CoulombNoAllocation, SeveralInputs) {
  using M2 = mech::two_pendulums_friction::Model;
  mech::two_pendulums_friction::Params<double> p;
  p.r = 0.2;
  p.r2 = 0.01;
  mechgen::dynamics::MinimalOptions o;
  o.integrator.rtol = 1e-9;
  o.sample_dt = 0.01;
  mechgen::dynamics::MinimalDynamics<M2> sim(p, o);
  const Eigen::Vector2d q0(0.0, 0.0), qd0(0.0, 0.0);
  ASSERT_TRUE(sim.Initialize(q0));
  mechgen::dynamics::MinimalSummary summary;
  double sum = 0;
  const long before = g_allocations.load();
  Eigen::internal::set_is_malloc_allowed(false);
  const bool ok = sim.Simulate(0.0, q0, qd0, 8.0,
                               [&](const auto& s) {
                                 sum += s.q.sum() + s.friction.sum();
                                 return true;
                               },
                               &summary);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(ok) << mechgen::dynamics::FormatSummary(summary);
  EXPECT_GE(summary.stick_intervals, 1);
  EXPECT_TRUE(std::isfinite(sum));
}

TEST(CoulombNoAllocation, DrivenSliderCrank) {
  using SC = mech::slider_crank_coulomb::Model;
  using Drive = mechgen::dynamics::Drive<mechgen::dynamics::ConstantSpeedLaw>;
  mechgen::dynamics::PrescribedOptions o;
  o.sample_dt = 0.01;
  mechgen::dynamics::PrescribedDynamics<SC, 1, Drive> sim(mech::slider_crank_coulomb::Params<double>(), {0},
                                                          Drive(mechgen::dynamics::ConstantSpeedLaw{0.5, 10.0, 0.0}),
                                                          mechgen::dynamics::NoForce(), o);
  const Eigen::Matrix<double, 0, 1> none;
  ASSERT_TRUE(sim.Initialize(0.0, none));
  mechgen::dynamics::PrescribedSummary summary;
  double sum = 0;
  const long before = g_allocations.load();
  Eigen::internal::set_is_malloc_allowed(false);
  const bool ok = sim.Simulate(0.0, none, none, 1.0,
                               [&](const auto& s) {
                                 sum += s.lambda.sum() + s.friction.sum();
                                 return true;
                               },
                               &summary);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(ok) << mechgen::dynamics::FormatSummary(summary);
  EXPECT_TRUE(summary.coulomb);
  EXPECT_TRUE(std::isfinite(sum));
}

}  // namespace
