#!/usr/bin/env bash
# Fuzzes the model reader, validator, topology and derivation for a bounded time.
#
#   bash fuzz/run.sh [seconds]          # default 60
#
# Builds fuzz/ with clang-14 into build-fuzz/ (MECHGEN_FUZZ_BUILD overrides), seeds the
# corpus with models/*.yaml, fuzz/regressions/* and fuzz/degenerate/*.yaml, then runs
# libFuzzer for the given time. A crash, sanitizer report, timeout (> 20 s per input) or
# memory blow-up (> 2 GiB) is written to build-fuzz/artifacts/; copy it to
# fuzz/regressions/ so that the ctest fuzz_regressions replays it forever.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
build=${MECHGEN_FUZZ_BUILD:-build-fuzz}
CC=clang-14 CXX=clang++-14 cmake -S fuzz -B "$build" -G Ninja >/dev/null
cmake --build "$build"
mkdir -p "$build/corpus" "$build/artifacts"
cp models/*.yaml "$build/corpus/"
cp fuzz/regressions/* fuzz/degenerate/*.yaml "$build/corpus/" 2>/dev/null || true
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0}
status=0
"$build/model_fuzzer" "$build/corpus" -dict=fuzz/yaml.dict -max_total_time="$seconds" \
  -timeout=20 -rss_limit_mb=2048 -max_len=8192 -print_final_stats=1 \
  -artifact_prefix="$build/artifacts/" || status=$?
if compgen -G "$build/artifacts/*" >/dev/null; then
  echo "fuzz: findings in $build/artifacts/:" >&2
  ls -l "$build/artifacts/" >&2
fi
exit $status
