// A sweep step (PositionSolver::MoveTo + ComputeMotion) must not touch the heap.
//
// This binary replaces the global operator new with a counting one, and also builds with
// EIGEN_RUNTIME_NO_MALLOC so that Eigen asserts if it would allocate while
// Eigen::internal::set_is_malloc_allowed(false) is in effect.
#define EIGEN_RUNTIME_NO_MALLOC
#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "handwritten_fourbar.h"
#include "handwritten_rocker_driven.h"
#ifdef MECHGEN_HAVE_fourbar
#include "fourbar.h"
#include "mechgen/core/view_runtime.h"  // PositionSolver<ViewModel>: mechgen_runtime_view
namespace mech::fourbar {
const mechgen::ModelView& View();
}
#endif
#include "mechgen/position/motion.h"
#include "mechgen/position/ceres_adapter.h"
#include "mechgen/position/solver.h"

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

namespace mechgen::position {
namespace {

template <class M>
long AllocationsDuringSweep(double q_begin, double q_end, int steps) {
  using VecQ = typename ModelTypes<M>::VecQ;
  CeresPositionSolver<M> solver;
  EXPECT_EQ(solver.AssembleDefault(nullptr), Status::kConverged);  // Ceres: allocates
  EXPECT_EQ(solver.MoveTo(VecQ::Constant(q_begin), nullptr), Status::kConverged);
  Summary summary;
  Motion<M> motion;
  const long before = g_allocations.load();
  Eigen::internal::set_is_malloc_allowed(false);
  for (int i = 1; i <= steps; ++i) {
    const VecQ q = VecQ::Constant(q_begin + (q_end - q_begin) * i / steps);
    solver.MoveTo(q, &summary);
    ComputeMotion(solver.state(), VecQ::Constant(1.0), VecQ::Constant(0.0), &motion);
    EXPECT_EQ(summary.status, Status::kConverged);
  }
  Eigen::internal::set_is_malloc_allowed(true);
  return g_allocations.load() - before;
}

TEST(NoAllocation, CountingOperatorNewSeesAllocations) {
  const long before = g_allocations.load();
  int* volatile p = new int(3);  // volatile: the compiler may not elide the pair
  delete p;
  EXPECT_EQ(g_allocations.load() - before, 1);
}

TEST(NoAllocation, FourBarSweepStep) {
  // 0.5 deg steps over a full turn, K and L from the model.
  EXPECT_EQ(AllocationsDuringSweep<mech::handwritten_fourbar::Model>(0, 2 * M_PI, 720), 0);
}

TEST(NoAllocation, OrderOneModelWithNumericalL) {
  // Larger steps that need sub-stepping near the toggle, and L by finite differences.
  EXPECT_EQ(AllocationsDuringSweep<mech::handwritten_rocker_driven::Model>(1.8, 2.46, 40), 0);
}

TEST(NoAllocation, NewtonAssemblerFromPoorGuessAndFallback) {
  // The Ceres-free Assembler (fixed-size Levenberg–Marquardt) allocates nothing: assembly
  // from a poor guess, and a continuation into a dead point that ends in the fallback.
  using M = mech::handwritten_rocker_driven::Model;
  using VecQ = typename ModelTypes<M>::VecQ;
  using VecPhi = typename ModelTypes<M>::VecPhi;
  PositionSolver<M> solver;  // NewtonAssembler
  Summary summary;
  const long before = g_allocations.load();
  Eigen::internal::set_is_malloc_allowed(false);
  const Status assembled = solver.Assemble(VecQ::Constant(2.0), VecPhi(-0.2, 0.8), 0, &summary);
  const Status stopped = solver.MoveTo(VecQ::Constant(2.5), &summary);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(assembled, Status::kConverged);
  EXPECT_EQ(stopped, Status::kSingular);  // beyond the toggle at 2.467 rad
  EXPECT_TRUE(summary.used_assembler);
  EXPECT_EQ(g_allocations.load() - before, 0);
}

#ifdef MECHGEN_HAVE_fourbar
TEST(NoAllocation, GeneratedFourBarSweepStep) {
  // The generated model: M::Solve (closed-form dyad) corrects, and the checks use the Phi
  // and Phi_phi of Model::Coeffs (ModelFeatures::kCoeffsHavePhi).
  static_assert(ModelFeatures<mech::fourbar::Model>::kCoeffsHavePhi);
  static_assert(!ModelFeatures<mech::handwritten_fourbar::Model>::kCoeffsHavePhi);
  EXPECT_EQ(AllocationsDuringSweep<mech::fourbar::Model>(0, 2 * M_PI, 720), 0);
}

TEST(NoAllocation, ViewFourBarAssemblySweepAndSplitStep) {
  // The runtime compiled once for the model view (issue 43): bounded dynamic matrices, the
  // view's buffers on the stack. Assembly (NewtonAssembler), 720 steps with the motion, and a
  // step long enough to be split allocate nothing (operator new; Eigen's own heap would need a
  // size beyond the bounds, which the bounded types cannot hold).
  using VecQ = ModelTypes<ViewModel>::VecQ;
  const long before = g_allocations.load();
  Eigen::internal::set_is_malloc_allowed(false);
  ViewPositionSolver solver{ViewModel(mech::fourbar::View())};
  Summary summary;
  const Status assembled = solver.AssembleDefault(&summary);
  Motion<ViewModel> motion;
  int converged = 0;
  for (int i = 0; i <= 720; ++i) {
    converged += solver.MoveTo(VecQ::Constant(1, 2 * M_PI * i / 720), &summary) == Status::kConverged;
    ComputeMotion(solver.state(), VecQ::Constant(1, 1.0), VecQ::Constant(1, 0.0), &motion);
  }
  const Status split = solver.MoveTo(VecQ::Constant(1, M_PI), &summary);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(assembled, Status::kConverged);
  EXPECT_EQ(converged, 721);
  EXPECT_EQ(split, Status::kConverged);
  EXPECT_GT(summary.rejected_substeps + summary.substeps, 1);  // it was split
  EXPECT_EQ(g_allocations.load() - before, 0);
}
#endif

}  // namespace
}  // namespace mechgen::position
