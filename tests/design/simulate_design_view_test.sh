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
press=$(realpath "$4") press_object=$(realpath "$5")
# (view_tool, fixed_tool, object: the engine's; fail, $root entered; same_as_tool)
source "$(dirname "$0")/../view_compare.sh" "$1" "$2" "$3"

# design <case> <expected status> <options...>: same_as_tool on `simulate ... --csv out.csv`
# (every file written, the exit status, standard output and error byte for byte), and where it
# runs, sensitivity columns in the CSV.
design() {
  local name=$1 expected=$2
  shift 2
  same_as_tool "$(basename "$fixed_tool")" simulate "$name" "$expected" "$@" --csv out.csv
  if [[ $expected -eq 0 ]]; then
    grep -q "/d" "$name/fixed/out.csv" 2> /dev/null || fail "$name: no sensitivity columns"
  fi
}

design engine_grid 0 --design --t-end 0.05 --dt 0.005 --qd0 50
design engine_dopri5 0 --design --t-end 0.1 --qd0 100 --method dopri5
design engine_set 0 --design --t-end 0.05 --qd0 50 --set r=0.05 --rtol 1e-10
fixed_tool=$press object=$press_object
design press_grid 0 --design --t-end 0.5 --dt 0.05 --qd0 12 --rtol 1e-13 --atol 1e-14
design press_dopri5 0 --design --t-end 0.3 --method dopri5
design press_set 0 --design --t-end 0.2 --set m3=10 --dt 0.01
design press_drive 2 --design --drive theta_crank=speed:1
design press_projection 2 --design --energy-projection

[[ $failures -eq 0 ]] && echo "mechgen_view simulate --design: all checks passed"
exit $((failures > 0))
