// Shared oracles of the dynamics tests, written for any model in generated shape (the
// handwritten four-bar and the generated models alike).
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace dynamics_test {

/// Complete elliptic integral of the first kind K(k) = pi / (2 AGM(1, sqrt(1 - k^2))),
/// by the arithmetic–geometric mean (converges quadratically).
inline double EllipticK(double k) {
  double a = 1.0, b = std::sqrt(1.0 - k * k);
  for (int i = 0; i < 64 && std::abs(a - b) > 1e-16 * a; ++i) {
    const double an = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = an;
  }
  return M_PI / (2.0 * a);
}

/// Period of a pendulum (moment of inertia J about the pivot, m g lc of its weight) swinging
/// with amplitude theta0 from the downward vertical:
///   T = 4 sqrt(J / (m g lc)) K(sin(theta0 / 2)).
inline double PendulumPeriod(double J, double mglc, double theta0) {
  return 4.0 * std::sqrt(J / mglc) * EllipticK(std::sin(theta0 / 2));
}

/// Generalized inertia from point velocities: for each moving link with mass m, centre G
/// and moment of inertia J about G, T = 1/2 sum (m |v_G|^2 + J omega^2) with v_G, omega
/// taken by central differences of solved positions along the motion (qd = 1), so that
/// I = 2 T / qd^2. `centre(q, link, &xy, &angle)` returns the centre and the angle of a link at
/// the configuration solved at q.
template <class Centre>
double InertiaFromPointVelocities(double q, int num_links, const double* m, const double* J,
                                  Centre&& centre, double h = 1e-5) {
  double I = 0;
  for (int i = 0; i < num_links; ++i) {
    Eigen::Vector2d gp, gm;
    double ap = 0, am = 0;
    centre(q + h, i, &gp, &ap);
    centre(q - h, i, &gm, &am);
    const Eigen::Vector2d v = (gp - gm) / (2 * h);
    const double w = (ap - am) / (2 * h);
    I += m[i] * v.squaredNorm() + J[i] * w * w;
  }
  return I;
}

}  // namespace dynamics_test
