// Helpers of the statics tests: positions along a sweep from the generated closed-form
// solver, lookup of coordinates, reactions and friction joints by name, and tolerances.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace mechtest::statics {

constexpr double kDeg = M_PI / 180;

/// Index of `name` in a names array, -1 if absent.
template <size_t N>
int IndexOf(const std::array<const char*, N>& names, const std::string& name) {
  for (size_t i = 0; i < N; ++i) {
    if (name == names[i]) return static_cast<int>(i);
  }
  return -1;
}

/// Solves the positions at q (a single input) with the generated solver on the model's
/// assembly branch; the guess is the model's assembly phi.
template <typename M>
bool SolveAt(const typename M::template ParamsT<double>& p, double q,
             Eigen::Matrix<double, M::kNphi, 1>* phi) {
  for (int i = 0; i < M::kNphi; ++i) (*phi)(i) = M::kAssemblyPhi[i];
  const Eigen::Matrix<double, M::kNq, 1> qv = Eigen::Matrix<double, M::kNq, 1>::Constant(q);
  const auto report = M::Solve(p, qv, phi);
  return report.status == std::decay_t<decltype(report.status)>::kConverged;
}

/// |a - b| <= tol * max(1, scale): the check every comparison below makes.
inline ::testing::AssertionResult Near(double a, double b, double tol, double scale,
                                       const std::string& what) {
  const double bound = tol * std::max(1.0, std::abs(scale));
  if (std::abs(a - b) <= bound && std::isfinite(a) && std::isfinite(b)) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << what << ": generated/left " << a << " vs oracle/right "
                                       << b << " (diff " << a - b << ", bound " << bound << ")";
}

}  // namespace mechtest::statics
