// dynamics_reference: prints the reference theta(3 s) of the massive four-bar (reference.h),
// its convergence, checks of the hand-written EOM (the two forms against each other, I'
// against a central difference of I, Q against -dV/dq) and the cross-check with Simbody at
// its tightest accuracies. Output: results/reference.txt of bench/dynamics/run.sh.
#include <cmath>
#include <cstdio>

#include "handwritten_dynamics.h"
#include "reference.h"
#include "simbody_fourbar.h"

using namespace bench_dynamics;

int main() {
  const double t_end = 3.0;
  // Checks of the hand-written EOM over a turn.
  const FourbarParams<long double> pl;
  long double max_form = 0, max_di = 0, max_q = 0;
  for (int i = 0; i < 360; ++i) {
    const long double q = i * 3.14159265358979323846L / 180 + 0.001L, qd = 1.7L;
    FourbarEom<long double> a, b, ap, am;
    Rhs(pl, q, qd, &a);
    RhsTextbook(pl, q, qd, &b);
    max_form = std::fmax(max_form, std::fabs(a.qdd - b.qdd) / (1 + std::fabs(a.qdd)));
    const long double dq = 1e-6L;
    Rhs(pl, q + dq, qd, &ap);
    Rhs(pl, q - dq, qd, &am);
    max_di = std::fmax(max_di, std::fabs((ap.I - am.I) / (2 * dq) - a.dI) / (1 + std::fabs(a.dI)));
    const long double dV = (Energy(pl, q + dq, 0.0L) - Energy(pl, q - dq, 0.0L)) / (2 * dq);
    max_q = std::fmax(max_q, std::fabs(dV + a.Q) / (1 + std::fabs(a.Q)));
  }
  std::printf("hand-written EOM over a turn (rel. max): |fast - textbook| qdd %.1Le, "
              "I' vs central diff of I %.1Le, Q vs -dV/dq %.1Le\n", max_form, max_di, max_q);

  std::printf("reference theta(3 s), long double RK4 on 2^n and 2^(n+1) fixed steps + Richardson:\n");
  ReferenceSolution ref;
  for (int n = 12; n <= 17; ++n) {
    ref = ComputeReference(t_end, n);
    std::printf("  n = %2d  theta = %.18Lf  thetad = %.15Lf  est. error %.1Le  energy drift %.1Le J\n",
                n, ref.theta, ref.thetad, ref.error_estimate, ref.energy_drift);
  }
  SimbodyFourbar simbody;
  std::printf("Simbody (%s):\n", SimbodyFourbar::LibraryPath().c_str());
  for (SimbodyIntegrator integ : {SimbodyIntegrator::kRungeKuttaMerson,
                                  SimbodyIntegrator::kRungeKuttaFeldberg,
                                  SimbodyIntegrator::kCPodes}) {
    for (double acc : {1e-10, 1e-11, 1e-12, 1e-13}) {
      if (acc < 1e-12 && integ != SimbodyIntegrator::kRungeKuttaMerson) continue;
      const SimbodyRun run = simbody.Simulate(integ, acc, t_end);
      std::printf("  %-10s accuracy %.0e  theta = %.15f  |theta - ref| = %.2e  steps %ld  %s\n",
                  Name(integ), acc, run.theta, std::fabs(run.theta - (double)ref.theta), run.steps,
                  run.ok ? "ok" : "FAILED");
    }
  }
  return 0;
}
