#!/bin/sh
# The <model>_simulate command (runtime/tools/simulate_main.cc) on the handwritten massive
# four-bar: a conservative run writes a CSV whose energy E - W_nc stays at its first value, the
# exit status is 0; a run that fails (here: out of integrator steps) exits 1 with the reason
# on stderr; a usage error exits 2. The plot script runs when gnuplot is installed.
# Usage: simulate_tool_test.sh <simulate executable> <plot_dynamics.gnuplot> <out dir>
set -u
sim=$1
plot=$2
out=$3
rm -rf "$out" && mkdir -p "$out" || exit 1
fail() { echo "FAIL: $*"; exit 1; }

"$sim" --t-end 3 --dt 0.01 --rtol 1e-10 --atol 1e-12 --no-steady --csv "$out/fb.csv" > "$out/fb.txt" 2>&1 \
  || fail "conservative run exited $? ($(cat "$out/fb.txt"))"
awk '!/^#/ { print; exit }' "$out/fb.csv" | grep -q '^t,theta_crank,theta_crank_dot,theta_crank_ddot,T,V,E,W_nc,Q_theta_crank,F_A_x' \
  || fail "unexpected CSV header: $(awk '!/^#/ { print; exit }' "$out/fb.csv")"
rows=$(($(grep -vc '^#' "$out/fb.csv") - 1))
[ "$rows" -eq 301 ] || fail "expected 301 rows, got $rows"
# E - W_nc (columns 7, 8) within 1e-6 J of its first value; the crank moves by > 0.5 rad.
awk -F, '/^#/ { next } ++line == 2 { e0 = $7 - $8; q0 = $2 } line > 1 { d = $7 - $8 - e0; if (d < 0) d = -d;
         if (d > m) m = d; dq = $2 - q0; if (dq < 0) dq = -dq; if (dq > mq) mq = dq }
         END { if (m > 1e-6 || mq < 0.5) { print "energy drift " m ", motion " mq; exit 1 } }' \
  "$out/fb.csv" || fail "energy not kept"
grep -q "success" "$out/fb.txt" || fail "no success in the summary: $(cat "$out/fb.txt")"

# Dop853 and the energy projection run too.
"$sim" --t-end 1 --method dop853 --energy-projection --csv "$out/fb853.csv" --quiet \
  || fail "dop853 run exited $?"

# A failure: the integrator's step budget runs out (exit 1, the reason on stderr).
"$sim" --t-end 100 --max-steps 20 --csv "$out/bad.csv" > "$out/bad.txt" 2> "$out/bad.err"
[ $? -eq 1 ] || fail "a failed run did not exit 1"
grep -q "integrator_failed" "$out/bad.err" || fail "no reason on stderr: $(cat "$out/bad.err")"
# Usage errors: exit 2, one line "<tool>: error: ...", no CSV; --opt=value as --opt value.
name=$(basename "$sim")
for args in "--t-end 1 --bogus" "--rtol 1e300" "--rtol=nan" "--q0 1e300" "--dt 1e-300" "--t-end inf" \
            "--max-steps 2e9x" "--atol=-1"; do
  rm -f "$out/usage.csv"
  # shellcheck disable=SC2086
  "$sim" $args --csv "$out/usage.csv" > /dev/null 2> "$out/usage.err"
  status=$?
  [ "$status" -eq 2 ] || fail "'$args': exit status $status, expected 2"
  [ "$(wc -l < "$out/usage.err")" -eq 1 ] || fail "'$args': not one line on stderr: $(cat "$out/usage.err")"
  grep -q "^$name: error: " "$out/usage.err" || fail "'$args': message $(cat "$out/usage.err")"
  [ ! -e "$out/usage.csv" ] || fail "'$args': wrote a CSV"
done
"$sim" --t-end=0.2 --dt=0.01 --q0=0.3 --qd0=-1 --csv="$out/eq.csv" --quiet || fail "--opt=value run"
"$sim" --t-end 0.2 --dt 0.01 --q0 0.3 --qd0 -1 --csv "$out/sp.csv" --quiet || fail "--opt value run"
cmp -s "$out/eq.csv" "$out/sp.csv" || fail "--opt=value and --opt value wrote different CSVs"
# A sample step that cannot advance the time (t + dt == t): refused (exit 1 or 2), never a
# loop without end.
timeout 120 "$sim" --t-end 1 --dt 1e-300 --csv "$out/tiny.csv" > /dev/null 2> "$out/tiny.err"
rc=$?
[ $rc -eq 1 ] || [ $rc -eq 2 ] || fail "--dt 1e-300 exited $rc (124: it did not stop)"
# A usage error.
"$sim" --t-end 1 --bogus > /dev/null 2>&1
[ $? -eq 2 ] || fail "usage error did not exit 2"

if command -v gnuplot > /dev/null 2>&1; then
  gnuplot -e "csv='$out/fb.csv'; png='$out/fb.png'" "$plot" > "$out/plot.txt" 2>&1 \
    || fail "gnuplot failed: $(cat "$out/plot.txt")"
  [ -s "$out/fb.png" ] || fail "no PNG"
fi
echo "ok"
