// libFuzzer target: the sweep command's argument parsing and what it drives (targets.h,
// sweep_target.h). Runs in a private temporary directory (the files it writes stay there);
// run it with -close_fd_mask=3 (fuzz/run.sh does) so that its output does not flood the log,
// and with absolute paths for the corpus, the dictionary and the artifacts.
#include <unistd.h>

#include <cstdlib>

#define MECHGEN_FUZZ_NO_GENERATOR
#include "sweep_target.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  char dir[] = "/tmp/mechgen_sweep_fuzz_XXXXXX";
  if (mkdtemp(dir) == nullptr || chdir(dir) != 0) std::abort();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)mechgen_fuzz::FuzzSweep(data, size);
  return 0;
}
