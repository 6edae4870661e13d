#!/usr/bin/env bash
# Installs what is missing, configures ./build (Release, Ninja) and builds the given
# targets (all when none). Used by the README's two commands. MECHGEN_BUILD_BENCHMARKS=OFF
# leaves the benchmark programs out (scripts/test.sh: no test runs them; each bench/*/run.sh
# configures them back in); MECHGEN_ALL_MODEL_TOOLS=OFF builds only the shipped models' tools
# that a test runs (scripts/test.sh; see the top-level CMakeLists.txt); MECHGEN_UNIT_TESTS=OFF
# leaves the GoogleTest programs out (a quicker build; the top-level CMakeLists.txt);
# MECHGEN_SANITIZER_STAGE_FOLLOWS=ON those whose tests the sanitizer stage runs (scripts/test.sh,
# when that stage follows). MECHGEN_DEPS=main
# installs only the main job's packages (scripts/deps.sh), MECHGEN_BUILD_TESTS=OFF configures
# without the test suite (scripts/quickstart.sh: it needs neither GoogleTest nor the tests').
#   bash scripts/build.sh [target ...]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh "${MECHGEN_DEPS:-all}"
# The compiler cache, where there is one (scripts/deps.sh all installs it): a rebuild after a
# small change, or a second clone, compiles only what changed. CCACHE_BASEDIR makes the paths in
# the commands relative, so clones in other folders share the entries. A cold build gains
# nothing from it and loses little (ccache's own hashing, about 1 %).
launcher=()
if command -v ccache >/dev/null; then
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD}
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" \
  -DMECHGEN_BUILD_TESTS="${MECHGEN_BUILD_TESTS:-ON}" \
  -DMECHGEN_BUILD_BENCHMARKS="${MECHGEN_BUILD_BENCHMARKS:-ON}" \
  -DMECHGEN_ALL_MODEL_TOOLS="${MECHGEN_ALL_MODEL_TOOLS:-ON}" \
  -DMECHGEN_UNIT_TESTS="${MECHGEN_UNIT_TESTS:-ON}" \
  -DMECHGEN_SANITIZER_STAGE_FOLLOWS="${MECHGEN_SANITIZER_STAGE_FOLLOWS:-OFF}" >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
echo "mechgen: building ${*:-everything} in ./build (first time: several minutes on 2 cores)"
cmake --build build --parallel 2 "${targets[@]}" -- --quiet
