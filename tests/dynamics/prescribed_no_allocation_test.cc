// PrescribedDynamics (mechgen/dynamics/prescribed.h) must not touch the heap in its hot path:
// a whole Simulate() with a driver (the five-bar with crank2 on a spline law, crank1 free),
// with every coordinate prescribed (inverse dynamics), and a run stopped at a singular
// configuration (event location on the dense output). This binary counts global operator new
// and builds with EIGEN_RUNTIME_NO_MALLOC (Eigen asserts if it would allocate).
#define EIGEN_RUNTIME_NO_MALLOC
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "fivebar_massive.h"
#include "fivebar_robot.h"
#include "mechgen/dynamics/prescribed.h"

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

namespace dyn = mechgen::dynamics;
using V1 = Eigen::Matrix<double, 1, 1>;
using V0 = Eigen::Matrix<double, 0, 1>;

TEST(PrescribedNoAllocation, DriverInverseAndSingularStop) {
  using FB = mech::fivebar_massive::Model;
  using Robot = mech::fivebar_robot::Model;
  dyn::PrescribedOptions o;
  o.integrator.rtol = 1e-9;
  o.sample_dt = 0.01;
  auto spline = dyn::MakeDrive(dyn::SplineLaw<4>({0.0, 0.4, 0.8, 1.2}, {1.5707963267948966, 1.9, 2.1, 1.6}));
  dyn::PrescribedDynamics<FB, 1, decltype(spline), dyn::NoForce, dyn::Dopri5> driven(
      FB::ParamsT<double>(), {1}, spline, dyn::NoForce(), o);
  ASSERT_TRUE(driven.Initialize(0.0, V1(1.5707963267948966)));
  auto both = dyn::MakeDrive(dyn::RestToRestLaw{2.3, 2.0, 0.0, 0.5}, dyn::RestToRestLaw{0.8, 1.1, 0.0, 0.5});
  dyn::PrescribedDynamics<Robot, 2, decltype(both), dyn::NoForce, dyn::Dop853> inverse(
      Robot::ParamsT<double>(), {0, 1}, both, dyn::NoForce(), o);
  ASSERT_TRUE(inverse.Initialize(0.0, V0()));
  o.min_rcond = 1e-3;
  auto opening = dyn::MakeDrive(dyn::ConstantSpeedLaw{2.356194490192345, 1.0, 0.0},
                                dyn::ConstantSpeedLaw{0.7853981633974483, -1.0, 0.0});
  dyn::PrescribedDynamics<Robot, 2, decltype(opening), dyn::NoForce, dyn::Dopri5> singular(
      Robot::ParamsT<double>(), {0, 1}, opening, dyn::NoForce(), o);
  ASSERT_TRUE(singular.Initialize(0.0, V0()));

  dyn::PrescribedSummary s1, s2, s3;
  double sum = 0;
  int withheld = 0;  // samples whose actuator forces are withheld (NaN): at a singular stop
  auto observe = [&](const auto& s) {
    if (s.lambda.allFinite()) {
      sum += s.q(0) + s.lambda.sum();
    } else {
      ++withheld;
    }
    return true;
  };
  const long before = g_allocations.load();
  Eigen::internal::set_is_malloc_allowed(false);
  const bool ok1 = driven.Simulate(0.0, V1(1.5707963267948966), V1(0.0), 1.5, observe, &s1);
  const bool ok2 = inverse.Simulate(0.0, V0(), V0(), 0.6, observe, &s2);
  const bool ok3 = singular.Simulate(0.0, V0(), V0(), 1.0, observe, &s3);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(ok1) << dyn::FormatSummary(s1);
  EXPECT_TRUE(ok2) << dyn::FormatSummary(s2);
  EXPECT_FALSE(ok3);
  EXPECT_EQ(s3.status, dyn::Status::kDeadPoint) << dyn::FormatSummary(s3);
  EXPECT_GT(s1.samples, 100);
  EXPECT_TRUE(std::isfinite(sum));
  EXPECT_EQ(withheld, 1);  // the sample where the singular run stopped, only
}

}  // namespace
