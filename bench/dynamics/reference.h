// The reference theta(t_end) of the massive four-bar, independent of the code under test:
// the hand-written EOM (handwritten_dynamics.h) in long double, classical RK4 with a fixed
// step on 2^n and 2^(n+1) steps, and Richardson's extrapolation (error ~ h^4: the difference
// / 15 estimates the error of the finer run). Cross-checked against Simbody at its tightest
// accuracy by dynamics_reference (bench/dynamics/reference_main.cc).
#pragma once

#include <cmath>

#include "handwritten_dynamics.h"

namespace bench_dynamics {

struct ReferenceSolution {
  long double theta = 0, thetad = 0;  // at t_end, from 2^(n+1) steps extrapolated
  long double error_estimate = 0;     // |theta_fine - theta_coarse| / 15
  long double energy_drift = 0;       // E(t_end) - E(0) of the fine run
};

inline void Rk4(long double t_end, long steps, long double* q, long double* qd) {
  const FourbarParams<long double> p;
  const long double h = t_end / steps;
  FourbarEom<long double> e;
  auto f = [&](long double x, long double v) {
    Rhs(p, x, v, &e);
    return e.qdd;
  };
  long double x = *q, v = *qd;
  for (long i = 0; i < steps; ++i) {
    const long double k1x = v, k1v = f(x, v);
    const long double k2x = v + 0.5L * h * k1v, k2v = f(x + 0.5L * h * k1x, v + 0.5L * h * k1v);
    const long double k3x = v + 0.5L * h * k2v, k3v = f(x + 0.5L * h * k2x, v + 0.5L * h * k2v);
    const long double k4x = v + h * k3v, k4v = f(x + h * k3x, v + h * k3v);
    x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
  }
  *q = x;
  *qd = v;
}

/// From rest at theta = 90 deg to t_end on 2^log2_steps and twice as many steps.
inline ReferenceSolution ComputeReference(double t_end, int log2_steps = 16) {
  const long double q0 = 3.14159265358979323846264338327950288L / 2;
  long double qc = q0, vc = 0, qf = q0, vf = 0;
  Rk4(t_end, 1L << log2_steps, &qc, &vc);
  Rk4(t_end, 1L << (log2_steps + 1), &qf, &vf);
  ReferenceSolution r;
  r.theta = qf + (qf - qc) / 15;
  r.thetad = vf + (vf - vc) / 15;
  r.error_estimate = std::fabs(qf - qc) / 15;
  const FourbarParams<long double> p;
  r.energy_drift = Energy(p, qf, vf) - Energy(p, q0, 0.0L);
  return r;
}

}  // namespace bench_dynamics
