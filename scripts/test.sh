#!/usr/bin/env bash
# The README's second command: install what is missing, build everything, run the whole
# test suite (ctest), then the same suite built with AddressSanitizer and
# UndefinedBehaviorSanitizer (scripts/sanitize.sh; MECHGEN_SANITIZERS=0 skips that stage).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
# The benchmark programs are not tests (no test runs them) and were a sixth of this build's
# compile time: left out here; bench/*/run.sh configure them back in when run. Likewise the
# models' tools that no test runs (about 55 programs of 20 to 50 s of compile each):
# `bash scripts/build.sh` (the default) builds them all; see MECHGEN_ALL_MODEL_TOOLS in the
# top-level CMakeLists.txt.
# With the sanitizer stage (the default), the GoogleTest programs are built and run there only
# (MECHGEN_UNIT_TESTS=OFF here): that stage builds every one of them with ASan and UBSan and
# runs all their tests, and building them a second time here, at -O1 without the sanitizers,
# was half of this build's compile time (1,054 of 2,236 s of CPU in the cold run of stop 51)
# for the same checks on the same IEEE arithmetic. This build then runs what the user runs:
# `mechgen` and its commands, the per-model tools, the view against those tools byte for byte,
# the generated files, the install and its consumer, the fuzz findings (ctest lists them).
# MECHGEN_SANITIZERS=0 runs the whole suite here instead.
unit_tests=OFF
[ "${MECHGEN_SANITIZERS:-1}" != "0" ] || unit_tests=ON
MECHGEN_BUILD_BENCHMARKS=OFF MECHGEN_ALL_MODEL_TOOLS=OFF MECHGEN_UNIT_TESTS=$unit_tests bash scripts/build.sh
echo "test: Release build took $(( $(date +%s) - start )) s"
ctest --test-dir build --output-on-failure --parallel 2 "$@"
echo "test: Release build and tests took $(( $(date +%s) - start )) s"
if [ "${MECHGEN_SANITIZERS:-1}" != "0" ]; then
  bash scripts/sanitize.sh "$@"
fi
