/**
 * \file synthesis/freudenstein.h
 * Function generation by Freudenstein's equation (issue 28, the exact method): a four-bar
 * with ground d (pivots A = (0, 0), D = (d, 0)), crank a at the input angle theta2, coupler
 * b, rocker c at the output angle theta4 (both absolute, CCW from the ground line) closes,
 * a e^{i theta2} + b e^{i theta3} = d + c e^{i theta4}, exactly where
 *   K1 cos(theta4) - K2 cos(theta2) + K3 = cos(theta2 - theta4),
 *   K1 = d / a,  K2 = d / c,  K3 = (a^2 - b^2 + c^2 + d^2) / (2 a c)
 * (|d + c e^{i theta4} - a e^{i theta2}|^2 = b^2 expanded). Three pairs (theta2_i, theta4_i)
 * give K by a 3 x 3 linear solve (exact: residuals at rounding); more pairs, the least-squares
 * K (QR). d sets the scale. Header-only, Eigen.
 */
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace mechgen::synthesis {

/// The result of Freudenstein synthesis.
struct FreudensteinResult {
  Eigen::Vector3d K = Eigen::Vector3d::Zero();  ///< K1, K2, K3
  double a = 0, b = 0, c = 0, d = 0;            ///< crank, coupler, rocker, ground
  std::vector<double> residual;                 ///< Freudenstein's equation at each pair
  bool ok = false;
  std::string why;  ///< when not ok: why there is no four-bar
};

/// Freudenstein's equation at one pair: K1 cos t4 - K2 cos t2 + K3 - cos(t2 - t4).
inline double FreudensteinResidual(const Eigen::Vector3d& K, double theta2, double theta4) {
  return K(0) * std::cos(theta4) - K(1) * std::cos(theta2) + K(2) - std::cos(theta2 - theta4);
}

/// The four-bar whose output follows theta4[i] at theta2[i] (three pairs: exactly; more: in
/// the least-squares sense of Freudenstein's equation), with ground length d > 0.
inline FreudensteinResult Freudenstein(const std::vector<double>& theta2, const std::vector<double>& theta4, double d) {
  FreudensteinResult r;
  r.d = d;
  const int n = static_cast<int>(theta2.size());
  if (n < 3 || static_cast<int>(theta4.size()) != n) {
    r.why = "Freudenstein's equation needs at least three (input, output) pairs of equal count";
    return r;
  }
  if (!(d > 0) || !std::isfinite(d)) {
    r.why = "the ground length d must be a positive number";
    return r;
  }
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd rhs(n);
  for (int i = 0; i < n; ++i) {
    A(i, 0) = std::cos(theta4[static_cast<size_t>(i)]);
    A(i, 1) = -std::cos(theta2[static_cast<size_t>(i)]);
    A(i, 2) = 1;
    rhs(i) = std::cos(theta2[static_cast<size_t>(i)] - theta4[static_cast<size_t>(i)]);
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  if (qr.rank() < 3) {
    r.why = "the pairs do not determine K1, K2, K3 (two pairs share an angle's cosine)";
    return r;
  }
  r.K = qr.solve(rhs);
  for (int i = 0; i < n; ++i)
    r.residual.push_back(FreudensteinResidual(r.K, theta2[static_cast<size_t>(i)], theta4[static_cast<size_t>(i)]));
  // Lengths: a = d / K1, c = d / K2 (a negative one is a link turned by pi: its angle's
  // cosine changes sign, so the pairs then describe the other sense), b^2 from K3.
  if (!(r.K(0) > 0) || !(r.K(1) > 0)) {
    r.why = "K1 or K2 is not positive: no four-bar with these angles measured this way";
    return r;
  }
  r.a = d / r.K(0);
  r.c = d / r.K(1);
  const double b2 = r.a * r.a + r.c * r.c + d * d - 2 * r.a * r.c * r.K(2);
  if (!(b2 > 0)) {
    r.why = "b^2 = a^2 + c^2 + d^2 - 2 a c K3 is not positive: no coupler closes the loop";
    return r;
  }
  r.b = std::sqrt(b2);
  r.ok = true;
  return r;
}

}  // namespace mechgen::synthesis
