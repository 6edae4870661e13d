// Not a program to run: compiled by the tests dynamics.missing_flag_message and
// dynamics.missing_model_flag_message (tests/dynamics/CMakeLists.txt), which expect the
// compiler to stop with the one static_assert of core/model_traits.h that names the flag the
// model type lacks.
#include "mechgen/core/model_traits.h"

#ifndef MECHGEN_TEST_OLD_HEADER
// A model type that declares none of the kHas* flags.
struct ModelWithoutFlags {};

static_assert(!mechgen::HasDynamics<ModelWithoutFlags>::value, "never reached");
#else
// A model type like a header generated before the flags of Coefficients' members and Model's
// functions: the twelve output flags only, and SolveTrig, which the runtime no longer detects.
struct OldHeaderModel {
  static constexpr bool kHasStatics = false;
  static constexpr bool kHasStaticsQ = false;
  static constexpr bool kHasStaticsStiffness = false;
  static constexpr bool kHasStaticsV = false;
  static constexpr bool kHasStaticsD2V = false;
  static constexpr bool kHasStaticsR = false;
  static constexpr bool kHasStaticsFriction = false;
  static constexpr bool kHasDynamics = false;
  static constexpr bool kHasExcess = false;
  static constexpr bool kHasShaking = false;
  static constexpr bool kHasRhs = false;
  static constexpr bool kHasRhsConstants = false;
  template <typename Scalar>
  static int SolveTrig() {
    return 0;
  }
};

static_assert(!mechgen::HasDynamics<OldHeaderModel>::value, "the output flags are there");
static_assert(!mechgen::HasSolveTrig<OldHeaderModel>::value, "never reached");
#endif

int main() { return 0; }
