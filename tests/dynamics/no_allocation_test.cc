// The dynamics' hot paths must not touch the heap: a whole MinimalDynamics::Simulate (every
// rhs evaluation, the events, the dense samples, the energy projection) with both integrators,
// the excess-coordinate method, and a kinetostatics cycle, on the handwritten massive four-bar
// and the generated fourbar_massive. This binary counts global operator new and builds with
// EIGEN_RUNTIME_NO_MALLOC (Eigen asserts if it would allocate while malloc is disallowed).
#define EIGEN_RUNTIME_NO_MALLOC
#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "fourbar_massive.h"
#include "handwritten_fourbar_dynamics.h"
#include "mechgen/dynamics/excess.h"
#include "mechgen/dynamics/forward.h"
#include "mechgen/dynamics/kinetostatics.h"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

// The replacements: operator new(size_t) and operator delete(void*) are the one malloc/free
// pair, kept out of line as they would be in a translation unit of their own; the array and
// sized forms forward to them, as the library's defaults do (operator new[] is counted too).
// Inlined into a caller, the malloc() or free() of one met the other's call there and GCC 12
// warned -Wmismatched-new-delete (free() on a pointer from operator new, or operator delete
// on one from malloc()).
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
void SimulateWithoutAllocation(bool projection) {
  mechgen::dynamics::MinimalOptions o;
  o.integrator.rtol = 1e-9;
  o.sample_dt = 0.01;
  o.energy_projection = projection;
  o.stop_at_speed_zero = true;
  mechgen::dynamics::MinimalDynamics<M, Method> sim(typename M::template ParamsT<double>(), o);
  ASSERT_TRUE(sim.Initialize(Vec1(1.5707963267948966)));
  mechgen::dynamics::MinimalSummary summary;
  double sum = 0;
  const long before = g_allocations.load();
  Eigen::internal::set_is_malloc_allowed(false);
  const bool ok = sim.Simulate(
      0.0, Vec1(1.5707963267948966), Vec1(0.0), 5.0,
      [&](const auto& s) {
        sum += s.q(0);
        return true;
      },
      [](double t, const Vec1&, const Vec1&, const auto&) { return 4.0 - t; }, &summary);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(ok) << mechgen::dynamics::FormatSummary(summary);
  EXPECT_GT(summary.samples, 50);
  EXPECT_TRUE(std::isfinite(sum));
}

TEST(DynamicsNoAllocation, MinimalHandwritten) {
  SimulateWithoutAllocation<mech::handwritten_fourbar_dynamics::Model, mechgen::dynamics::Dopri5>(false);
  SimulateWithoutAllocation<mech::handwritten_fourbar_dynamics::Model, mechgen::dynamics::Dop853>(true);
}

TEST(DynamicsNoAllocation, MinimalGenerated) {
  SimulateWithoutAllocation<mech::fourbar_massive::Model, mechgen::dynamics::Dopri5>(true);
  SimulateWithoutAllocation<mech::fourbar_massive::Model, mechgen::dynamics::Dop853>(false);
}

TEST(DynamicsNoAllocation, ExcessAndKinetostatics) {
  namespace hw = mech::handwritten_fourbar_dynamics;
  mechgen::dynamics::ExcessOptions o;
  o.projection = true;
  o.sample_dt = 0.01;
  mechgen::dynamics::ExcessDynamics<hw::Model, mechgen::dynamics::Dop853> excess(hw::Params<double>(), o);
  mechgen::dynamics::ExcessSummary es;
  mechgen::dynamics::Kinetostatics<mech::fourbar_massive::Model> k((mech::fourbar_massive::Params<double>()));
  ASSERT_TRUE(k.Initialize(Vec1(0.0)));
  const long before = g_allocations.load();
  Eigen::internal::set_is_malloc_allowed(false);
  const bool ok = excess.Simulate(0.0, Vec1(1.5707963267948966), Vec1(0.0), Eigen::Vector2d(0.5, 1.9),
                                  2.0, [](const auto&) { return true; }, &es);
  const auto ks = k.Cycle(mechgen::dynamics::Kinetostatics<mech::fourbar_massive::Model>::ConstantSpeed(
                              Vec1(0.0), Vec1(3.0)),
                          0.0, 2.0, 100, [](const auto&) { return true; });
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(ok);
  EXPECT_TRUE(ks.IsSolutionUsable());
}

}  // namespace
