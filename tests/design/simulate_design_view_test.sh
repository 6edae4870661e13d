#!/usr/bin/env bash
# mechgen_view simulate --design (issues 43, 46): the trajectory sensitivities through the model
# view (dynamics/sensitivity.h on ModelCalls<ViewModel>, the view's generated
# EvalDynamicsJacobian; compiled once, runtime/view/analysis_simulate_design.cc) against the
# per-model tool's (<model>_simulate --design, fixed sizes): the CSV, the exit status, standard
# output and standard error byte for byte, on the shipped model with a design section and
# dynamics (engine_single) and on the damped press of tests/design (every parameter a design
# parameter), each with both integrators, a sample grid and every step, --set, and the usage
# errors (--design with --drive, --energy-projection).
# usage: simulate_design_view_test.sh <mechgen_view> <engine_single_simulate> <engine_single object>
#        <design_press_simulate> <design_press object>
set -uo pipefail
view_tool=$(realpath "$1")
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
cd "$root" || exit 1

# same <fixed tool> <object> <options...>: both CSVs byte for byte, the same exit status,
# standard output and standard error (each run in its own directory, the same CSV name).
same() {
  local fixed=$1 object=$2
  shift 2
  rm -rf fixed view && mkdir fixed view
  (cd fixed && "$fixed" "$@" --csv out.csv > ../fixed.out 2> ../fixed.err)
  local fixed_status=$?
  (cd view && "$view_tool" --name "$(basename "$fixed")" simulate "$object" "$@" --csv out.csv > ../view.out \
    2> ../view.err)
  local view_status=$?
  [[ $fixed_status -eq $view_status ]] || fail "$(basename "$fixed") $*: exit $view_status through the view, $fixed_status fixed"
  if [[ $fixed_status -ne 2 ]]; then
    [[ -s fixed/out.csv ]] || fail "$(basename "$fixed") $*: the fixed-size tool wrote no CSV: $(cat fixed.err)"
    grep -q "/d" fixed/out.csv || fail "$(basename "$fixed") $*: no sensitivity columns"
    cmp -s fixed/out.csv view/out.csv || fail "$(basename "$fixed") $*: the CSVs differ: $(cmp fixed/out.csv view/out.csv 2>&1 | head -1)"
  else
    [[ ! -e view/out.csv ]] || fail "$(basename "$fixed") $*: a usage error wrote a CSV through the view"
  fi
  cmp -s fixed.out view.out || fail "$(basename "$fixed") $*: the standard outputs differ: $(diff fixed.out view.out | head -3)"
  cmp -s fixed.err view.err || fail "$(basename "$fixed") $*: the standard errors differ: $(diff fixed.err view.err | head -3)"
}

engine=$(realpath "$2") engine_object=$(realpath "$3") press=$(realpath "$4") press_object=$(realpath "$5")
same "$engine" "$engine_object" --design --t-end 0.05 --dt 0.005 --qd0 50
same "$engine" "$engine_object" --design --t-end 0.1 --qd0 100 --method dopri5
same "$engine" "$engine_object" --design --t-end 0.05 --qd0 50 --set r=0.05 --rtol 1e-10
same "$press" "$press_object" --design --t-end 0.5 --dt 0.05 --qd0 12 --rtol 1e-13 --atol 1e-14
same "$press" "$press_object" --design --t-end 0.3 --method dopri5
same "$press" "$press_object" --design --t-end 0.2 --set m3=10 --dt 0.01
same "$press" "$press_object" --design --drive theta_crank=speed:1
same "$press" "$press_object" --design --energy-projection

[[ $failures -eq 0 ]] && echo "mechgen_view simulate --design: all checks passed"
exit $((failures > 0))
