// The shipped models as GoogleTest type lists, for tests that run on every model.
//
// AllModels is every model of MECHGEN_SHIPPED_MODELS (models/CMakeLists.txt): CMake writes
// kinematics_shipped_models.h with their includes and MECHTEST_SHIPPED_MODEL_TYPES, so a
// newly shipped model is covered by the generic tests (finite differences, Jacobians, Jets,
// float, no allocation) without editing this file. PaulModels is the five models whose
// geometry the hand-written oracles and loop_closure_test.cc transcribe from their YAML.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "fivebar.h"
#include "fourbar.h"
#include "fourbar_crossed.h"
#include "inverted_slider_crank.h"
#include "kinematics_shipped_models.h"
#include "slider_crank.h"

namespace mechtest {

using AllModels = ::testing::Types<MECHTEST_SHIPPED_MODEL_TYPES>;

using PaulModels = ::testing::Types<mech::fourbar::Model,
                                    mech::fourbar_crossed::Model,
                                    mech::slider_crank::Model,
                                    mech::inverted_slider_crank::Model,
                                    mech::fivebar::Model>;

/// Names typed tests by the model ("FiniteDifferenceTest/fivebar.KMatches...").
class ModelNames {
 public:
  template <typename M>
  static std::string GetName(int) {
    return M::kName;
  }
};

/// Samples: 720 over a full crank turn for one input (0.5 deg apart); a 25 x 25 grid over
/// the two ranges of a two-input model (the five-bar: 5 deg apart); 200 random points
/// (fixed seed) for more inputs.
template <class M>
constexpr int kSamplesPerDof = M::kNq == 1   ? 720
                               : M::kNq == 2 ? 25
                                             : 200;

}  // namespace mechtest
