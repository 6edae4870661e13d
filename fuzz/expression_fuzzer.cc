// libFuzzer target: one expression of the model language through the reader's checks,
// GiNaC's parser, differentiation and the C++ printer (targets.h, FuzzExpression).
#include "targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return mechgen_fuzz::FuzzExpression(data, size);
}
