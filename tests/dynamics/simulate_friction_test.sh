#!/bin/sh
# The <model>_simulate command with Coulomb friction (issue 26; runtime/tools/simulate_main.cc,
# mechgen/dynamics/friction.h) on the test block on an incline (30 deg, mu from --set):
#  - mu = 0.7 > tan 30 deg: from rest it stays, every row stuck = 1, s_slide unchanged, and the
#    friction force is m g sin(alpha) up the slope (+u) = 9.81 N, to 1e-9;
#  - the same with --friction off: it slides down at g sin(alpha), s = -g sin(alpha) t^2 / 2,
#    and the CSV has no friction columns;
#  - mu = 0.3, launched up at 3 m/s: the stop's row at t1 = v0 / (g (sin + mu cos)), friction
#    -mu m g cos(alpha) before it and +mu m g cos(alpha) after (sliding back), stuck = 0 always;
#  - the header names friction_slide [N] and stuck, the summary lists the stuck intervals;
#  - driven up the slope at 1 m/s: lambda_s_slide = m g (sin + mu cos), friction_slide =
#    -mu m g cos(alpha), to 1e-9 (its column after rcond);
#  - --friction maybe: exit 2, one line, no CSV.
# Given mechgen_view and the model's shared object (issue 43), the same runs through the runtime
# compiled once (`mechgen_view simulate`, M = ViewModel): the stick and slip above and more (from
# rest stuck, launched up and sliding back, launched up and stuck at the stop, both integrators,
# the default sampling, --friction off and on, a push that breaks it away), the driven block
# (--drive: up the slope with its Coulomb friction in lambda, a rest-to-rest move with Dop853,
# --friction off), a failed run (too few steps: exit 1) and usage errors (exit 2) give the
# tool's CSV, standard output, standard
# error and exit status byte for byte (each run in a directory of its own; mechgen_view --name:
# the tool's name).
# Usage: simulate_friction_test.sh <incline_friction_simulate> <out dir> [<mechgen_view> <object>]
set -u
sim=$1
out=$2
rm -rf "$out" && mkdir -p "$out" || exit 1
fail() { echo "FAIL: $*"; exit 1; }

"$sim" --t-end 2 --dt 0.01 --set mu=0.7 --q0 0.25 --csv "$out/stay.csv" > "$out/stay.txt" 2>&1 \
  || fail "stuck run exited $? ($(cat "$out/stay.txt"))"
header=$(awk '!/^#/ { print; exit }' "$out/stay.csv")
echo "$header" | grep -q '^t,s_slide,s_slide_dot,s_slide_ddot,T,V,E,W_nc,Q_s_slide,friction_slide,stuck,' \
  || fail "unexpected CSV header: $header"
grep -q '^# *friction_slide *\[N\]' "$out/stay.csv" || grep -q 'friction_slide.*\[N\]' "$out/stay.csv" \
  || fail "no unit for friction_slide in the header comments"
grep -q "stuck by static friction: \[0 s, end)" "$out/stay.txt" || fail "no stuck interval listed: $(cat "$out/stay.txt")"
awk -F, '/^#/ { next } ++line == 1 { next }
         { if ($2 != 0.25 || $3 != 0 || $11 != 1) { print "moved at t = " $1; exit 1 }
           d = $10 - 9.81; if (d < 0) d = -d; if (d > 1e-9) { print "friction " $10 " at t = " $1; exit 1 } }
         END { if (line != 202) { print line - 1 " rows"; exit 1 } }' "$out/stay.csv" || fail "the block did not stay"

"$sim" --t-end 2 --dt 0.01 --set mu=0.7 --friction off --csv "$out/off.csv" --quiet || fail "--friction off run"
header=$(awk '!/^#/ { print; exit }' "$out/off.csv")
echo "$header" | grep -q '^t,s_slide,s_slide_dot,s_slide_ddot,T,V,E,W_nc,Q_s_slide,N_slide,' \
  || fail "--friction off: unexpected CSV header: $header"
awk -F, '/^#/ { next } ++line == 1 { next }
         { s = -0.5 * 9.81 * 0.5 * $1 * $1; d = $2 - s; if (d < 0) d = -d; if (d > 1e-6) {
             print "t = " $1 ": s = " $2 " expected " s; exit 1 } }' "$out/off.csv" \
  || fail "--friction off is not the frictionless slide"

"$sim" --t-end 2 --dt 0.01 --set mu=0.3 --qd0 3 --rtol 1e-10 --atol 1e-12 --csv "$out/up.csv" > "$out/up.txt" 2>&1 \
  || fail "launched run exited $? ($(cat "$out/up.txt"))"
grep -q "stuck by static friction: never" "$out/up.txt" || fail "a stuck interval: $(cat "$out/up.txt")"
awk -F, 'BEGIN { a = 9.81 * (0.5 + 0.3 * sqrt(0.75)); t1 = 3 / a; fn = 0.3 * 2 * 9.81 * sqrt(0.75) }
         /^#/ { next } ++line == 1 { next }
         { d = $1 - t1; if (d < 0) d = -d; if (d < 1e-9) found = 1
           if ($11 != 0) { print "stuck at " $1; exit 1 }
           want = ($1 < t1 - 1e-9) ? -fn : (($1 > t1 + 1e-9) ? fn : $10)
           e = $10 - want; if (e < 0) e = -e; if (e > 1e-9) { print "friction " $10 " at t = " $1 ", expected " want; exit 1 } }
         END { if (!found) { print "no row at the stop t1 = " t1; exit 1 } }' "$out/up.csv" \
  || fail "the launched block's friction or stop"

# Driven up the slope at 1 m/s: lambda = m g (sin alpha + mu cos alpha), the friction force
# -mu m g cos(alpha) (down the slope) in its column; the balance constant.
"$sim" --t-end 1 --dt 0.01 --set mu=0.3 --drive s_slide=speed:1 --csv "$out/driven.csv" > "$out/driven.txt" 2>&1 \
  || fail "driven run exited $? ($(cat "$out/driven.txt"))"
grep -q "Coulomb friction in the actuator forces" "$out/driven.txt" || fail "driven summary: $(cat "$out/driven.txt")"
header=$(awk '!/^#/ { print; exit }' "$out/driven.csv")
echo "$header" | grep -q ',lambda_s_slide,balance,rcond,friction_slide,' || fail "driven header: $header"
awk -F, 'BEGIN { l = 2 * 9.81 * (0.5 + 0.3 * sqrt(0.75)); fn = -0.3 * 2 * 9.81 * sqrt(0.75) }
         /^#/ { next } ++line == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
         { e = $c["lambda_s_slide"] - l; if (e < 0) e = -e; if (e > 1e-9) { print "lambda " $c["lambda_s_slide"] " at t = " $1 ", expected " l; exit 1 }
           e = $c["friction_slide"] - fn; if (e < 0) e = -e; if (e > 1e-9) { print "friction " $c["friction_slide"] " at t = " $1; exit 1 } }
         END { if (line != 102) { print line - 1 " rows"; exit 1 } }' "$out/driven.csv" || fail "the driven block's actuator force"

name=$(basename "$sim")
for args in "--friction maybe"; do
  rm -f "$out/usage.csv"
  # shellcheck disable=SC2086
  "$sim" $args --t-end 1 --csv "$out/usage.csv" > /dev/null 2> "$out/usage.err"
  status=$?
  [ "$status" -eq 2 ] || fail "'$args': exit status $status, expected 2"
  [ "$(wc -l < "$out/usage.err")" -eq 1 ] || fail "'$args': not one line on stderr: $(cat "$out/usage.err")"
  grep -q "^$name: error: .*friction" "$out/usage.err" || fail "'$args': message $(cat "$out/usage.err")"
  [ ! -e "$out/usage.csv" ] || fail "'$args': wrote a CSV"
done

if [ $# -ge 4 ]; then
  sim=$(realpath "$sim") view=$(realpath "$3") object=$(realpath "$4")
  # same <case> <expected status> <args...>: the tool and the view in directories of their own.
  same() {
    c=$1 expected=$2
    shift 2
    mkdir -p "$out/view_$c/fixed" "$out/view_$c/view" || exit 1
    (cd "$out/view_$c/fixed" && "$sim" "$@" > ../fixed.out 2> ../fixed.err)
    fixed_status=$?
    (cd "$out/view_$c/view" && "$view" --name "$name" simulate "$object" "$@" > ../view.out 2> ../view.err)
    view_status=$?
    [ "$fixed_status" -eq "$expected" ] || fail "view $c: the tool exited $fixed_status: $(head -3 "$out/view_$c/fixed.err")"
    [ "$view_status" -eq "$fixed_status" ] ||
      fail "view $c: mechgen_view exited $view_status, the tool $fixed_status: $(head -3 "$out/view_$c/view.err")"
    diff -r "$out/view_$c/fixed" "$out/view_$c/view" > /dev/null ||
      fail "view $c: the files differ: $(diff -r "$out/view_$c/fixed" "$out/view_$c/view" | head -4)"
    cmp -s "$out/view_$c/fixed.out" "$out/view_$c/view.out" ||
      fail "view $c: stdout differs: $(diff "$out/view_$c/fixed.out" "$out/view_$c/view.out" | head -6)"
    cmp -s "$out/view_$c/fixed.err" "$out/view_$c/view.err" ||
      fail "view $c: stderr differs: $(diff "$out/view_$c/fixed.err" "$out/view_$c/view.err" | head -4)"
  }
  same stay 0 --t-end 2 --dt 0.01 --set mu=0.7 --q0 0.25 --csv out.csv
  grep -q "stuck by static friction: \[0 s, end)" "$out/view_stay/view.out" || fail "view stay: $(cat "$out/view_stay/view.out")"
  same up 0 --t-end 2 --dt 0.01 --set mu=0.3 --qd0 3 --rtol 1e-10 --atol 1e-12 --csv out.csv
  grep -q "stick-slip transitions" "$out/view_up/view.out" || fail "view up: $(cat "$out/view_up/view.out")"
  same up_stuck 0 --t-end 1.5 --dt 0.005 --set mu=0.7 --qd0 3 --method dop853 --csv out.csv
  grep -q "stuck by static friction: \[[0-9.e-]* s, end)" "$out/view_up_stuck/view.out" ||
    fail "view up_stuck: not stuck at the stop: $(cat "$out/view_up_stuck/view.out")"
  same steps 0 --t-end 1 --set mu=0.3 --qd0 -2 --friction on --csv out.csv
  # a push along the slope F0 sin(w t) breaks the stuck block away and lets it stick again
  same push 0 --t-end 6 --dt 0.01 --set mu=0.7 --set F0=25 --csv out.csv
  grep -q "stuck by static friction: \[0 s, [0-9.e-]* s) \[" "$out/view_push/view.out" ||
    fail "view push: no breakaway and second stick: $(cat "$out/view_push/view.out")"
  same off 0 --t-end 1 --dt 0.01 --set mu=0.7 --friction off --csv out.csv
  same failed 1 --t-end 2 --dt 0.01 --set mu=0.3 --qd0 3 --max-steps 5 --csv out.csv
  grep -q "the simulation failed" "$out/view_failed/view.err" || fail "view failed: $(cat "$out/view_failed/view.err")"
  same usage 2 --friction maybe --t-end 1 --csv out.csv
  same driven 0 --t-end 1 --dt 0.01 --set mu=0.3 --drive s_slide=speed:1 --csv out.csv
  grep -q "Coulomb friction in the actuator forces" "$out/view_driven/view.out" ||
    fail "view driven: no friction in lambda: $(cat "$out/view_driven/view.out")"
  same driven_move 0 --t-end 0.8 --set mu=0.5 --drive s_slide=move:0.4:0.1:0.6 --method dop853 --csv out.csv
  same driven_off 0 --t-end 0.5 --dt 0.05 --set mu=0.5 --drive s_slide=cycloidal:-0.2:0:0.4 --friction off \
    --csv out.csv
  same driven_failed 1 --t-end 1 --dt 0.01 --set mu=0.3 --drive s_slide=speed:1 --max-steps 3 --csv out.csv
  same driven_usage 2 --drive s_slide=speed:1 --drive s_slide=speed:2 --csv out.csv
  same driven_name 2 --drive s=speed:1 --csv out.csv
fi
echo "simulate friction test passed"
