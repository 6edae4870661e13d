#!/usr/bin/env bash
# Fuzzes the generator and the sweep command for a bounded time, one target after another
# on one core (targets.h says what each target runs):
#
#   bash fuzz/run.sh [model_seconds] [expression_seconds] [sweep_seconds]   # default 60 60 60
#
# (0 seconds skips a target; the corpora in build-fuzz/corpus/ grow from run to run.)
# Builds fuzz/ with clang-14 into build-fuzz/ (MECHGEN_FUZZ_BUILD overrides) and keeps one
# corpus per target in build-fuzz/corpus/<target>/ (grown run over run), seeded with
#   model       models/*.yaml, fuzz/regressions/* (files), fuzz/degenerate/*.yaml and the
#               hostile test models (tests/generator/hostile/*.yaml)
#   expression  fuzz/seeds/expression/* (the shipped models' expressions) and the findings
#   sweep       fuzz/seeds/sweep/* (argument lists, one argument per line) and the findings
# with the dictionaries fuzz/yaml.dict, expression.dict, sweep.dict. The model target also
# mutates lines and tokens itself (model_fuzzer.cc). libFuzzer runs in fork mode (one job
# at a time): a timeout (> 60 s per input) or memory blow-up (> 2 GiB) is kept and the
# campaign goes on; a crash or sanitizer report stops it. Each is written to build-fuzz/artifacts/
# <target>/; copy it to fuzz/regressions/ (model) or fuzz/regressions/<target>/ so that the ctests replay it forever.
# Prints each target's executions, coverage (cov: edges, ft: features) and findings, and
# the totals. The campaign of the issue 12 note was
#   nice -n 15 bash fuzz/run.sh 900 1500 300
set -euo pipefail
cd "$(dirname "$0")/.."
times=("${1:-60}" "${2:-60}" "${3:-60}")
targets=(model expression sweep)
build=${MECHGEN_FUZZ_BUILD:-build-fuzz}
build=$(cd "$(dirname "$build")" && pwd)/$(basename "$build")  # absolute: the sweep target changes directory
CC=clang-14 CXX=clang++-14 cmake -S fuzz -B "$build" -G Ninja >/dev/null
cmake --build "$build" -j 1
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0}
mkdir -p "$build/corpus/model" "$build/corpus/expression" "$build/corpus/sweep"
# (cam_flat.yaml and regressions/cam_flat_slow.yaml are left out: they take 25 to 70 s under
# the sanitizers; the corpus gets cams from
# the other cam models and the mutator's cam lines.)
cp $(ls models/*.yaml | grep -v cam_flat.yaml) fuzz/degenerate/*.yaml "$build/corpus/model/"
cp tests/generator/hostile/*.yaml "$build/corpus/model/" 2>/dev/null || true
find fuzz/regressions -maxdepth 1 -type f ! -name "*slow*" -exec cp {} "$build/corpus/model/" \;
cp fuzz/seeds/expression/* "$build/corpus/expression/"
cp fuzz/regressions/expression/* "$build/corpus/expression/" 2>/dev/null || true
cp fuzz/seeds/sweep/* "$build/corpus/sweep/"
cp fuzz/regressions/sweep/* "$build/corpus/sweep/" 2>/dev/null || true
status=0
total=0
summary=""
for i in 0 1 2; do
  t=${targets[$i]}
  [ "${times[$i]}" = 0 ] && continue  # 0 seconds: skip this target
  dict=$PWD/fuzz/yaml.dict
  extra=(-max_len=8192)
  [ "$t" = expression ] && dict=$PWD/fuzz/expression.dict && extra=(-max_len=512 -timeout=10)
  [ "$t" = sweep ] && dict=$PWD/fuzz/sweep.dict && extra=(-max_len=1024 -close_fd_mask=3)
  mkdir -p "$build/artifacts/$t"
  log="$build/fuzz_$t.log"
  rc=0
  "$build/${t}_fuzzer" "$build/corpus/$t" -dict="$dict" -max_total_time="${times[$i]}" \
    -timeout=60 -rss_limit_mb=2048 -print_final_stats=1 -fork=1 -ignore_timeouts=1 -ignore_ooms=1 "${extra[@]}" \
    -artifact_prefix="$build/artifacts/$t/" >"$log" 2>&1 || rc=$?
  if [ $rc -ne 0 ]; then status=$rc; fi
  # (fork mode: the parent's last "#<executions>: cov: ... ft: ... corp: ..." line)
  last=$(grep -E '^#[0-9]+' "$log" | tail -1 || true)
  runs=$(echo "$last" | grep -oE '^#[0-9]+' | tr -d '#' || true)
  cov=$(echo "$last" | grep -o 'cov: [0-9]*' | awk '{print $2}' || true)
  ft=$(echo "$last" | grep -o 'ft: [0-9]*' | awk '{print $2}' || true)
  corpus=$(echo "$last" | grep -oE 'corp: [0-9]+' | awk '{print $2}' || true)
  findings=$(find "$build/artifacts/$t" -type f | wc -l)
  total=$((total + ${runs:-0}))
  line=$(printf '%-10s %6ss  executions %9s  cov %6s  ft %6s  corpus %10s  findings %s  (rc %s)' \
    "$t" "${times[$i]}" "${runs:-?}" "${cov:-?}" "${ft:-?}" "${corpus:-?}" "$findings" "$rc")
  echo "$line"
  summary+="$line"$'\n'
done
echo "total executions $total"
if compgen -G "$build/artifacts/*/*" >/dev/null; then
  echo "fuzz: findings in $build/artifacts/:" >&2
  ls -lR "$build/artifacts/" >&2
fi
exit $status
