#!/usr/bin/env bash
# The sweep command's contract under hostile arguments and failing outputs (issue 12):
#  - a table of bad arguments: each gets exactly one line on stderr matching its pattern,
#    exit status 2 (usage) and writes nothing (no file, no directory);
#  - outputs that cannot be written (/dev/full, a directory, a path under a regular file, a
#    file-size limit hit mid-row): one line "error: cannot write <path>: <strerror>", exit
#    status 1, no partial file, a previous file at the destination left as it was, no
#    temporary file left behind;
#  - a sweep that stops at a change point: exit status 3, the counts per status on stderr,
#    the CSV written whole, its not_run rows holding the inputs they asked for (not nan);
#  - a clean sweep: exit status 0, nothing on stderr, unique CSV column names.
# The change point's rows come from the sweep of tests/runtime/models/changepoint_fourbar.yaml
# through mechgen_view (its shared object; the per-model sweep's output, sweep_view_test.sh).
# usage: sweep_tool_test.sh <fourbar_sweep> <mechgen_view> <changepoint_fourbar.so>
set -uo pipefail
tool=$(realpath "$1") stop_tool=("$(realpath "$2")" sweep "$(realpath "$3")")
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# run <name> <expected status> <stderr pattern (ERE, whole line)> <tool> <args...>
# Runs in a fresh empty directory; afterwards the directory must hold nothing.
run_refused() {
  local name=$1 expected=$2 pattern=$3 exe=$4
  shift 4
  local dir="$root/$name"
  mkdir -p "$dir"
  (cd "$dir" && "$exe" "$@" > ../"$name".out 2> ../"$name".err)
  local status=$?
  local before=$failures
  local err lines
  err=$(cat "$root/$name.err")
  lines=$(printf '%s' "$err" | grep -c '')
  [ "$status" -eq "$expected" ] || fail "$name: exit status $status, expected $expected ($err)"
  [ "$lines" -eq 1 ] || fail "$name: $lines lines on stderr: $err"
  printf '%s\n' "$err" | grep -Eqx "$pattern" || fail "$name: message '$err' !~ /$pattern/"
  local left
  left=$(cd "$dir" && find . -mindepth 1 | head -5)
  [ -z "$left" ] || fail "$name: wrote $left"
  [ "$failures" -ne "$before" ] || echo "ok $name: $err"
}

out="--csv out/f.csv --svg out/f.svg"
# Usage errors: one line "<tool>: error: --x: bad value '...': expected ..." (the command-line
# layer of every tool, runtime/tools/common/).
T=$(basename "$tool")
steps_msg="$T: error: --steps: bad value .*: expected an integer from 1 to 10000000"
run_refused steps_zero 2 "$T: error: --steps: bad value '0': expected an integer from 1 to 10000000" "$tool" --steps 0 $out
run_refused steps_negative 2 "$steps_msg" "$tool" --steps -5 $out
run_refused steps_int_max 2 "$T: error: --steps: bad value '2147483647': .*" "$tool" --steps 2147483647 $out
run_refused steps_huge 2 "$T: error: --steps: bad value \(a 300-character value\): .*" "$tool" --steps "$(printf '9%.0s' $(seq 300))" $out
run_refused steps_overflow 2 "$steps_msg" "$tool" --steps 99999999999999999999 $out
run_refused steps_text 2 "$steps_msg" "$tool" --steps many $out
run_refused steps_float 2 "$steps_msg" "$tool" --steps 1.5 $out
run_refused steps_nan 2 "$steps_msg" "$tool" --steps nan $out
run_refused steps_inf 2 "$steps_msg" "$tool" --steps=inf $out
run_refused steps_1e300 2 "$steps_msg" "$tool" --steps 1e300 $out
run_refused steps_empty 2 "$steps_msg" "$tool" --steps "" $out
run_refused steps_missing 2 "$T: error: --steps: .*" "$tool" $out --steps
run_refused table_negative 2 "$T: error: --table: bad value '-1': expected an integer from 0 to .*" "$tool" --table -1 $out
run_refused table_text 2 "$T: error: --table: bad value 'x': .*" "$tool" --table x $out
run_refused unknown_option 2 "$T: error: .*--frobnicate.*" "$tool" --frobnicate $out
run_refused extra_positional 2 "$T: error: .*extra.*" "$tool" extra $out
run_refused range_no_colon 2 "$T: error: --range: bad value 'theta_crank': expected input:min:max" "$tool" --range theta_crank $out
run_refused range_unknown_input 2 "$T: error: --range: bad value 'rocker:0:1': expected input:min:max; no input named 'rocker'; inputs are theta_crank" "$tool" --range rocker:0:1 $out
range_msg="$T: error: --range: bad value .*: expected input:min:max with min and max in \[-1e4, 1e4\] .*"
run_refused range_not_number 2 "$range_msg" "$tool" --range theta_crank:a:b $out
run_refused range_nan 2 "$range_msg" "$tool" --range theta_crank:nan:1 $out
run_refused range_inf 2 "$range_msg" "$tool" --range theta_crank:0:inf $out
run_refused range_overflow 2 "$range_msg" "$tool" --range theta_crank:0:1e400 $out
run_refused range_1e300 2 "$range_msg" "$tool" --range=theta_crank:0:1e300 $out
run_refused range_too_long_per_step 2 "$T: error: --range: theta_crank moves .* per step, more than the solver's limit of 1000; .*" "$tool" --range theta_crank:0:9999 --steps 1 $out
run_refused range_long_text 2 "$T: error: --range: bad value \(a [0-9]+-character value\): .*" "$tool" --range "$(printf 'x%.0s' $(seq 200)):0:1" $out
run_refused range_control_characters 2 "$T: error: --range: bad value 'theta_crank.x1B\[2J': expected input:min:max" "$tool" --range "$(printf 'theta_crank\033[2J')" $out
run_refused qd_count 2 "$T: error: --qd: takes one value" "$tool" --qd 1 2 $out
run_refused qd_text 2 "$T: error: --qd: bad value 'fast': expected a number in \[-100000, 100000\] .*" "$tool" --qd fast $out
run_refused qd_1e300 2 "$T: error: --qd: bad value '1e300': expected a number in \[-100000, 100000\] .*" "$tool" --qd=1e300 $out
run_refused qdd_inf 2 "$T: error: --qdd: bad value 'inf': expected .*" "$tool" --qdd inf $out

# Outputs that cannot be written: exit 1, one line with the path and the reason.
run_refused csv_dev_full 1 "error: cannot write /dev/full: No space left on device" "$tool" --csv /dev/full --table 0
run_refused svg_dev_full 1 "error: cannot write /dev/full: No space left on device" "$tool" --svg /dev/full --table 0
mkdir -p "$root/adir"
run_refused csv_is_directory 1 "error: cannot write $root/adir: Is a directory" "$tool" --csv "$root/adir" --table 0
touch "$root/afile"
run_refused csv_under_a_file 1 "error: cannot write $root/afile/x.csv: .*" "$tool" --csv "$root/afile/x.csv" --table 0
# A standard output that cannot be written (the table goes there).
"$tool" --table 8 --steps 36 > /dev/full 2> "$root/stdout.err"
status=$?
[ "$status" -eq 1 ] || fail "stdout_full: exit status $status"
grep -Eqx "error: cannot write the standard output" "$root/stdout.err" \
  || fail "stdout_full: message $(cat "$root/stdout.err")"
echo "ok stdout_full: $(cat "$root/stdout.err")"

# A file-size limit hit mid-row (as on a nearly full disk): the write fails with EFBIG; the
# previous CSV at the destination stays whole, no temporary file is left.
dir="$root/limit"
mkdir -p "$dir"
printf 'previous,file\n1,2\n' > "$dir/f.csv"
(cd "$dir" && trap '' XFSZ && ulimit -f 16 && "$tool" --steps 3600 --csv f.csv --svg f.svg \
  --table 0 > ../limit.out 2> ../limit.err)
status=$?
[ "$status" -eq 1 ] || fail "limit: exit status $status"
grep -Eqx "error: cannot write f.csv: File too large" "$root/limit.err" \
  || fail "limit: message $(cat "$root/limit.err")"
[ "$(cat "$dir/f.csv")" = "$(printf 'previous,file\n1,2')" ] || fail "limit: f.csv changed"
[ "$(cd "$dir" && ls -A)" = "f.csv" ] || fail "limit: left $(cd "$dir" && ls -A)"
echo "ok limit: $(cat "$root/limit.err")"

# --at-singular follow passes the change point (issue 26): -179.5 .. 179.5 deg in 359 steps (no
# row at exactly 0 deg, where Phi_phi is singular) all converge, exit 0; every row closes the
# loop (B + b e_coupler = D + c e_rocker, a = 1, b = 3, c = d = 2: by hand from the CSV's
# angles), and the motion goes on along the same smooth curve: the coupler's K keeps its sign
# through 0 deg (both rows next to it have K_theta_coupler < -2) while the rocker's angle
# changes sign (the folded-flat position is passed, not bounced off).
dir="$root/follow"
mkdir -p "$dir"
(cd "$dir" && "${stop_tool[@]}" --at-singular follow --range theta_crank:-179.5deg:179.5deg --steps 359 \
   --csv f.csv --table 0 > ../follow.out 2> ../follow.err)
status=$?
[ "$status" -eq 0 ] || fail "follow: exit status $status: $(cat "$root/follow.err")"
awk -F, '/^#/ { next } ++line == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
         { n++
           if ($col["status"] != "converged") { print "row " line ": " $col["status"]; bad++ }
           t = $col["theta_crank"]; u = $col["theta_coupler"]; v = $col["theta_rocker"]
           ex = cos(t) + 3 * cos(u) - 2 - 2 * cos(v); ey = sin(t) + 3 * sin(u) - 2 * sin(v)
           e = sqrt(ex * ex + ey * ey); if (e > worst) worst = e
           if (t > -0.01 && t < 0.01) { near++; if ($col["K_theta_coupler_theta_crank"] > -2) bad++
                                        if (t < 0) before = v; else after = v } }
         END { if (n != 360 || near != 2 || worst > 1e-12 || bad || before * after >= 0) {
                 print n " rows, " near " next to 0 deg, closure " worst ", " bad " bad, rocker " before " / " after; exit 1 }
               print "closure residual " worst }' "$dir/f.csv" > "$root/follow.awk" \
  || fail "follow: $(cat "$root/follow.awk")"
echo "ok follow: $(cat "$root/follow.awk")"
run_refused at_singular_bad 2 ".*--at-singular.*" "${stop_tool[@]}" --at-singular bounce

# A sweep that stops at the change point (-180 .. 180 deg, 360 steps; theta_crank = 0 is row
# 180): exit 3, the counts on stderr, the CSV whole, not_run rows with their inputs.
dir="$root/stop"
mkdir -p "$dir"
(cd "$dir" && "${stop_tool[@]}" --csv f.csv --table 0 > ../stop.out 2> ../stop.err)
status=$?
[ "$status" -eq 3 ] || fail "stop: exit status $status"
grep -Eqx "error: 181 of 361 rows did not converge: 1 singular, 180 not_run \(see the status column\)" \
  "$root/stop.err" || fail "stop: message $(cat "$root/stop.err")"
[ "$(grep -vc '^#' "$dir/f.csv")" -eq 362 ] || fail "stop: CSV rows"
# Row 182 (index 181): theta_crank = 1 deg asked, not run.
awk -F, '/^#/ { next } ++line == 1 { for (i = 1; i <= NF; ++i) col[$i] = i }
         line > 1 && $col["status"] == "not_run" {
           n++; q = $col["theta_crank"]; want = -3.14159265358979 + (line - 2) * 6.28318530717959 / 360
           if (q == "nan" || (q - want) > 1e-9 || (want - q) > 1e-9) { print "row " line ": " q; bad++ }
           if ($col["theta_coupler"] != "nan") { print "row " line " has a value"; bad++ } }
         END { if (n != 180 || bad) { print n " not_run rows, " bad " bad"; exit 1 } }' \
  "$dir/f.csv" || fail "stop: not_run rows"
echo "ok stop: $(cat "$root/stop.err")"

# A clean sweep: exit 0, stderr empty, unique column names, whole files.
dir="$root/clean"
mkdir -p "$dir"
(cd "$dir" && "$tool" --steps 36 --csv out/f.csv --svg out/f.svg > ../clean.out 2> ../clean.err)
status=$?
[ "$status" -eq 0 ] || fail "clean: exit status $status"
[ ! -s "$root/clean.err" ] || fail "clean: stderr $(cat "$root/clean.err")"
[ "$(grep -vc '^#' "$dir/out/f.csv")" -eq 38 ] || fail "clean: CSV rows"
dups=$(awk '!/^#/ { print; exit }' "$dir/out/f.csv" | tr ',' '\n' | sort | uniq -d)
[ -z "$dups" ] || fail "clean: duplicate columns $dups"
tail -n 1 "$dir/out/f.svg" | grep -q "</svg>" || fail "clean: SVG not whole"
[ "$(cd "$dir/out" && ls -A | tr '\n' ' ')" = "f.csv f.svg " ] || fail "clean: left $(ls -A "$dir/out")"
echo "ok clean"

[ "$failures" -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
echo PASS
