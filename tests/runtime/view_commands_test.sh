#!/usr/bin/env bash
# Every analysis of `mechgen` through the model view (issue 43: the runtime compiled once,
# mechgen_view, the model's generated code compiled into the private cache) on shipped models:
# sweep, statics with dead zones, forward dynamics, the trajectory sensitivities (--design),
# the engine cycle, the flywheel with its simulated check, a design study on two threads, and a
# path synthesis whose model file the generator takes back. Each run exits 0 through
# mechgen_view (its --verbose line), writes the rows its options ask for, and no number in its
# CSV is NaN. The Release build checks these commands' bytes against the per-model
# programs (sweep_view_tool, statics_view_tool, simulate_view_tool, tool_commands,
# flywheel_command, study.command, synthesis.command); this test is what the sanitizer stage
# (scripts/sanitize.sh) runs of them: the runtime's view instantiation and the generator under
# ASan and UBSan, with no per-model program compiled.
# usage: view_commands_test.sh <mechgen> <source dir>
set -uo pipefail
mechgen=$(realpath "$1") source_dir=$(realpath "$2")
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
cd "$root" || exit 1
export MECHGEN_CACHE_DIR=$root/cache
failures=0
compiled=0  # commands whose --verbose showed the model's object compiled (checked at the end)
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
models=$source_dir/models

# run NAME ROWS CSV -- mechgen arguments: exit 0 through mechgen_view, ROWS data rows in CSV (the
# header line excluded, comment lines too), no field NaN (an infinite mechanical advantage at a
# toggle is written inf: a value, not a failure).
run() {
  local name=$1 rows=$2 csv=$3
  shift 4
  "$mechgen" "$@" > "$name.out" 2> "$name.err"
  local status=$?
  if [ "$status" -ne 0 ]; then fail "$name: exit status $status: $(tail -3 "$name.err")"; return; fi
  grep -q "mechgen_view --name" "$name.err" || fail "$name: not through the model view: $(tail -3 "$name.err")"
  # The model's object (its compiles on the model's first command, under the cache's view/): one
  # optimization level each, -O3 (kViewOptimization, generator/driver/tool_command.cc; README).
  local levels
  levels=$(grep -E '^mechgen: .* -c [^ ]*/view/' "$name.err" |
           awk '{ n = 0; o = ""; for (i = 1; i <= NF; ++i) if ($i ~ /^-O/) { ++n; o = $i } print n " " o }' | sort -u)
  [ -z "$levels" ] || compiled=$((compiled + 1))
  [ -z "$levels" ] || [ "$levels" = "1 -O3" ] || fail "$name: the model's object compiled with $levels (want one -O3)"
  local got
  got=$(grep -v '^#' "$csv" | tail -n +2 | wc -l)
  [ "$got" -eq "$rows" ] || fail "$name: $got rows in $csv, expected $rows"
  if grep -v '^#' "$csv" | tail -n +2 | grep -qiE '(^|,)[-+]?nan(,|$)'; then
    fail "$name: a NaN in $csv: $(grep -v '^#' "$csv" | grep -iE '(^|,)[-+]?nan(,|$)' | head -1)"
  fi
  echo "ok $name"
}

run sweep 37 sweep.csv -- sweep --verbose "$models/fourbar.yaml" --steps 36 --csv sweep.csv
run statics 73 statics.csv -- statics --verbose "$models/slider_crank_friction.yaml" --steps 72 --dead-zones \
  --csv statics.csv
run simulate 201 simulate.csv -- simulate --verbose "$models/slider_crank_motor.yaml" --t-end 0.2 \
  --csv simulate.csv
run design 201 design.csv -- simulate --verbose "$source_dir/tests/design/models/design_fourbar_massive.yaml" \
  --design --t-end 0.2 --csv design.csv
run engine 1440 engine.csv -- engine --verbose "$models/engine_single.yaml" cycle --csv engine.csv
run flywheel 3600 flywheel.csv -- flywheel --verbose "$source_dir/tests/flywheel/models/punch_press.yaml" \
  --rpm 300 --cs 0.02 --samples 3600 --csv flywheel.csv

cat > study.yaml << 'EOF'
method: monte_carlo
count: 64
seed: 7
analysis: positions
at: [0, 60deg, 120deg]
parameters:
  a: {tolerance: 0.01}
  b: {tolerance: 0.01}
metrics:
  - {kind: at, column: coupler.P.x, step: 1}
  - {kind: path_deviation, point: coupler.P}
EOF
run study 64 study.csv -- study --verbose "$models/fourbar.yaml" --study study.yaml --threads 2 --csv study.csv

"$mechgen" synthesize --verbose "$models/fourbar.yaml" --task "$source_dir/tests/synthesis/tasks/fourbar_refind.yaml" \
  --evaluations 2000 --threads 2 --out synthesis > synthesis.out 2> synthesis.err
status=$?
if [ "$status" -ne 0 ]; then fail "synthesize: exit status $status: $(tail -3 synthesis.err)"
else
  grep -q "mechgen_view --name" synthesis.err || fail "synthesize: not through the model view"
  # the synthesized model is an ordinary model file: the sweep runs on it (through the view)
  run synthesized 13 synthesized.csv -- sweep --verbose synthesis/fourbar.yaml --steps 12 --csv synthesized.csv
fi

[ "$compiled" -gt 0 ] || fail "no command showed the model's object compiled (--verbose's compile lines not found)"
[ "$failures" -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
echo "all view commands passed"
