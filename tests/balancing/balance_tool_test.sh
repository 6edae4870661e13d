#!/usr/bin/env bash
# mechgen_balance (runtime/tools/balance_main.cc): the balance table, a two-plane rotor
# (the lever-rule hand case of rotor_test.cc), the Khurmi & Gupta flywheel (energy_loop_test.cc)
# from loop areas and a sampled torque; then bad input: exit status 2 (options) or 1 (data), a message naming the
# problem on stderr and nothing on stdout.
# Wittenbauer's design on a machine with a known flywheel. And plot_energy_loop.gnuplot and
# plot_wittenbauer.gnuplot on what it writes (when gnuplot is installed).
# usage: balance_tool_test.sh <mechgen_balance> <plot_energy_loop.gnuplot> <plot_wittenbauer.gnuplot>
set -euo pipefail
tool=$1 plot=$2 wplot=$3
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$tool" table > "$out/table.txt" || fail "table exit status"
cat "$out/table.txt"
grep -Eq '^inline4 +4  0 +4\.000 line +0 +0 *$' "$out/table.txt" || fail "inline4 row"
grep -Eq '^inline6 +6  0 +0 +0 +0 *$' "$out/table.txt" || fail "inline6 row"
grep -Eq '^v8_crossplane +8  0 +0 +3\.162 rotating +0 *$' "$out/table.txt" || fail "v8 row"
grep -Eq '^inline3 +3  0 +0 +1\.732 line +1\.732 line *$' "$out/table.txt" || fail "inline3 row"
"$tool" table --csv > "$out/table.csv" || fail "table --csv"
[ "$(grep -vc '^#' "$out/table.csv")" -eq 14 ] || fail "CSV rows"
head -n 1 "$out/table.csv" | grep -q '^# mechgen_balance table: .*Signs: ' || fail "table CSV: first line"
[ "$(grep -c '^# [a-z_]* \[[^]]*\]: ' "$out/table.csv")" -eq 14 ] || fail "table CSV: unit lines"
# The 90 deg V-twin (hand values): a primary force of constant length 1 turning with the crank,
# a secondary force on a line of amplitude sqrt 2, no moments; every number round-trips, so
# to the last bit.
awk -F, '$1 == "vtwin90" { found = 1
    ok = $2 == 2 && $3 - 1 < 1e-15 && 1 - $3 < 1e-15 && $4 - 1 < 1e-15 && 1 - $4 < 1e-15 &&
         $5 == "rotating" && ($6 - sqrt(2))^2 < 1e-30 && $7 == 0 && $8 == "line" &&
         $9 == 0 && $10 == 0 && $11 == "balanced" && $12 == 0 && $13 == 0 && $14 == "balanced" }
  END { exit !(found && ok) }' "$out/table.csv" || fail "vtwin90 CSV"

printf '# two unbalances\nm,r,angle_deg,z\n2,0.1,0,0.1\n1,0.2,90,0.3\n' > "$out/rotor.csv"
"$tool" rotor --csv "$out/rotor.csv" --radius 0.1 --left 0 --right 0.4 > "$out/rotor.txt" \
  || fail "rotor exit status"
cat "$out/rotor.txt"
grep -q 'left  plane z = 0 m: 1.58114 kg at r = 0.1 m, angle 198.4349 deg' "$out/rotor.txt" \
  || fail "left correction"
grep -q 'right plane z = 0.4 m: 1.58114 kg at r = 0.1 m, angle 251.5651 deg' "$out/rotor.txt" \
  || fail "right correction"
grep -Eq 'residual after the corrections: \|U\| = [0-9.e-]+ kg m, \|M\| = [0-9.e-]+ kg m\^2$' \
  "$out/rotor.txt" || fail "residual line"
residual=$(sed -n 's/.*|U| = \([0-9.e-]*\) kg m.*/\1/p' "$out/rotor.txt")
awk -v r="$residual" 'BEGIN { exit !(r < 1e-15) }' || fail "residual $residual"

"$tool" flywheel --areas "295,-685,40,-340,960,-270" --torque-scale 5 --angle-scale 1 \
  --rpm 1800 --mass 36 --gyration 0.15 > "$out/fly.txt" || fail "flywheel exit status"
cat "$out/fly.txt"
grep -q 'dE = 985 area units x 0.0872665 J per unit = 85.9575 J' "$out/fly.txt" || fail "dE"
grep -q 'flywheel I = 0.81 kg m^2: C_s = dE/(I w^2) = 0.00298673' "$out/fly.txt" || fail "C_s"

# A layout of one's own from a file: the in-line five preset again, with the bank angle column.
printf '# in-line five\n0,0,-2\n216,0,-1\n144,0,0\n72,0,1\n288,0,2\n' > "$out/five.csv"
"$tool" table --csv --engine "$out/five.csv" --layout inline5 > "$out/five.txt" || fail "--engine"
[ "$(grep -v '^#' "$out/five.txt" | sed -n 2p | cut -d, -f2-)" = "$(grep -v '^#' "$out/five.txt" | sed -n 3p | cut -d, -f2-)" ] \
  || fail "--engine differs from the preset"
grep -q '^five,5,0,0,balanced,0,0,balanced,0.449' "$out/five.txt" || fail "five"

# A sampled excess torque 120 sin(theta) N m (T_d - T_l, T_l = 100): dE = 240 J exactly.
awk 'BEGIN { print "angle_deg,T_d,T_l"; for (k = 0; k < 360; k += 2)
  printf "%d,%.15g,100\n", k, 100 + 120 * sin(k * atan2(0, -1) / 180) }' > "$out/torque.csv"
"$tool" flywheel --torque-csv "$out/torque.csv" --rpm 600 --cs 0.01 > "$out/torque.txt" \
  || fail "torque-csv exit status"
cat "$out/torque.txt"
grep -q 'E_max = 240 J at 180.000 deg, E_min = 0 J at 0.000 deg' "$out/torque.txt" || fail "E"
grep -q 'required I = dE/(C_s w^2) = 6.07927 kg m^2' "$out/torque.txt" || fail "I"
"$tool" flywheel --torque-csv "$out/torque.csv" --rpm 600 --cs 0.01 --energy-csv "$out/E.csv" \
  > /dev/null || fail "--energy-csv"
[ "$(awk '!/^#/ { print; exit }' "$out/E.csv")" = "angle_deg,excess_torque,E" ] || fail "E.csv header"
[ "$(grep -vc '^#' "$out/E.csv")" -eq 182 ] || fail "E.csv rows"
# Its comment lines: the tool and the signs, then each column's unit.
head -n 1 "$out/E.csv" | grep -q '^# mechgen_balance flywheel, .*Signs: excess_torque = T_d - T_l' \
  || fail "E.csv: first comment line $(head -n 1 "$out/E.csv")"
[ "$(sed -n 2,4p "$out/E.csv" | cut -d: -f1 | tr '\n' ' ')" = "# angle_deg [deg] # excess_torque [N m] # E [J] " ] \
  || fail "E.csv: unit lines $(sed -n 2,4p "$out/E.csv")"
# A failed write: exit 1, one line, nothing left behind.
rc=0
"$tool" flywheel --torque-csv "$out/torque.csv" --rpm 600 --cs 0.01 --energy-csv /dev/full \
  > /dev/null 2> "$out/full.err" || rc=$?
[ "$rc" -eq 1 ] || fail "--energy-csv /dev/full: exit status $rc, expected 1"
[ "$(wc -l < "$out/full.err")" -eq 1 ] || fail "--energy-csv /dev/full: not one line: $(cat "$out/full.err")"
# E(180°) = 240 J to the fourth-order integration error (about 5e-6 J at 2° steps).
awk -F, '$1 == 180 { found = 1; if ($3 < 240 - 1e-4 || $3 > 240 + 1e-4) exit 1 }
  END { exit !found }' "$out/E.csv" || fail "E(180 deg) = 240 J"

if command -v gnuplot > /dev/null; then
  gnuplot -e "csv='$out/E.csv'; png='$out/E.png'" "$plot" || fail "gnuplot"
  [ -s "$out/E.png" ] || fail "no PNG"
fi

# Wittenbauer (the synthetic machine of energy_loop_test.cc): I_m = 0.2 + 0.05 cos 2t +
# 0.02 sin t, E = 30 sin t + 12 (sin(2t + 0.5) - sin 0.5), flywheel 1.3 kg m^2, T0 = 900 J.
# The speeds of the trace give --rpm (mid-range) and --cs; the design must return 1.3 and 900.
awk 'BEGIN { pi = atan2(0, -1); print "angle_deg,I_m,E"
  for (k = 0; k < 360; ++k) { t = k * pi / 180
    printf "%d,%.17g,%.17g\n", k, 0.2 + 0.05 * cos(2 * t) + 0.02 * sin(t),
      30 * sin(t) + 12 * (sin(2 * t + 0.5) - sin(0.5)) } }' > "$out/machine.csv"
read -r rpm cs < <(awk -F, 'NR > 1 { w = sqrt(2 * (900 + $3) / (1.3 + $2))
  if (NR == 2 || w > hi) hi = w; if (NR == 2 || w < lo) lo = w }
  END { mid = (hi + lo) / 2; printf "%.17g %.17g\n", mid * 30 / atan2(0, -1), (hi - lo) / mid }' \
  "$out/machine.csv")
"$tool" wittenbauer --csv "$out/machine.csv" --design --rpm "$rpm" --cs "$cs" \
  --diagram-csv "$out/diagram.csv" > "$out/wit.txt" || fail "wittenbauer --design"
cat "$out/wit.txt"
grep -q 'flywheel I_f = 1.3 kg m^2, kinetic energy at 0 deg T0 = 900 J' "$out/wit.txt" \
  || fail "Wittenbauer flywheel"
"$tool" wittenbauer --csv "$out/diagram.csv" > "$out/wit2.txt" || fail "wittenbauer"
cat "$out/wit2.txt"
grep -q "C_s = (w_max - w_min)/w_mid = $(printf '%.6g' "$cs")\$" "$out/wit2.txt" || fail "C_s back"
if command -v gnuplot > /dev/null; then
  gnuplot -e "csv='$out/diagram.csv'; png='$out/W.png'" "$wplot" || fail "gnuplot wittenbauer"
  [ -s "$out/W.png" ] || fail "no Wittenbauer PNG"
fi

awk 'BEGIN { for (k = 0; k < 720; k += 2) printf "%d,%.15g\n", k, 30 + 120 * sin(k * atan2(0, -1) / 360)^2 }' \
  > "$out/t720.csv"
# Bad input: one line "mechgen_balance: error: ..." naming the problem, no partial output;
# exit status 2 for a usage error (options), 1 for bad data in a file or a failed computation.
expect_error() {
  local expected=$1 pattern=$2
  shift 2
  set +e
  "$tool" "$@" > "$out/bad.out" 2> "$out/bad.err"
  local status=$?
  set -e
  [ "$status" -eq "$expected" ] || fail "exit status $status (expected $expected) for: $* ($(cat "$out/bad.err"))"
  [ "$(wc -l < "$out/bad.err")" -eq 1 ] || { cat "$out/bad.err"; fail "not one line on stderr for: $*"; }
  grep -q "^mechgen_balance: error: " "$out/bad.err" || { cat "$out/bad.err"; fail "no tool prefix for: $*"; }
  grep -q -- "$pattern" "$out/bad.err" || { cat "$out/bad.err"; fail "message for: $*"; }
  [ ! -s "$out/bad.out" ] || fail "partial output for: $*"
  echo "ok (status $status): $(cat "$out/bad.err")"
}
expect_error 1 "correction planes coincide" rotor --csv "$out/rotor.csv" --radius 0.1 --left 0.2 --right 0.2
expect_error 2 "--radius: bad value '0': expected a number in (0, 1e+06]" rotor --csv "$out/rotor.csv" --radius 0 --left 0 --right 1
printf '2,0.1,0,0.1\n-1,0.2,90,0.3\n' > "$out/negative.csv"
expect_error 1 "negative.csv: unbalance 2: bad unbalance" rotor --csv "$out/negative.csv" --radius 0.1
printf '2,0.1,0,0.1\n1,0.2,abc,0.3\n' > "$out/text.csv"
expect_error 1 "text.csv:2: 'abc' is not a number" rotor --csv "$out/text.csv" --radius 0.1
expect_error 1 "cannot open" rotor --csv "$out/missing.csv" --radius 0.1
expect_error 2 "the loop does not close (sum of the areas = 270" flywheel --areas "295,-685,40,-340,960" --scale 1 --rpm 1800 --cs 0.003
expect_error 2 "give either the flywheel" flywheel --areas "1,-1" --scale 1 --rpm 1800
expect_error 2 "no such layout" table --layout w12
expect_error 2 "needs --cs" wittenbauer --csv "$out/machine.csv" --design --rpm 300
expect_error 2 "energy-csv needs --torque-csv" flywheel --areas "1,-1" --scale 1 --rpm 600 --cs 0.01 --energy-csv "$out/x.csv"
[ ! -e "$out/x.csv" ] || fail "x.csv written on error"
expect_error 1 "mean excess torque is 90 N m" flywheel --torque-csv "$out/t720.csv" --cycle-deg 720 --rpm 600 --cs 0.01
# Usage errors of CLI11 itself: exit 2 (not CLI11's own codes in the hundreds), one line.
expect_error 2 "nosuch" table --nosuch
expect_error 2 "subcommand" frobnicate
expect_error 2 "rpm" flywheel --areas "1,-1" --scale 1 --cs 0.01
# Values that cannot mean anything: nan is not "not given", inf and 1e300 are not numbers
# of a flywheel; --opt=value as --opt value.
expect_error 2 "--inertia: bad value 'inf': expected a number in (0, 1e+12]" flywheel --areas "1,-1" --scale 1 --rpm 600 --inertia inf
expect_error 2 "--cs: bad value 'nan': expected a number in \[1e-06, 2)" flywheel --areas "1,-1" --scale 1 --rpm 600 --cs nan
expect_error 2 "--cs: bad value 'nan'" flywheel --areas "1,-1" --scale 1 --rpm 600 --inertia 2 --cs=nan
expect_error 2 "--rpm: bad value '1e300'" flywheel --areas "1,-1" --scale 1 --rpm=1e300 --cs 0.01
expect_error 2 "--rotating-ratio: bad value '-inf'" table --rotating-ratio=-inf
expect_error 2 "--areas: 'inf' is not a number" flywheel --areas "1,inf,-1" --scale 1 --rpm 600 --cs 0.01
# Finite values whose figures cannot mean anything (issue 45; each printed inf or nan, exit 0):
# overflowing sums, a C_s or a speed so small that the flywheel runs off the numbers, a
# flywheel so small that the speed would reach zero, an inertia that underflows, correction
# masses beyond the numbers. Options: exit 2; with a file: exit 1, the file named.
expect_error 2 "--areas: their running sums are beyond the range of numbers" flywheel --areas 1e308,1e308,-1e308,-1e308 --scale 1 --rpm 60 --cs 0.02
expect_error 2 "dE = 1e+300 area units x 1e+12 J per unit is beyond the range of numbers" flywheel --areas 1e300,-1e300 --scale 1e12 --rpm 60 --cs 0.02
expect_error 2 "--cs: bad value '1e-300': expected a number in \[1e-06, 2)" flywheel --areas 1,-1 --scale 1 --rpm 60 --cs 1e-300
expect_error 2 "--rpm: bad value '1e-300': expected a number in \[0.001, 1e+06\]" flywheel --areas 1,-1 --scale 1 --rpm 1e-300 --cs 0.02
expect_error 2 "--rpm: bad value '1e-300'" wittenbauer --csv "$out/machine.csv" --design --rpm 1e-300 --cs 0.02
expect_error 2 "dE/(I w^2) = 2.53303e+298 >= 2, the speed would fall to zero" flywheel --areas 1,-1 --scale 1 --rpm 60 --inertia 1e-300
expect_error 2 "dE/(I w^2) = 2.53303 >= 2" flywheel --areas 1,-1 --scale 1 --rpm 60 --inertia 0.01
expect_error 2 "--mass x --gyration^2 = 0 kg m^2: not a positive inertia" flywheel --areas 1,-1 --scale 1 --rpm 60 --mass 1e9 --gyration 1e-200
printf '0,1e308\n90,1e308\n180,-1e308\n270,-1e308\n' > "$out/huge.csv"
expect_error 1 "huge.csv: a sample or area, or a sum of them, is not finite" flywheel --torque-csv "$out/huge.csv" --rpm 60 --cs 0.02
printf '0,1e300\n90,-1e300\n180,1e300\n270,-1e300\n' > "$out/large.csv"
expect_error 1 "large.csv: the flywheel I = 1e-300 kg m^2 is too small" flywheel --torque-csv "$out/large.csv" --rpm 60 --inertia 1e-300
"$tool" flywheel --torque-csv "$out/large.csv" --rpm 60 --cs 0.02 > "$out/large.txt" || fail "large torques: exit status"
grep -qi 'inf\|nan' "$out/large.txt" && fail "large torques: a non-finite figure: $(cat "$out/large.txt")"
printf '1e300,1,0,0\n' > "$out/heavy.csv"
expect_error 1 "heavy.csv: the unbalance sums or the correction masses are beyond the range of numbers" rotor --csv "$out/heavy.csv" --radius 1e-300
"$tool" flywheel --areas=295,-685,40,-340,960,-270 --scale=1 --rpm=1800 --mass=36 --gyration=0.15 > "$out/eq.txt" \
  || fail "--opt=value: exit status"
"$tool" flywheel --areas 295,-685,40,-340,960,-270 --scale 1 --rpm 1800 --mass 36 --gyration 0.15 > "$out/sp.txt" \
  || fail "--opt value: exit status"
cmp -s "$out/eq.txt" "$out/sp.txt" || fail "--opt=value and --opt value differ"
echo PASS
