// The switch restarts (issue 26) must not touch the heap either: a whole
// MinimalDynamics::Simulate of the shaper with masses (tests/dynamics/models/shaper_massive.yaml:
// a cutting force switched on and off twice a turn) with both integrators, restarting at every
// switch (checked: the restarts happen). Counts global operator new and builds with
// EIGEN_RUNTIME_NO_MALLOC, as no_allocation_test.cc does.
#define EIGEN_RUNTIME_NO_MALLOC
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "mechgen/dynamics/forward.h"
#include "shaper_massive.h"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

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

using M = mech::shaper_massive::Model;
using Vec1 = Eigen::Matrix<double, 1, 1>;

template <template <int> class Method>
void SimulateWithoutAllocation() {
  mechgen::dynamics::MinimalOptions o;
  o.integrator.rtol = 1e-9;
  o.sample_dt = 0.01;
  mechgen::dynamics::MinimalDynamics<M, Method> sim(M::ParamsT<double>(), o);
  ASSERT_TRUE(sim.Initialize(Vec1(0.0)));
  mechgen::dynamics::MinimalSummary summary;
  double sum = 0;
  const long before = g_allocations.load();
  Eigen::internal::set_is_malloc_allowed(false);
  const bool ok = sim.Simulate(
      0.0, Vec1(0.0), Vec1(6.0), 4.0,
      [&](const auto& s) {
        sum += s.q(0);
        return true;
      },
      &summary);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(ok) << mechgen::dynamics::FormatSummary(summary);
  EXPECT_GE(summary.switch_restarts, 2) << mechgen::dynamics::FormatSummary(summary);
  EXPECT_TRUE(std::isfinite(sum));
}

TEST(SwitchesNoAllocation, ShaperWithRestarts) {
  SimulateWithoutAllocation<mechgen::dynamics::Dopri5>();
  SimulateWithoutAllocation<mechgen::dynamics::Dop853>();
}

}  // namespace
