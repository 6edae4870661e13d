#!/usr/bin/env bash
# engine_single_engine: each subcommand writes its CSVs and summary; usage errors exit 2 and
# a failed computation exits 1, neither leaving an output file.
set -euo pipefail
tool=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$tool" cycle --rpm 3000 --samples 720 --csv "$tmp/cycle.csv" > "$tmp/cycle.txt"
awk '!/^#/ { print; exit }' "$tmp/cycle.csv" | grep -q '^theta_deg,T_gas,T_inertia,T_total,p_1,thrust_1,F_O_x,F_O_y,pin_1_x' || fail "cycle header"
[ "$(grep -vc '^#' "$tmp/cycle.csv")" -eq 721 ] || fail "cycle rows"
grep -q 'mean torque' "$tmp/cycle.txt" || fail "cycle summary"
# the shaking force and moment, then the rocking couple about the cylinders' middle (couples.h)
awk '!/^#/ { print; exit }' "$tmp/cycle.csv" | grep -q ',shake_F_x,shake_F_y,shake_M,M_rock_x,M_rock_y$' || fail "cycle header: shaking, rocking couple"
grep -q 'rocking couple about the cylinders.* primary .* secondary ' "$tmp/cycle.txt" || fail "cycle summary: rocking couple"

"$tool" flywheel --rpm 2000 --cs 0.05 --loop "$tmp/loop.csv" --sweep "$tmp/sweep.csv" \
  --wittenbauer "$tmp/witt.csv" > "$tmp/fly.txt"
for f in loop sweep witt; do [ -s "$tmp/$f.csv" ] || fail "flywheel $f.csv"; done
grep -q 'simulated steady cycle' "$tmp/fly.txt" || fail "flywheel summary"
# Issue 45: the smallest C_s accepted (1e-6) and the slowest speed (1e-3 rpm) give finite figures.
"$tool" flywheel --rpm 2000 --cs 1e-6 --loop "$tmp/loop.csv" --sweep "$tmp/sweep.csv" \
  --wittenbauer "$tmp/witt.csv" > "$tmp/fly_small.txt" || fail "flywheel --cs 1e-6 exited $?"
grep -qi 'inf\|nan' "$tmp/fly_small.txt" && fail "flywheel --cs 1e-6: a non-finite figure: $(cat "$tmp/fly_small.txt")"
"$tool" cycle --rpm 1e-3 --csv "$tmp/slow.csv" > "$tmp/slow.txt" || fail "cycle --rpm 1e-3 exited $?"
grep -qi 'inf\|nan' "$tmp/slow.txt" && fail "cycle --rpm 1e-3: a non-finite figure: $(cat "$tmp/slow.txt")"

"$tool" runup --rpm 2000 --idle-rpm 1500 --steady-tol 1e-4 --csv "$tmp/runup.csv" > "$tmp/runup.txt"
grep -q '^  steady at' "$tmp/runup.txt" || fail "runup did not reach a steady state"

# usage errors: exit 2, nothing written
for args in "bogus" "cycle --rpm -1" "cycle --nosuch 1" "flywheel --cs 2" "cycle --samples 3" \
            "cycle --rpm inf" "cycle --rpm=nan" "cycle --samples 2e9" "runup --dt 1e-300" \
            "runup --t-end=1e300" \
            "flywheel --cs 1e-300" "flywheel --cs 5e-7" "flywheel --rpm 1e-300" "cycle --rpm 1e-300" \
            "runup --idle-rpm 1e-300"; do
  set +e
  # shellcheck disable=SC2086
  "$tool" $args --csv "$tmp/bad.csv" > /dev/null 2> "$tmp/err.txt"
  rc=$?
  set -e
  [ "$rc" -eq 2 ] || fail "'$args' exited $rc, expected 2"
  [ ! -e "$tmp/bad.csv" ] || fail "'$args' left $tmp/bad.csv"
  grep -q "^$(basename "$tool"): error: " "$tmp/err.txt" || fail "'$args': no message"
  [ "$(wc -l < "$tmp/err.txt")" -eq 1 ] || fail "'$args': not one line on stderr"
done
# a bad pressure table: exit 2, nothing written
printf 'angle_deg,p\n0,1e5\n0,2e5\n' > "$tmp/table.csv"
set +e
"$tool" cycle --table "$tmp/table.csv" --csv "$tmp/bad.csv" > /dev/null 2>&1
rc=$?
set -e
[ "$rc" -eq 2 ] && [ ! -e "$tmp/bad.csv" ] || fail "bad table: exit $rc"
# a computation that fails (the load cannot be met: a motored engine): exit 1, nothing written
set +e
"$tool" runup --heat 0 --csv "$tmp/bad.csv" > /dev/null 2> "$tmp/err.txt"
rc=$?
set -e
[ "$rc" -eq 1 ] && [ ! -e "$tmp/bad.csv" ] || fail "motored runup: exit $rc"
# a run-up whose CSV step cannot advance the time (t + dt == t): refused (exit 1 or 2, nothing
# written), never a loop without end
set +e
timeout 120 "$tool" runup --dt 1e-300 --csv "$tmp/bad.csv" > /dev/null 2> "$tmp/err.txt"
rc=$?
set -e
{ [ "$rc" -eq 1 ] || [ "$rc" -eq 2 ]; } && [ ! -e "$tmp/bad.csv" ] || fail "runup --dt 1e-300: exit $rc"
# a table: a constant 1 bar over the expansion stroke only
printf 'angle_deg,p\n0,1e5\n179.9,1e5\n180,0\n719.9,0\n' > "$tmp/table.csv"
"$tool" cycle --table "$tmp/table.csv" --csv "$tmp/t.csv" > /dev/null || fail "table cycle"
echo "engine tool: ok"
