#!/bin/bash
# The flywheel command (issue 25): the per-model tool <model>_flywheel and `mechgen flywheel
# MODEL` on a model file outside the source tree, with an empty cache, cached, and --no-cache
# (the same CSV bytes as the per-model tool each time; through the runtime compiled once, and with
# MECHGEN_VIEW=0 the per-model program), --help, a bad option (exit 2, one line), a model without `forces` (one
# line, exit 1, nothing compiled), a machine that cannot be sized (exit 1, the angle said), a
# copy of the tool in an installed layout (its plot script from <prefix>/share/mechgen/tools)
# and a missing plot script (one line, exit 1, nothing written).
# usage: flywheel_command_test.sh <mechgen> <source dir> <punch_press_flywheel>
set -u
mechgen=$1 src=$2 tool=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# The per-model tool: CSV with units in its header, the summary with units.
"$tool" --rpm 300 --cs 0.02 --samples 3600 --csv "$work/tool.csv" > "$work/tool.out" 2>&1 ||
  fail "punch_press_flywheel exited $?: $(cat "$work/tool.out")"
grep -q '^theta,theta_deg,T_req,T_mean,E,' "$work/tool.csv" || fail "CSV header"
grep -q '^# T_req \[N m\]' "$work/tool.csv" || fail "CSV column units"
grep -q '^# punch_press_flywheel, model punch_press: energy loop' "$work/tool.csv" || fail "CSV about line"
[ "$(grep -vc '^#' "$work/tool.csv")" = 3601 ] || fail "CSV rows"
grep -q 'dE = [0-9.]* J' "$work/tool.out" || fail "summary dE"
grep -q 'flywheel I_fly = [0-9.]* kg m^2' "$work/tool.out" || fail "summary I_fly"
grep -q 'simulated C_s = ' "$work/tool.out" || fail "summary simulated C_s"
# Steadiness judged against the C_s asked (issue 45), the tolerance stated.
grep -q '^  steady: the cycle-mean speed changed by .* (tolerance 2e-05 = 0.001 x the expected C_s 0.02); settling time none' \
  "$work/tool.out" || fail "steady line: $(grep 'steady:' "$work/tool.out")"
# The punch's switches located (machine_cycle_test.cc checks their angles): 6, breaks at 0 and 180 deg.
grep -q 'breaks of the loop (deg): 0, .*180, .*; 6 switches of the loads located$' "$work/tool.out" ||
  fail "breaks line: $(grep breaks "$work/tool.out")"
# Energy per stroke: F0 (delta - w/2) = 110 J (fourth order with the switches' breaks: < 1e-6 J
# at 3600 samples, tests/flywheel/machine_cycle_test.cc; 1e-3 J without).
awk '/work per cycle/ { w = $4; exit } END { if (w < 109.999999 || w > 110.000001) exit 1 }' "$work/tool.out" ||
  fail "work per cycle: $(grep 'work per cycle' "$work/tool.out")"
"$tool" --rpm 300 --cs 0.02 --samples 3600 --no-switch-breaks --no-check > "$work/plain.out" 2>&1 ||
  fail "--no-switch-breaks exited $?"
grep -q 'breaks of the loop' "$work/plain.out" && fail "--no-switch-breaks still has breaks"
awk '/work per cycle/ { w = $4; exit } END { if (w < 109.999 || w > 110.001) exit 1 }' "$work/plain.out" ||
  fail "work per cycle without breaks: $(grep 'work per cycle' "$work/plain.out")"

# A bad option: exit 2, one line.
"$tool" --cs 2 > "$work/bad.out" 2> "$work/bad.err"; status=$?
[ $status = 2 ] || fail "--cs 2 exited $status"
[ "$(wc -l < "$work/bad.err")" = 1 ] || fail "--cs 2: not one line: $(cat "$work/bad.err")"
"$tool" --motor diesel 2> "$work/bad.err"; [ $? = 2 ] || fail "--motor diesel"
# A C_s that cannot mean anything (issue 45: 1e-300 printed an infinite flywheel): exit 2, one
# line, nothing on stdout; the steadiness given two ways.
for bad in "--cs 1e-300" "--cs 5e-7" "--cs 0" "--steady-tol 1e-6 --steady-fraction 1e-2" \
           "--check-samples 1000000 --max-cycles 100000" "--motor shunt --slip 1e-300"; do
  # shellcheck disable=SC2086
  "$tool" $bad > "$work/bad.out" 2> "$work/bad.err"; status=$?
  [ $status = 2 ] || fail "$bad exited $status"
  [ "$(wc -l < "$work/bad.err")" = 1 ] || fail "$bad: not one line: $(cat "$work/bad.err")"
  [ -s "$work/bad.out" ] && fail "$bad: wrote to stdout"
done
"$tool" --break 7.5deg --break 8deg --samples 360 --rpm 60 2> "$work/bad.err" > /dev/null; status=$?
[ $status = 2 ] || fail "--break too close exited $status"
grep -q 'closer than 3 sample intervals' "$work/bad.err" || fail "--break message: $(cat "$work/bad.err")"
[ "$(wc -l < "$work/bad.err")" = 1 ] || fail "--break: not one line: $(cat "$work/bad.err")"
# A break between samples is taken (7.25 deg at 360 samples: between 7 and 8 deg).
"$tool" --break 7.25deg --samples 360 --rpm 60 --no-check > "$work/break.out" 2>&1 || fail "--break 7.25deg exited $?"
grep -q 'breaks of the loop (deg): 0, 7.25, ' "$work/break.out" || fail "--break 7.25deg: $(grep breaks "$work/break.out")"
# A machine that cannot be sized: the punch reversed (it drives the ram: no net load).
"$tool" --set F0=-20000 --no-check > /dev/null 2> "$work/noload.err"; status=$?
[ $status = 1 ] || fail "F0 < 0 exited $status"
grep -q 'mean required torque is negative' "$work/noload.err" || fail "no-load message"

# The plot script as installed (runtime/tools/common/gnuplot.h): a copy of the tool in
# <prefix>/bin runs <prefix>/share/mechgen/tools/plot_energy_loop.gnuplot, not the one of the
# tree it was built from; that copy of the script marks that it ran (a file beside the CSV).
# $MECHGEN_TOOLS_DIR, when set, is the only place looked in: one that lacks the script is one
# line naming it, exit 1, nothing computed or written (the CSV and the picture absent).
if command -v gnuplot > /dev/null; then
  prefix="$work/prefix"
  mkdir -p "$prefix/bin" "$prefix/share/mechgen/tools" "$work/empty"
  cp "$tool" "$prefix/bin/punch_press_flywheel"
  { echo "set print csv.'.installed'; print 'installed'; set print"
    cat "$src/runtime/tools/plot_energy_loop.gnuplot"; } > "$prefix/share/mechgen/tools/plot_energy_loop.gnuplot"
  env -u MECHGEN_TOOLS_DIR "$prefix/bin/punch_press_flywheel" --samples 360 --rpm 60 --no-check \
    --csv "$work/installed.csv" --png "$work/installed.png" > "$work/installed.out" 2>&1 ||
    fail "the installed copy exited $?: $(cat "$work/installed.out")"
  [ -f "$work/installed.csv.installed" ] || fail "the installed copy did not run share/mechgen/tools' script"
  head -c 8 "$work/installed.png" | od -An -c | grep -q "P   N   G" || fail "installed.png is not a PNG"
  grep -q "^wrote $work/installed.png\$" "$work/installed.out" || fail "no 'wrote installed.png' line"
  for runner in "$tool" "$prefix/bin/punch_press_flywheel"; do
    MECHGEN_TOOLS_DIR="$work/empty" "$runner" --samples 360 --rpm 60 --no-check --csv "$work/missing.csv" \
      --png "$work/missing.png" > "$work/missing.out" 2> "$work/missing.err"; status=$?
    [ $status = 1 ] || fail "$runner with no script exited $status"
    [ "$(wc -l < "$work/missing.err")" = 1 ] || fail "no script: not one line: $(cat "$work/missing.err")"
    grep -qxF "error: cannot find plot_energy_loop.gnuplot in \$MECHGEN_TOOLS_DIR = $work/empty (point it at mechgen's runtime/tools or share/mechgen/tools, or unset it)" \
      "$work/missing.err" || fail "no script: $(cat "$work/missing.err")"
    [ ! -e "$work/missing.csv" ] && [ ! -e "$work/missing.png" ] && [ ! -s "$work/missing.out" ] ||
      fail "no script: something was written"
  done
fi

# mechgen flywheel on a copy of the model outside the tree, uncached (compiles) then cached.
mkdir -p "$work/models" "$work/cache"
cp "$src/tests/flywheel/models/punch_press.yaml" "$work/models/press.yaml"
export MECHGEN_CACHE_DIR="$work/cache"
"$mechgen" flywheel "$work/models/press.yaml" --rpm 300 --cs 0.02 --samples 3600 \
  --csv "$work/first.csv" > "$work/first.out" 2> "$work/first.err" ||
  fail "mechgen flywheel (uncached) exited $?: $(cat "$work/first.err")"
cmp -s "$work/tool.csv" "$work/first.csv" || fail "mechgen flywheel's CSV differs from punch_press_flywheel's"
start=$(date +%s.%N)
"$mechgen" flywheel "$work/models/press.yaml" --rpm 300 --cs 0.02 --samples 3600 \
  --csv "$work/second.csv" > "$work/second.out" 2>&1 || fail "mechgen flywheel (cached) exited $?"
end=$(date +%s.%N)
cmp -s "$work/tool.csv" "$work/second.csv" || fail "cached CSV differs"
awk -v a="$start" -v b="$end" 'BEGIN { exit !(b - a < 5) }' || fail "the cached run took $(echo "$end - $start" | bc) s"
# The runs above went through the runtime compiled once (mechgen_view flywheel, issue 43);
# MECHGEN_VIEW=0 keeps the per-model program: the same CSV, and the cached program below.
MECHGEN_VIEW=0 "$mechgen" flywheel "$work/models/press.yaml" --rpm 300 --cs 0.02 --samples 3600 \
  --csv "$work/program.csv" > "$work/program.out" 2> "$work/program.err" ||
  fail "mechgen flywheel (MECHGEN_VIEW=0) exited $?: $(cat "$work/program.err")"
cmp -s "$work/tool.csv" "$work/program.csv" || fail "the per-model program's CSV differs from punch_press_flywheel's"
# The cached program was compiled with the source tree's runtime/tools as its tools directory
# (-DMECHGEN_TOOLS_DIR): a copy of it in the installed layout above still runs the prefix's
# (marked) script, which comes first.
if command -v gnuplot > /dev/null; then
  cached=$(find "$MECHGEN_CACHE_DIR/flywheel" -mindepth 2 -maxdepth 2 -type f -name flywheel | head -n 1)
  [ -n "$cached" ] || fail "no cached flywheel program in $MECHGEN_CACHE_DIR/flywheel"
  cp "$cached" "$prefix/bin/press_flywheel"
  rm -f "$work/installed.csv.installed"
  env -u MECHGEN_TOOLS_DIR "$prefix/bin/press_flywheel" --samples 360 --rpm 60 --no-check \
    --csv "$work/installed.csv" --svg "$work/installed.svg" > "$work/installed.out" 2>&1 ||
    fail "the installed copy of the cached program exited $?: $(cat "$work/installed.out")"
  [ -f "$work/installed.csv.installed" ] ||
    fail "the installed copy of the cached program ran the script of the tree it was built from"
  grep -q '<svg' "$work/installed.svg" || fail "installed.svg is not an SVG"
fi
# --no-cache: built in a temporary directory, run, deleted; the cache untouched.
entries_before=$(find "$MECHGEN_CACHE_DIR/flywheel" -mindepth 1 -maxdepth 1 | wc -l)
"$mechgen" flywheel --no-cache "$work/models/press.yaml" --rpm 300 --cs 0.02 --samples 3600 \
  --csv "$work/nocache.csv" > /dev/null 2> "$work/nocache.err" ||
  fail "mechgen flywheel --no-cache exited $?: $(cat "$work/nocache.err")"
cmp -s "$work/tool.csv" "$work/nocache.csv" || fail "--no-cache CSV differs"
[ "$(find "$MECHGEN_CACHE_DIR/flywheel" -mindepth 1 -maxdepth 1 | wc -l)" = "$entries_before" ] ||
  fail "--no-cache changed the cache"
"$mechgen" flywheel "$work/models/press.yaml" --help > "$work/help.out" || fail "--help exited $?"
grep -q -- '--cs' "$work/help.out" || fail "--help lists --cs"
"$mechgen" flywheel "$work/models/press.yaml" --rpm -3 > /dev/null 2> "$work/bad.err"; status=$?
[ $status = 2 ] || fail "mechgen flywheel --rpm -3 exited $status"
[ "$(wc -l < "$work/bad.err")" = 1 ] || fail "mechgen flywheel --rpm -3: not one line"
"$mechgen" --help | grep -q 'flywheel' || fail "mechgen --help does not list flywheel"

# A model without forces: one line, exit 1, nothing compiled.
cp "$src/models/fourbar.yaml" "$work/models/plain.yaml"
"$mechgen" flywheel "$work/models/plain.yaml" > /dev/null 2> "$work/plain.err"; status=$?
[ $status = 1 ] || fail "a model without forces exited $status"
[ "$(wc -l < "$work/plain.err")" = 1 ] || fail "a model without forces: not one line: $(cat "$work/plain.err")"
grep -q 'forces' "$work/plain.err" || fail "the message does not name forces"
echo "flywheel command: ok"
