#!/usr/bin/env bash
# The README's second command: install what is missing, build everything, run the whole
# test suite (ctest): all but the tests labelled sanitizer in the Release build, then the
# generator and the runtime's view instantiation built with AddressSanitizer and
# UndefinedBehaviorSanitizer and the tests labelled sanitizer run there (scripts/sanitize.sh;
# MECHGEN_SANITIZERS=0 skips that stage and runs every test in the Release build).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
# The benchmark programs are not tests (no test runs them) and were a sixth of this build's
# compile time: left out here; bench/*/run.sh configure them back in when run. Likewise the
# models' tools that no test runs (about 55 programs of 20 to 50 s of compile each):
# `bash scripts/build.sh` (the default) builds them all; see MECHGEN_ALL_MODEL_TOOLS in the
# top-level CMakeLists.txt.
# Every test but those labelled sanitizer runs here, the GoogleTest programs at -O1
# (tests/CMakeLists.txt) on what the user's compiler makes of the runtime; the sanitizer stage
# (scripts/sanitize.sh) then builds the generator and the runtime's view instantiation with ASan
# and UBSan and runs the tests labelled sanitizer (the generator's own GoogleTest programs,
# model_test, the commands through the view, the hostile models) there only: this stage neither
# builds their GoogleTest programs (MECHGEN_SANITIZER_STAGE_FOLLOWS, the top-level CMakeLists.txt)
# nor runs them (-LE sanitizer). Each test runs once, in the build that checks it most;
# MECHGEN_SANITIZERS=0 skips that stage and runs every test here.
follows=ON release_tests=(-LE sanitizer)
if [ "${MECHGEN_SANITIZERS:-1}" = "0" ]; then follows=OFF release_tests=(); fi
MECHGEN_BUILD_BENCHMARKS=OFF MECHGEN_ALL_MODEL_TOOLS=OFF MECHGEN_UNIT_TESTS=ON \
  MECHGEN_SANITIZER_STAGE_FOLLOWS=$follows bash scripts/build.sh
echo "test: Release build took $(( $(date +%s) - start )) s"
ctest --test-dir build --output-on-failure --parallel 2 "${release_tests[@]}" "$@"
echo "test: Release build and tests took $(( $(date +%s) - start )) s"
if [ "${MECHGEN_SANITIZERS:-1}" != "0" ]; then
  bash scripts/sanitize.sh "$@"
fi
