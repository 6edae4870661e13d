// What the model-view tests (view_solver_test.cc, view_statics_test.cc, view_dynamics_test.cc,
// in model_test) compare with: the same shape and the same bits in every entry, NaN included;
// and a view's parameters set by name (tests/study, tests/flywheel).
#pragma once

#include <cstring>
#include <initializer_list>
#include <utility>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "mechgen/core/model_calls.h"
#include "mechgen/core/view_model.h"

namespace mechgen::view_test {

/// a and b of the same shape, every entry the same bits.
template <class A, class B>
::testing::AssertionResult SameBits(const char* what, const A& a, const B& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) {
    return ::testing::AssertionFailure() << what << ": " << a.rows() << " x " << a.cols() << " vs " << b.rows()
                                         << " x " << b.cols();
  }
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    for (Eigen::Index i = 0; i < a.rows(); ++i) {
      const double x = a(i, j), y = b(i, j);
      if (std::memcmp(&x, &y, sizeof(double)) != 0) {
        return ::testing::AssertionFailure() << what << "(" << i << ", " << j << "): " << x << " vs " << y
                                             << " (difference " << (x - y) << ")";
      }
    }
  }
  return ::testing::AssertionSuccess();
}

/// x and y the same bits.
inline ::testing::AssertionResult SameBits(const char* what, double x, double y) {
  if (std::memcmp(&x, &y, sizeof(double)) == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << what << ": " << x << " vs " << y;
}

/// A model's parameters through its view: the defaults, those in `values` set by name (an
/// unknown name fails the test), then the derived ones (as a study sets a sample's).
inline ViewParams ParamsOf(const ViewModel& model, std::initializer_list<std::pair<const char*, double>> values = {}) {
  using C = ModelCalls<ViewModel>;
  ViewParams p = C::DefaultParams(model);
  for (const auto& [name, value] : values) {
    double* x = C::FindParameter(model, &p, name);
    EXPECT_NE(x, nullptr) << name;
    if (x != nullptr) *x = value;
  }
  C::ParametersSet(model, &p);
  return p;
}

}  // namespace mechgen::view_test
