// The five-bar robot of robot_cycle.h in Simbody, behind a plain interface (the Simbody
// translation unit is compiled apart: Debian's libsimbody-dev needs NDEBUG undefined).
#pragma once

#include <string>
#include <vector>

namespace bench_multi {

enum class SimbodyIntegrator { kRungeKuttaMerson, kRungeKuttaFeldberg, kCPodes };
const char* Name(SimbodyIntegrator integrator);

struct SimbodyRobotRun {
  double q[2] = {0, 0};  // motor angles at the end (rad)
  long steps = 0;
  long realizations = 0;
  bool ok = false;
};

class SimbodyFivebar {
 public:
  SimbodyFivebar();
  ~SimbodyFivebar();
  SimbodyFivebar(const SimbodyFivebar&) = delete;
  SimbodyFivebar& operator=(const SimbodyFivebar&) = delete;

  /// The cycle from rest at q_ref(0) to t_end at the given accuracy (Integrator::setAccuracy).
  /// restart_at_breaks: step to each of robot_cycle.h's kCycleBreaks and initialize the
  /// integrator again there (as the mechgen "Breaks" runs restart theirs).
  SimbodyRobotRun Simulate(SimbodyIntegrator integrator, double accuracy, double t_end,
                           bool restart_at_breaks = false) const;

  /// Stores n states along a simulation (accuracy 1e-8) to time the right-hand side on.
  void RecordStates(int n, double t_end);
  /// One right-hand side at recorded state k % n: set t, q, u, realize(Acceleration).
  /// Returns the first motor's acceleration (to keep it observable).
  double Rhs(int k);

  static std::string LibraryPath();

 private:
  struct Impl;
  Impl* impl_;
};

}  // namespace bench_multi
