// Not a program to run: compiled by the test dynamics.missing_flag_message
// (tests/dynamics/CMakeLists.txt), which expects the compiler to stop with the one
// static_assert of core/model_traits.h that names the flag the model type lacks.
#include "mechgen/core/model_traits.h"

// A model type that declares none of the twelve kHas* flags.
struct ModelWithoutFlags {};

static_assert(!mechgen::HasDynamics<ModelWithoutFlags>::value, "never reached");

int main() { return 0; }
