#!/usr/bin/env bash
# The statics command on the hand-written slider-crank (friction at the crank bearing):
# its table, dead zones (three over a full turn: about 0, 180 and 360 deg, see
# statics_friction_test.cc for the angles), equilibria (the dead centres), CSV and SVG (a force
# diagram: scale bar, magnitudes, input labels; rendered by rsvg-convert when installed); the
# stub for a model without statics; and plot_statics.gnuplot on the CSV.
# usage: statics_tool_test.sh <statics tool> <stub tool> <plot_statics.gnuplot>
set -euo pipefail
tool=$1 stub=$2 plot=$3
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$tool" --steps 720 --csv "$out/s.csv" --svg "$out/s.svg" --dead-zones --equilibria \
  --samples 180 > "$out/stdout.txt" || fail "exit status $?"
cat "$out/stdout.txt"
grep -q "721/721 rows converged, 0 singular" "$out/stdout.txt" || fail "rows"
grep -q "dead zones of theta_crank (self-locking: the load cannot drive it back): 3 (converged)" \
  "$out/stdout.txt" || fail "dead zones"
grep -q "equilibrium positions (Q = 0 along the line): 2 (converged)" "$out/stdout.txt" \
  || fail "equilibria"
grep -q "theta_crank = 180.0000 deg: stiffness .*, stable" "$out/stdout.txt" || fail "stable BDC"
awk '!/^#/ { print; exit }' "$out/s.csv" | grep -q "^theta_crank,theta_rod,s_slide,drive_theta_crank," \
  || fail "CSV header"
[ "$(grep -vc '^#' "$out/s.csv")" -eq 722 ] || fail "CSV rows"
grep -q '<g id="reactions" data-force-scale="' "$out/s.svg" || fail "SVG reactions"
grep -q '<g id="force_scale"' "$out/s.svg" || fail "SVG force scale"
grep -q 'class="magnitude"' "$out/s.svg" || fail "SVG arrow magnitudes"
grep -q 'class="input"[^>]*>theta_crank = ' "$out/s.svg" || fail "SVG input labels"
if command -v rsvg-convert > /dev/null; then
  rsvg-convert "$out/s.svg" -o "$out/s_svg.png" || fail "rsvg-convert"
  [ -s "$out/s_svg.png" ] || fail "rendered SVG"
fi

set +e
"$stub" > "$out/stub.txt" 2>&1
status=$?
set -e
[ "$status" -eq 2 ] || fail "stub exit status $status"
grep -q "generated without statics" "$out/stub.txt" || fail "stub message"

if command -v gnuplot > /dev/null; then
  gnuplot -e "csv='$out/s.csv'; png='$out/s.png'" "$plot" || fail "gnuplot"
  [ -s "$out/s.png" ] || fail "no PNG"
  gnuplot -e "csv='$out/s.csv'; svg='$out/plot.svg'" "$plot" || fail "gnuplot svg"
  grep -q "F_O_mag" "$out/plot.svg" || fail "plot legend"
fi
echo PASS
