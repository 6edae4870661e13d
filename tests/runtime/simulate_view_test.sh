#!/usr/bin/env bash
# mechgen_view simulate (issue 43): a model compiled into a shared object with its view's entry
# point (<name>.cc + <name>_view.cc, -DMECHGEN_VIEW_ENTRY, g++ -O2 -shared -fPIC), loaded and
# simulated through the runtime compiled once (mechgen_runtime_view):
#  - its CSV equals, byte for byte, the per-model tool's (<name>_simulate) for the same options,
#    on the slider-crank with a motor (one input, switching loads, reactions; a friction joint,
#    its friction with the model's default, on and off: Coulomb friction's stick and slip through
#    the view are compared on tests/dynamics' incline, simulate_friction_test.sh)
#    and the five-bar robot (two inputs, the one-pass M::Rhs stages), each with two option sets,
#    and so are its exit status, standard output and standard error (a failed run's too);
#  - --set through the view's parameter table: the same run and summary;
#  - the driven motion (--drive, dynamics/prescribed.h instantiated for the view with the driven
#    inputs counted at run time): every input driven (both of the robot's, the motor's crank:
#    each law kind, a table law, both integrators), one of the robot's two driven and the other
#    free, runs that end at a dead point (exit 1: a free arm falling into one, and both motors
#    driven into the stretched configuration, whose last row withholds the torques), and usage
#    errors (an unknown input, one driven twice, too many --drive): the same bytes (mechgen_view
#    --name: the tool's name in the messages);
#  - --design on a model without a design section (the view's --design against the per-model
#    tools': tests/design/simulate_design_view_test.sh) is a usage error (exit 2, also run by
#    mechgen: no fallback) with one line on stderr and nothing written, as are a bad --set, a bad
#    option and a model without dynamics.
# usage: simulate_view_test.sh <c++ compiler> <mechgen_view> <slider_crank_motor_simulate>
#        <fivebar_robot_simulate> <models build dir> <runtime include dir> <Eigen include dir>
set -uo pipefail
cxx=$1 view_tool=$(realpath "$2") motor_tool=$(realpath "$3") robot_tool=$(realpath "$4") models=$(realpath "$5")
runtime_include=$(realpath "$6") eigen=$7
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
cd "$root" || exit 1

build() {  # build <model>: <model>.so from the generated code
  local dir=$models/mechgen_$1
  "$cxx" -O2 -shared -fPIC -DMECHGEN_VIEW_ENTRY -I"$dir" -I"$runtime_include" -I"$eigen" \
    "$dir/$1.cc" "$dir/$1_view.cc" -o "$1.so" || { echo "FAIL: cannot build $1.so"; exit 1; }
}
build slider_crank_motor
build fivebar_robot

# same <model> <fixed tool> <options...>: both CSVs byte for byte, the same exit status, standard
# output and standard error (each run in its own directory, the same CSV name).
same() {
  local model=$1 fixed=$2
  shift 2
  rm -rf fixed view && mkdir fixed view
  (cd fixed && "$fixed" "$@" --csv out.csv > ../fixed.out 2> ../fixed.err)
  local fixed_status=$?
  (cd view && "$view_tool" --name "$(basename "$fixed")" simulate "$root/$model.so" "$@" --csv out.csv > ../view.out \
    2> ../view.err)
  local view_status=$?
  [[ $fixed_status -eq $view_status ]] || fail "$model $*: exit $view_status through the view, $fixed_status fixed"
  [[ -s fixed/out.csv || $fixed_status -eq 2 ]] || fail "$model $*: the fixed-size tool wrote no CSV: $(cat fixed.err)"
  [[ $fixed_status -ne 2 || ! -e view/out.csv ]] || fail "$model $*: a usage error wrote a CSV through the view"
  if [[ $fixed_status -ne 2 ]]; then
    cmp -s fixed/out.csv view/out.csv || fail "$model $*: the CSVs differ: $(cmp fixed/out.csv view/out.csv 2>&1 | head -1)"
  fi
  cmp -s fixed.out view.out || fail "$model $*: the standard outputs differ: $(diff fixed.out view.out | head -3)"
  cmp -s fixed.err view.err || fail "$model $*: the standard errors differ: $(diff fixed.err view.err | head -3)"
}
same slider_crank_motor "$motor_tool" --friction off --t-end 0.5 --dt 0.005
same slider_crank_motor "$motor_tool" --friction off --t-end 0.3 --dt 0.002 --method dop853 --energy-projection \
  --q0 1 --qd0 20
# (the robot falls under its weight into a dead point at t = 0.145 s: exit 1, the same failure)
same fivebar_robot "$robot_tool" --t-end 0.5 --dt 0.005
same fivebar_robot "$robot_tool" --t-end 0.08 --dt 0.001 --method dop853 --qd0 1,-2 --rtol 1e-10
# the parameters through the view's table (common/view_params.h): the same run and summary
same slider_crank_motor "$motor_tool" --friction off --t-end 0.3 --dt 0.005 --set J_fly=0.8 --set m3=5
# its friction joint O (viscous: no Coulomb coefficient) with the default --friction and with on
same slider_crank_motor "$motor_tool" --t-end 0.4 --dt 0.004
same slider_crank_motor "$motor_tool" --friction on --t-end 0.2 --method dop853
# the driven motion (--drive): every input driven, each law (a rest-to-rest move, a cycloidal one)
printf 't,q\n0,2.356\n0.2,2.45\n0.4,2.6\n0.6,2.55\n' > "$root/law.csv"
same fivebar_robot "$robot_tool" --rtol 1e-10 --atol 1e-12 --drive theta_prox1=move:120deg:0.1:0.6 \
  --drive theta_prox2=cycloidal:60deg:0:0.5 --t-end 0.8 --dt 0.01
# ... in the other order, by the table law, with Dop853
same fivebar_robot "$robot_tool" --drive theta_prox2=speed:0 --drive "theta_prox1=table:$root/law.csv" --t-end 0.8 \
  --dt 0.05 --method dop853
# one driven, the other free (the reduced forward dynamics, the one-pass M::Rhs stages): the free
# arm falls into a singular configuration, the run ends there (exit 1, the same figures)
same fivebar_robot "$robot_tool" --drive theta_prox1=speed:1 --t-end 1 --dt 0.01
same fivebar_robot "$robot_tool" --drive theta_prox2=move:0.5:0:0.3 --qd0 0,0.5 --t-end 0.1 --dt 0.002 \
  --set mp=0.5
# both driven into the stretched configuration: a dead point, the last row's torques withheld
same fivebar_robot "$robot_tool" --drive theta_prox1=speed:1 --drive theta_prox2=speed:-1 --t-end 2 --dt 0.001
grep -q "lambda_theta_prox1 withheld" view.out || fail "stretched: the torques are not withheld: $(cat view.out)"
# the motor's crank at constant speed (every input driven, its viscous friction joint), with
# --friction on (no Coulomb coefficient: none in lambda) and every sample
same slider_crank_motor "$motor_tool" --drive theta_crank=speed:10 --t-end 0.3 --dt 0.001 --rtol 1e-11 --atol 1e-13
same slider_crank_motor "$motor_tool" --drive theta_crank=move:3:0.05:0.25 --t-end 0.3 --friction on
# usage errors (exit 2, one line, no CSV)
same fivebar_robot "$robot_tool" --drive theta_nope=speed:1
same fivebar_robot "$robot_tool" --drive theta_prox1=speed:1 --drive theta_prox1=speed:2
same slider_crank_motor "$motor_tool" --drive theta_crank=speed:1 --drive theta_crank=speed:2
same fivebar_robot "$robot_tool" --drive "theta_prox1=table:$root/missing.csv"
same slider_crank_motor "$motor_tool" --drive theta_crank=speed:1 --q0 1,2

# refused <name> <model> <pattern> <args...>: exit 2, one stderr line, nothing written.
refused() {
  local name=$1 model=$2 pattern=$3
  shift 3
  mkdir "$name" && (cd "$name" && "$view_tool" simulate "$root/$model.so" "$@" > ../"$name".out 2> ../"$name".err)
  local status=$?
  [[ $status -eq 2 ]] || fail "$name: exit $status, expected 2"
  [[ $(wc -l < "$name".err) -eq 1 ]] || fail "$name: stderr is not one line: $(cat "$name".err)"
  grep -Eq "$pattern" "$name".err || fail "$name: stderr $(cat "$name".err) does not match $pattern"
  [[ -z $(ls -A "$name") ]] || fail "$name: wrote $(ls -A "$name")"
}
refused design fivebar_robot "^fivebar_robot_simulate_view: error: --design: the model has no \`design\` section" \
  --design --csv out.csv
refused set fivebar_robot "^fivebar_robot_simulate_view: error: --set 'nosuch=0.3': no parameter 'nosuch'" --set nosuch=0.3 --csv out.csv
# run by mechgen (MECHGEN_VIEW_FALLBACK=1), --design on a model without a design section is the
# same usage error (the view runs --design: tests/design/simulate_design_view_test.sh), not a fallback
mkdir fallback && (cd fallback && MECHGEN_VIEW_FALLBACK=1 "$view_tool" simulate "$root/fivebar_robot.so" \
  --design --csv out.csv > ../fallback.out 2> ../fallback.err)
status=$?
[[ $status -eq 2 ]] || fail "fallback: exit $status, expected 2"
[[ -z $(ls -A fallback) ]] || fail "fallback: wrote something"
refused friction_on_none fivebar_robot "^fivebar_robot_simulate_view: error: --friction on: the model has no friction joints" \
  --friction on --csv out.csv
refused bad_option fivebar_robot "^fivebar_robot_simulate_view: error: " --no-such-option
refused q0_count fivebar_robot "^fivebar_robot_simulate_view: error: --q0: bad value '1': expected 2 value\(s\)" \
  --q0 1 --csv out.csv

# a model without dynamics (the four-bar's kinematics), as its per-model stub says
if [[ -d $models/mechgen_fourbar ]]; then
  build fourbar
  mkdir no_dynamics && (cd no_dynamics && "$view_tool" simulate "$root/fourbar.so" --csv out.csv > ../no_dynamics.out \
    2> ../no_dynamics.err)
  status=$?
  [[ $status -eq 2 ]] || fail "no_dynamics: exit $status, expected 2"
  grep -q "^fourbar: this model was generated without \`dynamics\`" no_dynamics.err || fail "no_dynamics: $(cat no_dynamics.err)"
  [[ -z $(ls -A no_dynamics) ]] || fail "no_dynamics: wrote $(ls -A no_dynamics)"
fi

[[ $failures -eq 0 ]] && echo "mechgen_view simulate: all checks passed"
exit $((failures > 0))
