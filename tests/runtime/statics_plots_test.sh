#!/usr/bin/env bash
# The statics command's pictures (issue 25): `--plots PREFIX` runs gnuplot on the command's own
# CSV: PREFIX_drive.<format> (plot_statics.gnuplot: the driving torque, with friction to run
# in +q and -q, against the crank angle) and PREFIX_bearings.<format> (plot_bearings.gnuplot:
# the polar diagram of each ground bearing's force, the ground's on the moving link, fixed
# frame). Checked:
#   - the bearing columns against the whole machine's free body: slider_crank_friction's only
#     horizontal external forces are the piston force F = 1000 N along -x and the ground's at
#     O (the slide's normal force is vertical, no friction in these columns), so
#     bearing_O_x = +1000 N on every row; |bearing| equals the joint's F_<J>_mag;
#   - the pictures: PNG and SVG written, the SVG legends name the curves and the link each
#     bearing carries, every SVG rendered by rsvg-convert to a PNG; the statics SVG (one
#     snapshot) says at each arrow which link's force on which it is;
#   - --table includes the last row of the range (0, 120, 240, 360 deg for 4 rows) and says
#     the units of its columns;
#   - gnuplot missing from PATH: one error line, exit 1, nothing written; a bad --plot-format:
#     one line, exit 2.
# usage: statics_plots_test.sh <slider_crank_friction_statics> <fourbar_loaded_statics>
set -euo pipefail
scf=$1 fl=$2
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
command -v gnuplot > /dev/null || { echo "gnuplot not installed: skipped"; exit 0; }

cd "$out"
"$scf" --steps 360 --plots scf --table 4 --svg scf.svg --snapshots 1 > scf.txt \
  || fail "slider_crank_friction exit $?"
cat scf.txt
[ -s scf.csv ] && [ -s scf_drive.png ] && [ -s scf_bearings.png ] || fail "scf outputs"
head -c 8 scf_drive.png | od -An -c | grep -q "P   N   G" || fail "scf_drive.png is not a PNG"
# The table: the first and the last row of the range.
grep -q "^units: drive_theta_crank, drive_theta_crank_plus, drive_theta_crank_minus \[N m\]; |F_O|, .* \[N\]" \
  scf.txt || fail "table units"
awk '$NF == "converged" { print $1 }' scf.txt > angles.txt
[ "$(tr '\n' ' ' < angles.txt)" = "0.0000 120.0000 240.0000 360.0000 " ] \
  || fail "table rows: $(tr '\n' ' ' < angles.txt)"
grep -q "^# bearing_O_x \[N\]: force of the ground on crank at the bearing O" scf.csv \
  || fail "bearing_O_x described"
grep -q "^# drive_theta_crank_plus \[N m\]:" scf.csv || fail "drive_plus described"
# The force diagram (one configuration): who acts on whom at each arrow, rendered.
grep -q '<title>F_B = ([^)]*) N: force of crank on rod</title>' scf.svg || fail "SVG: F_B's tooltip"
grep -q '<title>F_O = ([^)]*) N: force of ground on crank</title>' scf.svg || fail "SVG: F_O's tooltip"
[ "$(grep -c '<g class="snapshot"' scf.svg)" -eq 1 ] || fail "SVG: one snapshot"
rsvg-convert scf.svg -o scf_svg.png && [ -s scf_svg.png ] || fail "rsvg-convert scf.svg"
# Whole-machine balance along x, and the magnitude.
awk -F, '
  /^#/ { next }
  !header { for (i = 1; i <= NF; ++i) col[$i] = i; header = 1; next }
  {
    x = $col["bearing_O_x"]; y = $col["bearing_O_y"]; m = $col["F_O_mag"]
    if ((x - 1000) ^ 2 > 1e-14) { print "bearing_O_x = " x " on row " NR; bad = 1 }
    if ((sqrt(x * x + y * y) - m) ^ 2 > 1e-14) { print "|bearing_O| != F_O_mag on row " NR; bad = 1 }
    ++rows
  }
  END { if (bad || rows != 361) { print "rows " rows; exit 1 } }' scf.csv || fail "bearing_O"

"$fl" --steps 360 --plots fl --plot-format svg --table 0 > fl.txt || fail "fourbar_loaded exit $?"
cat fl.txt
for f in fl_drive.svg fl_bearings.svg; do
  [ -s "$f" ] || fail "no $f"
  rsvg-convert "$f" -o "${f%.svg}.png" || fail "rsvg-convert $f"
  [ -s "${f%.svg}.png" ] || fail "rendering $f"
done
grep -q "A (on crank)" fl_bearings.svg || fail "bearing A's legend"
grep -q "D (on rocker)" fl_bearings.svg || fail "bearing D's legend"
grep -q "force of the ground on the moving link" fl_bearings.svg || fail "bearings title"
grep -q "drive_theta_crank" fl_drive.svg || fail "drive legend"
grep -q "driving torque or force \[N m\]" fl_drive.svg || fail "drive axis unit"
awk -F, '
  /^#/ { next }
  !header { for (i = 1; i <= NF; ++i) col[$i] = i; header = 1; next }
  {
    for (j = 0; j < 2; ++j) {
      J = j ? "D" : "A"; x = $col["bearing_" J "_x"]; y = $col["bearing_" J "_y"]
      m = $col["F_" J "_mag"]
      if ((sqrt(x * x + y * y) - m) ^ 2 > 1e-12 * (1 + m * m)) { print J " row " NR; bad = 1 }
    }
  }
  END { exit bad }' fl.csv || fail "fourbar bearings"

# No gnuplot: one line, exit 1, no output at all.
mkdir nogp && cd nogp
set +e
PATH=/nonexistent "$scf" --plots p > stdout.txt 2> stderr.txt
status=$?
set -e
[ "$status" -eq 1 ] || fail "no gnuplot: exit status $status"
[ "$(wc -l < stderr.txt)" -eq 1 ] && grep -q "gnuplot not found on PATH" stderr.txt \
  || fail "no gnuplot: $(cat stderr.txt)"
[ -z "$(ls)" ] || [ "$(ls)" = "$(printf 'stderr.txt\nstdout.txt')" ] || fail "no gnuplot wrote $(ls)"
set +e
"$scf" --plots p --plot-format jpg > /dev/null 2> stderr.txt
status=$?
set -e
[ "$status" -eq 2 ] && [ "$(wc -l < stderr.txt)" -eq 1 ] || fail "--plot-format jpg: $status $(cat stderr.txt)"
echo PASS
