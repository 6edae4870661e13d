// The massive four-bar of bench/dynamics in Simbody, behind a plain interface: the Simbody
// translation unit is compiled apart (Debian's libsimbody-dev is built without NDEBUG, so its
// client code must be too, or it crashes; the rest of the benchmark keeps NDEBUG).
#pragma once

#include <string>
#include <vector>

namespace bench_dynamics {

enum class SimbodyIntegrator { kRungeKuttaMerson, kRungeKuttaFeldberg, kCPodes };

struct SimbodyRun {
  double theta = 0;        // crank angle at the end (unwrapped, rad)
  double energy0 = 0;      // total energy at t = 0 (Simbody's calcEnergy)
  double energy_end = 0;   // at the end
  long steps = 0;          // integrator steps taken
  long realizations = 0;   // Simbody realizations (its measure of right-hand sides)
  bool ok = false;
};

/// Builds the system once; Simulate() then integrates from rest at theta = 90 deg to t_end.
class SimbodyFourbar {
 public:
  SimbodyFourbar();
  ~SimbodyFourbar();
  SimbodyFourbar(const SimbodyFourbar&) = delete;
  SimbodyFourbar& operator=(const SimbodyFourbar&) = delete;

  /// Integrates to t_end at the given accuracy (Integrator::setAccuracy; the constraint
  /// tolerance is Simbody's default, accuracy / 10).
  SimbodyRun Simulate(SimbodyIntegrator integrator, double accuracy, double t_end) const;

  /// Energy drift E(t) - E(0) at the report times (stepTo each of them; interpolation allowed).
  void EnergyDrift(SimbodyIntegrator integrator, double accuracy, const std::vector<double>& times,
                   std::vector<double>* drift) const;

  /// Where the libSimTKsimbody in use lives (to tell the Debian build from the Release one).
  static std::string LibraryPath();

 private:
  struct Impl;
  Impl* impl_;
};

const char* Name(SimbodyIntegrator integrator);

}  // namespace bench_dynamics
