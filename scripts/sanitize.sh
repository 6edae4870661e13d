#!/usr/bin/env bash
# Second stage of the test command: builds the test suite with AddressSanitizer and
# UndefinedBehaviorSanitizer in ./build-asan (MECHGEN_ASAN_BUILD overrides) and runs ctest
# there. Called by scripts/test.sh (and so by .ci/run) after the Release suite. Neither the
# benchmarks nor the per-model sweeps (<model>_sweep: MECHGEN_BUILD_SWEEPS=OFF; the tests that
# run them run in the Release suite only) are built, and of the other per-model tools
# (_statics, _simulate, _engine, _flywheel) only those a test runs (MECHGEN_ALL_MODEL_TOOLS=OFF,
# the top-level CMakeLists.txt): one executable per model, most of this stage's build time
# once. The GoogleTest programs are built and run here only (scripts/test.sh builds the
# Release suite with MECHGEN_UNIT_TESTS=OFF). Every other test runs; extra ctest arguments are passed on (e.g. -R runtime to restrict it,
# -LE slow to skip the slow ones). Two tests that repeat identical generator runs to compare
# their bytes are left to the Release suite (GeneratedFiles.SameBytesOnEveryRun: six runs of
# every shipped model; Report.SameBytesFromSeparateProcesses): this stage's build already runs
# the sanitized generator on every shipped model, and GeneratedFiles.MatchWhatTheGenerator-
# ProducesNow runs it once more here; repeating the same runs adds no sanitizer coverage and
# took 300 of this stage's 985 test seconds. Likewise synthesis.command and study.command: they
# compile the synthesize and study drivers with the system compiler, uninstrumented (about 60 s
# each), and run them; the sanitized generator run inside them is every other test's too, and
# the drivers' code is sanitized here by synthesis_test and study_test, which link it. And
# statics_speed_command, for the same reason (it compiles the uninstrumented statics driver, 60
# to 85 s); the statics at a speed are sanitized here by statics_slider_crank_friction_test.
# The generated headers' standalone compile checks (kinematics.standalone_header.*,
# kinematics.header_includes.*) are not defined in this build (tests/kinematics/CMakeLists.txt):
# they check the compile with the shipped flags, which the Release build makes.
# Optimization: -Og with line tables (-g1) for everything: the generator, the runtime's view
# library, the model libraries and the test programs (MECHGEN_TEST_OPTIMIZATION in the
# top-level CMakeLists.txt). The sanitizers instrument at every level (their manuals advise
# -O1 for speed of the run, not for the checks); -Og takes a quarter to a half less compile time than -O1
# (runtime/view/dynamics.cc under ASan+UBSan: 140 s of user time against 185-268 s; the Jet
# typed test: 87 s against 154 s), and this stage's build is the largest part of CI; its
# tests run longer (365 s against ~290 s at -O1): cold, this stage took 1,832 s at -Og (build 1,499, tests 333) against 1,867 + ~290 at -O1. At
# RelWithDebInfo's -O2 -g this stage's build took about three times as long (the Jet typed
# test: 277 s against 109 s; the V8 engine's model library: 79 s against 25 s) and pushed
# CI past its 90 minutes; the reports keep file and line.
#   bash scripts/sanitize.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build=${MECHGEN_ASAN_BUILD:-build-asan}
sanitize="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
# The sanitizer options apply at build time too: the build runs mechgen (model generation)
# and the test binaries (GoogleTest discovery). halt_on_error: any report fails.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:halt_on_error=1:strict_string_checks=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
start=$(date +%s)
launcher=()  # the compiler cache, as in scripts/build.sh
if command -v ccache >/dev/null; then
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD}
  # -g1: ccache would hash the working directory into every entry (the debug information's
  # compilation directory); not hashing it lets a clone in another folder share the entries,
  # whose line tables then name the first clone's folder (reports keep the file and line).
  export CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-true}
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-Og -g1 -DNDEBUG" \
  -DMECHGEN_BUILD_BENCHMARKS=OFF -DMECHGEN_BUILD_SWEEPS=OFF -DMECHGEN_ALL_MODEL_TOOLS=OFF -DMECHGEN_UNIT_TESTS=ON \
  -DMECHGEN_TEST_OPTIMIZATION=-Og \
  -DCMAKE_CXX_FLAGS="$sanitize" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build "$build" --parallel 2 -- --quiet
echo "sanitize: build took $(( $(date +%s) - start )) s"
ctest --test-dir "$build" --output-on-failure --parallel 2 \
  -E '^(GeneratedFiles\.SameBytesOnEveryRun|Report\.SameBytesFromSeparateProcesses|synthesis\.command|study\.command|statics_speed_command)$' "$@"
echo "sanitize: build and tests took $(( $(date +%s) - start )) s"
