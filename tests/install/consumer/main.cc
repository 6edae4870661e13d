// Uses the generated four-bar without the mechgen runtime: one Newton solve on the
// generated Phi and Phi_phi, then K; prints the loop residual and exits 0 if closed.
#include <cmath>
#include <cstdio>

#include <Eigen/LU>

#include "fourbar.h"

int main() {
  using M = mech::fourbar::Model;
  const mech::fourbar::Params<double> p;
  mech::fourbar::Vec<double, M::kNq> q;
  mech::fourbar::Vec<double, M::kNphi> phi;
  for (int i = 0; i < M::kNq; ++i) q(i) = M::kAssemblyQ[i];
  for (int i = 0; i < M::kNphi; ++i) phi(i) = M::kAssemblyPhi[i];
  mech::fourbar::Vec<double, M::kNc> Phi;
  mech::fourbar::Mat<double, M::kNc, M::kNphi> Phi_phi;
  for (int it = 0; it < 50; ++it) {
    M::Phi(p, q, phi, &Phi, &Phi_phi);
    phi -= Phi_phi.inverse() * Phi;
  }
  M::Phi(p, q, phi, &Phi);
  mech::fourbar::Coefficients<double> c;
  M::Coeffs(p, q, phi, &c);
  std::printf("residual %.3g, K = (%.6f, %.6f)\n", Phi.norm(), c.K(0, 0), c.K(1, 0));
  return Phi.norm() < 1e-12 && std::isfinite(c.K(0, 0)) ? 0 : 1;
}
