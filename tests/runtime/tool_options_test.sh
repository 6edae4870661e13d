#!/usr/bin/env bash
# One command-line layer for every tool (runtime/tools/common/; issue 24): on each of
# <model>_sweep, <model>_statics, <model>_simulate, <model>_engine and mechgen_balance
#  - `--opt=value` and `--opt value` give the same run (the same CSV bytes);
#  - values that cannot mean anything (nan, inf, 1e300, a count of 2e9 or INT_MAX, a time step
#    that cannot advance t, a tolerance below what double precision resolves, a scan too
#    coarse for its range) exit 2 with exactly one line "<tool>: error: ..." on stderr, no
#    309-digit number in it, and write nothing (the run's directory stays empty), within a
#    time limit (a time step that does not advance t used to loop forever).
# usage: tool_options_test.sh <fourbar_sweep> <slider_crank_friction_statics>
#                             <slider_crank_motor_simulate> <engine_single_engine> <mechgen_balance>
set -uo pipefail
sweep=$(realpath "$1") statics=$(realpath "$2") simulate=$(realpath "$3") engine=$(realpath "$4")
balance=$(realpath "$5")
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
failures=0
n=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# refused <tool> <args...>: exit 2, one line "<tool name>: error: ..." (at most 300
# characters: no number printed in full), nothing written in the run's directory.
refused() {
  local exe=$1
  shift
  n=$((n + 1))
  local dir="$root/r$n"
  mkdir -p "$dir"
  (cd "$dir" && timeout 60 "$exe" "$@" > ../r$n.out 2> ../r$n.err)
  local status=$?
  local err lines name
  err=$(cat "$root/r$n.err")
  lines=$(grep -c '' "$root/r$n.err")
  name=$(basename "$exe")
  local what="$name $*"
  [ "$status" -eq 2 ] || { fail "$what: exit status $status, expected 2 ($err)"; return; }
  [ "$lines" -eq 1 ] || { fail "$what: $lines lines on stderr: $err"; return; }
  case "$err" in "$name: error: "*) ;; *) fail "$what: message '$err' lacks '$name: error: '"; return ;; esac
  [ "${#err}" -le 300 ] || { fail "$what: a ${#err}-character message: $err"; return; }
  local left
  left=$(cd "$dir" && find . -mindepth 1 | head -3)
  [ -z "$left" ] || { fail "$what: wrote $left"; return; }
  echo "ok $what: $err"
}

# same <name> <file> <tool> <args with --opt=value> -- <args with --opt value>: both exit 0
# and write the same <file>.
same() {
  local name=$1 file=$2 exe=$3
  shift 3
  local eq=() sp=()
  while [ "$1" != "--" ]; do eq+=("$1"); shift; done
  shift
  sp=("$@")
  mkdir -p "$root/$name.eq" "$root/$name.sp"
  (cd "$root/$name.eq" && timeout 120 "$exe" "${eq[@]}" > out.txt 2> err.txt) ||
    { fail "$name: --opt=value: exit status $? ($(cat "$root/$name.eq/err.txt"))"; return; }
  (cd "$root/$name.sp" && timeout 120 "$exe" "${sp[@]}" > out.txt 2> err.txt) ||
    { fail "$name: --opt value: exit status $? ($(cat "$root/$name.sp/err.txt"))"; return; }
  [ -s "$root/$name.eq/$file" ] || { fail "$name: no $file"; return; }
  cmp -s "$root/$name.eq/$file" "$root/$name.sp/$file" ||
    { fail "$name: --opt=value and --opt value wrote different $file"; return; }
  echo "ok $name: --opt=value and --opt value agree"
}

# ---- <model>_sweep ----
same sweep f.csv "$sweep" --steps=12 --table=0 --qd=2 --range=theta_crank:0:90deg --csv=f.csv \
  -- --steps 12 --table 0 --qd 2 --range theta_crank:0:90deg --csv f.csv
for args in "--steps nan" "--steps inf" "--steps 1e300" "--steps 2147483647" "--steps=2e9" \
            "--table inf" "--qd nan" "--qd=inf" "--qd 1e300" "--qdd -1e300" \
            "--range theta_crank:0:inf" "--range=theta_crank:0:1e300"; do
  # shellcheck disable=SC2086
  refused "$sweep" $args --csv f.csv --svg f.svg
done

# ---- <model>_statics ----
same statics f.csv "$statics" --steps=36 --table=0 --samples=72 --dead-zones --equilibria --csv=f.csv \
  -- --steps 36 --table 0 --samples 72 --dead-zones --equilibria --csv f.csv
for args in "--steps 2147483647" "--steps nan" "--steps=inf" "--steps 1e300" "--samples 2e9" \
            "--samples 1 --equilibria" "--samples 2 --dead-zones" \
            "--samples 40 --dead-zones --range theta_crank:0:720deg" \
            "--max-condition inf" "--max-condition=nan" "--max-condition 1e300" \
            "--snapshots 2e9" "--table 1e300" "--range theta_crank:0:nan" "--nosuch 1"; do
  # shellcheck disable=SC2086
  refused "$statics" $args --csv f.csv --svg f.svg
done

# ---- <model>_simulate ----
same simulate f.csv "$simulate" --t-end=0.05 --dt=0.01 --q0=-0.06 --qd0=1 --rtol=1e-9 --csv=f.csv --quiet \
  -- --t-end 0.05 --dt 0.01 --q0 -0.06 --qd0 1 --rtol 1e-9 --csv f.csv --quiet
for args in "--rtol 1e300" "--rtol nan" "--rtol=1e-300" "--atol inf" "--q0 1e300" "--q0=nan" \
            "--qd0 inf" "--dt 1e-300" "--dt=4.9e-324" "--t-end 1e300 --dt 1e-3" "--t-end inf" \
            "--max-steps 1e300" "--max-steps 2147483648" "--steady-tol nan" "--method rk4" \
            "--drive theta_crank=speed:inf" "--nosuch"; do
  # shellcheck disable=SC2086
  refused "$simulate" $args --csv f.csv
done

# ---- <model>_engine ----
same engine f.csv "$engine" cycle --rpm=2000 --samples=64 --csv=f.csv \
  -- cycle --rpm 2000 --samples 64 --csv f.csv
for args in "cycle --rpm inf" "cycle --rpm=nan" "cycle --rpm 1e300" "cycle --samples 2e9" \
            "cycle --cr 1e300" "cycle --heat nan" "flywheel --cs nan" "runup --dt 1e-300" \
            "runup --t-end inf"; do
  # shellcheck disable=SC2086
  refused "$engine" $args --csv f.csv
done

# ---- mechgen_balance ----
awk 'BEGIN { for (k = 0; k < 360; k += 10) printf "%d,%.17g\n", k, 100 * sin(k * atan2(0, -1) / 90) }' \
  > "$root/t.csv"
same balance E.csv "$balance" flywheel --torque-csv=../t.csv --rpm=600 --cs=0.01 --energy-csv=E.csv \
  -- flywheel --torque-csv ../t.csv --rpm 600 --cs 0.01 --energy-csv E.csv
for args in "flywheel --areas 1,-1 --scale 1 --rpm 600 --inertia inf" \
            "flywheel --areas 1,-1 --scale 1 --rpm 600 --cs nan" \
            "flywheel --areas 1,-1 --scale=1e300 --rpm 600 --cs 0.01" \
            "table --rotating-ratio nan" "table --nosuch"; do
  # shellcheck disable=SC2086
  refused "$balance" $args
done

[ "$failures" -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
echo PASS
