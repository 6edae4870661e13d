// The runtime math of issue 16 (harmonics, energy loop, Wittenbauer, rotor and engine balance)
// allocates nothing: the global operator new is replaced by a counting one, armed around the
// calls (PrintBalanceTable, which formats text, is the documented exception and not called).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <new>

#include "mechgen/machines/balancing/engine_balance.h"
#include "mechgen/machines/balancing/rotor.h"
#include "mechgen/machines/engine/harmonics.h"
#include "mechgen/machines/flywheel/energy_loop.h"

namespace {
bool armed = false;
int allocations = 0;
}  // namespace

// The replacements: operator new(size_t) and operator delete(void*) are the one malloc/free
// pair, kept out of line as they would be in a translation unit of their own; the array and
// sized forms forward to them, as the library's defaults do (operator new[] is counted too).
// Inlined into a caller, the malloc() or free() of one met the other's call there and GCC 12
// warned -Wmismatched-new-delete (free() on a pointer from operator new, or operator delete
// on one from malloc()).
[[gnu::noinline]] void* operator new(std::size_t size) {
  if (armed) ++allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return ::operator new(size); }
[[gnu::noinline]] void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { ::operator delete(p); }
void operator delete(void* p, std::size_t) noexcept { ::operator delete(p); }
void operator delete[](void* p, std::size_t) noexcept { ::operator delete(p); }

namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(NoAllocation, FlywheelAndBalancingMath) {
  constexpr int n = 128;
  double f[n], E[n], I[n], T[n], omega[n];
  for (int k = 0; k < n; ++k) {
    const double t = 2 * kPi * k / n;
    f[k] = 40 * std::sin(t) + 10 * std::cos(3 * t);
    I[k] = 1 + 0.1 * std::cos(2 * t);
    T[k] = 500 + 30 * std::sin(t);
    omega[k] = std::sqrt(2 * T[k] / I[k]);
  }
  const double areas[6] = {295, -685, 40, -340, 960, -270};
  const mechgen::balancing::Unbalance u[3] = {{1, 0.1, 0, 0}, {2, 0.05, 1, 0.3}, {0.5, 0.2, 2, 0.6}};

  armed = true;
  mechgen::engine::Harmonic h[8];
  const auto hs = mechgen::engine::Analyze(f, n, 2 * kPi, 0.2, 8, h);
  const auto loop = mechgen::flywheel::ExcessEnergy(f, n, 2 * kPi, 0.2, {}, E);
  const auto area = mechgen::flywheel::DeltaEFromAreas(areas, 6);
  const auto trace = mechgen::flywheel::AnalyzeSpeedTrace(omega, n, mechgen::flywheel::TraceSampling::kAngle);
  const auto speeds = mechgen::flywheel::Wittenbauer(I, T, n);
  const auto design = mechgen::flywheel::DesignByWittenbauer(I, E, n, 40, 30);
  const auto rotor = mechgen::balancing::BalanceTwoPlanes(u, 3, 0, 0.6, 0.1, 0.1);
  const auto layouts = mechgen::balancing::EngineLayouts();
  double total = 0;
  for (const auto& e : layouts) total += mechgen::balancing::AnalyzeBalance(e, 0.3).moment[0].Max();
  armed = false;

  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(hs, mechgen::engine::HarmonicsStatus::kOk);
  EXPECT_TRUE(loop.IsUsable());
  EXPECT_DOUBLE_EQ(area.delta, 985);
  EXPECT_EQ(trace.status, mechgen::flywheel::TraceStatus::kOk);
  EXPECT_EQ(speeds.status, mechgen::flywheel::WittenbauerStatus::kOk);
  EXPECT_TRUE(std::isfinite(design.I_flywheel));
  EXPECT_TRUE(rotor.IsUsable());
  EXPECT_GT(total, 0);
}

}  // namespace
