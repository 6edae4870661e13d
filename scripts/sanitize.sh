#!/usr/bin/env bash
# Second stage of the test command: the generator and the runtime's view instantiation built
# with AddressSanitizer and UndefinedBehaviorSanitizer in ./build-asan (MECHGEN_ASAN_BUILD
# overrides), and the tests labelled `sanitizer` run there (`ctest -L sanitizer`). Called by
# scripts/test.sh (and so by .ci/run) after the Release suite, which runs every other test
# (`ctest -LE sanitizer`) and builds none of the GoogleTest programs whose tests all run here
# (mechgen_sanitizer_tests(), tests/CMakeLists.txt).
# What this stage runs (mechgen_sanitized() in the tests' CMake files; MECHGEN_SANITIZER_STAGE=ON
# builds only what they need, the top-level CMakeLists.txt):
#   - the generator: its own GoogleTest programs (tests/generator: the symbolic pipeline, the
#     model front end, every shipped model through the command line, hostile and fuzzed models,
#     the report) and the hostile-model replays (fuzz_regressions, degenerate_models); the
#     build itself runs the sanitized generator on the models those programs use;
#   - the runtime, as `mechgen` runs it (compiled once, for the model view: mechgen_runtime_view,
#     mechgen_view): model_test (the view of every shipped model against its fixed-size
#     functions, the view's solver, statics and dynamics against the fixed-size runtime's) and
#     view_commands (sweep, statics, simulate with and without --design, engine, flywheel, study,
#     synthesize through the view);
#   - design.every_shipped_model, csv_column_names, sweep_command_errors (the generator's
#     command line).
# The other GoogleTest programs (the fixed-size instantiations of the same runtime source, one
# per test program) are built and run in the Release stage only, at -O1: building all of them
# here with the sanitizers was 2,759 of this stage's 4,515 s of compile jobs in the cold CI of
# stop 56 (their Release build: 1,319 s), and CI's 45 minutes (issue 43) left no room for both.
# Two tests that repeat identical generator runs to compare their bytes stay in the Release suite
# (GeneratedFiles.SameBytesOnEveryRun, Report.SameBytesFromSeparateProcesses): repeating the same
# runs adds no sanitizer coverage. Their programs (generator_cli_test, report_test) are labelled
# slow in the Release build and sanitizer here: they run in both stages, those two tests in the
# Release stage only. Extra ctest arguments are passed on (e.g. -R generator).
# Optimization: -Og with line tables (-g1) for everything: the generator, the runtime's view
# library, the model libraries and the test programs (MECHGEN_TEST_OPTIMIZATION in the
# top-level CMakeLists.txt). The sanitizers instrument at every level (their manuals advise
# -O1 for speed of the run, not for the checks); -Og takes a quarter to a half less compile time than -O1
# (runtime/view/dynamics.cc under ASan+UBSan: 140 s of user time against 185-268 s; the Jet
# typed test: 87 s against 154 s). At RelWithDebInfo's -O2 -g this stage's build took about
# three times as long; the reports keep file and line.
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
  -DMECHGEN_SANITIZER_STAGE=ON \
  -DMECHGEN_TEST_OPTIMIZATION=-Og \
  -DCMAKE_CXX_FLAGS="$sanitize" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build "$build" --parallel 2 -- --quiet
echo "sanitize: build took $(( $(date +%s) - start )) s"
ctest --test-dir "$build" --output-on-failure --parallel 2 -L sanitizer \
  -E '^(GeneratedFiles\.SameBytesOnEveryRun|Report\.SameBytesFromSeparateProcesses)$' "$@"
echo "sanitize: build and tests took $(( $(date +%s) - start )) s"
