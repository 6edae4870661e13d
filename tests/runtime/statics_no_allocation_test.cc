// The per-configuration statics functions (Solve, SolveAt, AnalyzeDrive, EvaluateRecord) must
// not touch the heap: this binary counts calls of the global operator new and builds with
// EIGEN_RUNTIME_NO_MALLOC (Eigen asserts if it would allocate while malloc is disallowed).
#define EIGEN_RUNTIME_NO_MALLOC
#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "handwritten_statics_pendulum.h"
#include "handwritten_statics_slider_crank.h"
#include "mechgen/position/solver.h"
#include "mechgen/statics/solve.h"
#include "mechgen/statics/sweep.h"

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

namespace mechgen::statics {
namespace {

template <class M>
long AllocationsPerConfiguration(double q_begin, double q_end, int steps) {
  using VecQ = typename ModelTypes<M>::VecQ;
  position::PositionSolver<M> solver;
  EXPECT_EQ(solver.AssembleDefault(nullptr), position::Status::kConverged);
  EXPECT_EQ(solver.MoveTo(VecQ::Constant(q_begin), nullptr), position::Status::kConverged);
  Solution<M> solution;
  DriveAnalysis drive;
  StaticsRecord<M> record;
  int converged = 0;
  const long before = g_allocations.load();
  Eigen::internal::set_is_malloc_allowed(false);
  for (int i = 1; i <= steps; ++i) {
    solver.MoveTo(VecQ::Constant(q_begin + (q_end - q_begin) * i / steps), nullptr);
    converged += SolveAt<M>(Options(), solver.params(), solver.state(), VecQ::Constant(1.0),
                            &solution) == Status::kConverged;
    converged += AnalyzeDriveAt<M>(Options(), solver.params(), solver.state(), 0, &drive) ==
                 Status::kConverged;
    record.kinematics.state = solver.state();
    record.kinematics.summary.status = position::Status::kConverged;
    converged += EvaluateRecord<M>(Options(), solver.params(), &record) == Status::kConverged;
  }
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(converged, 3 * steps);
  return g_allocations.load() - before;
}

TEST(StaticsNoAllocation, CountingOperatorNewSeesAllocations) {
  const long before = g_allocations.load();
  std::vector<double> v(10);
  EXPECT_GT(g_allocations.load(), before);
}

TEST(StaticsNoAllocation, SliderCrankWithFriction) {
  EXPECT_EQ(AllocationsPerConfiguration<mech::handwritten_statics_slider_crank::Model>(0.1, 6.0, 200),
            0);
}

TEST(StaticsNoAllocation, PendulumWithPotential) {
  EXPECT_EQ(AllocationsPerConfiguration<mech::handwritten_statics_pendulum::Model>(-3.0, 6.0, 200),
            0);
}

}  // namespace
}  // namespace mechgen::statics
