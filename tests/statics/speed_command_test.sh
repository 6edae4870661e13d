#!/usr/bin/env bash
# `mechgen statics` on a model whose loads read a velocity (tests/statics/models/
# shaper_speed.yaml: a cutting force that is a table of the ram's speed, a damper, viscous
# friction; issue 45), in a temporary directory with a private cache:
#   - every run, the first (which compiles) and the cached ones, says on its output and in its
#     CSV's first comment line which loads read a velocity and that they are taken at rest;
#   - --speed 60rpm: the note says the speed, the cutting force acts (max |drive| grows from
#     what the weights need at rest to the cutting stroke's hundreds of N m, the CSV's peak the
#     printed one), and --speed 6.283185307179585 (rad/s: 60 rpm converted as the flywheel's --rpm,
#     rpm 2 pi / 60, which rounds one ulp below 2 pi) writes the same CSV byte for byte;
#   - --speed with the scans: they are said to be at rest; a bad --speed, and --design with
#     --speed (its derivatives are of the statics at rest): exit 2, one line.
# usage: speed_command_test.sh <mechgen> <source dir>
set -uo pipefail
mechgen=$(realpath "$1") source_dir=$(realpath "$2")
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
cd "$root" || exit 1
export MECHGEN_CACHE_DIR=$root/cache
cp "$source_dir/tests/statics/models/shaper_speed.yaml" shaper_speed.yaml
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { echo "ok $*"; }
# The largest |drive_theta_crank| printed ("  max |drive_theta_crank| = 4.1 N m without ...").
peak() { sed -n 's/^  max |drive_theta_crank| = \([^ ]*\) N m.*/\1/p' "$1"; }

rest_note="note: at rest: the x of load 'cut' (s_stroke_dot), the damper 'ram' and the viscous friction at joint O4 read a velocity and are taken at qd = 0, t = 0"
speed_note="note: at theta_crank_dot = 6.28318531 rad/s: the x of load 'cut' (s_stroke_dot), the damper 'ram' and the viscous friction at joint O4 are taken at these velocities"
for run in first cached; do
  "$mechgen" statics shaper_speed.yaml --csv rest.csv --table 0 > rest.out 2> rest.err
  status=$?
  [ "$status" -eq 0 ] || { fail "$run run at rest: exit status $status: $(cat rest.err)"; continue; }
  if [ "$run" = cached ] && grep -q compiling rest.err; then fail "the second run compiled again"; fi
  grep -qF "$rest_note" rest.out || fail "$run run at rest: no note on stdout: $(head -3 rest.out)"
  head -1 rest.csv | grep -qF "# shaper_speed_statics, model shaper_speed: statics sweep (${rest_note#note: }" ||
    fail "$run run at rest: no note in the CSV's first line: $(head -1 rest.csv)"
done
[ "$failures" -eq 0 ] && ok "every run at rest says what reads a velocity (stdout and CSV)"

before=$failures
"$mechgen" statics shaper_speed.yaml --speed 60rpm --csv speed.csv --table 0 > speed.out 2> speed.err ||
  fail "--speed 60rpm: exit status $?: $(cat speed.err)"
grep -qF "$speed_note" speed.out || fail "--speed 60rpm: no note on stdout: $(head -3 speed.out)"
head -1 speed.csv | grep -qF "statics sweep (${speed_note#note: }" ||
  fail "--speed 60rpm: no note in the CSV's first line: $(head -1 speed.csv)"
at_rest=$(peak rest.out) at_speed=$(peak speed.out)
# The CSV's own peak of drive_theta_crank (the column after the inputs and coordinates).
column=$(grep -v '^#' speed.csv | head -1 | tr ',' '\n' | grep -n '^drive_theta_crank$' | cut -d: -f1)
csv_peak=$(grep -v '^#' speed.csv | tail -n +2 | cut -d, -f"$column" |
           awk '{ v = $1 < 0 ? -$1 : $1; if (v > m) m = v } END { printf "%.6g", m }')
awk -v r="$at_rest" -v s="$at_speed" -v c="$csv_peak" 'BEGIN {
  exit !(r + 0 > 0 && s > 200 && s > 3 * r && (c - s) * (c - s) <= 1e-10 * s * s) }' ||
  fail "max |drive|: at rest $at_rest, at 60 rpm $at_speed (CSV $csv_peak): expected the cutting peak"
"$mechgen" statics shaper_speed.yaml --speed 6.283185307179585 --csv radians.csv --table 0 > radians.out 2>&1 ||
  fail "--speed 6.283185307179585: exit status $?"
cmp -s speed.csv radians.csv || fail "--speed 60rpm and --speed 6.283185307179585 wrote different CSVs"
[ "$failures" -ne "$before" ] ||
  ok "--speed 60rpm: noted, max |drive| $at_rest N m at rest -> $at_speed N m, the same as in rad/s"

before=$failures
"$mechgen" statics shaper_speed.yaml --speed 2 --dead-zones --equilibria --table 0 > scans.out 2>&1 ||
  fail "--speed with the scans: exit status $?"
grep -q "^note: the dead-zone and equilibrium scans are at rest" scans.out ||
  fail "--speed with the scans: not said to be at rest: $(head -4 scans.out)"
for bad in abc 1e6 2e6rpm nan rpm; do
  "$mechgen" statics shaper_speed.yaml --speed "$bad" > bad.out 2> bad.err
  status=$?
  [ "$status" -eq 2 ] || fail "--speed $bad: exit status $status, expected 2"
  [ "$(wc -l < bad.err)" -eq 1 ] && grep -q "error: --speed: bad value" bad.err ||
    fail "--speed $bad: $(cat bad.err)"
done
# The design derivatives are those of the statics at rest: not with a speed the loads read.
"$mechgen" statics shaper_speed.yaml --speed 1 --design > design.out 2> design.err
status=$?
# (--design is not through the model view: mechgen may first say that it compiles the
# per-model program; the error is the one line after its own.)
[ "$status" -eq 2 ] && [ "$(grep -vc '^mechgen: ' design.err)" -eq 1 ] && grep -q "error: --design with --speed" design.err ||
  fail "--speed with --design: exit status $status: $(cat design.err)"
[ "$failures" -ne "$before" ] || ok "the scans at rest, bad speeds and --design with --speed refused"

[ "$failures" -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
echo "all ok"
