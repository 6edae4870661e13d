#!/usr/bin/env bash
# mechgen_view flywheel (issue 43): the punch press compiled into a shared object with its view's
# entry point (tests/runtime's mechgen_view_object()), loaded and run through the machines of the
# runtime compiled once (mechgen_runtime_view: machines/view_machines.h):
#  - the energy loop's CSV, the standard output and the standard error byte for byte the
#    per-model tool punch_press_flywheel's with the same options, each run in a directory of its
#    own (mechgen_view --name: the tool's name in the messages): the sampled cycle with the
#    punch's switches located from the generated switch modes, and the simulated check of the
#    flywheel (WithFlywheel<ViewModel>: the flywheel added through the view's calls) under the
#    constant and the shunt motor;
#  - --set and --params through the view's parameter table, a derived parameter (s_p = a + b -
#    delta) following: the same bytes as the tool's, not the defaults';
#  - a machine that cannot be sized (no load) and a usage error: the same status and line;
#  - --design (machines/flywheel/cycle_design.h through ModelCalls: the view's Design and
#    DynamicsDesign) on the design press of tests/design (every parameter a design parameter,
#    mass, a damper and a spring): the printed sensitivities and the CSV's dT_req/d<p> columns
#    byte for byte design_press_flywheel's, with the simulated check and with --set; on the punch
#    press (no design section) the same usage error.
# usage: flywheel_view_test.sh <mechgen_view> <punch_press_flywheel> <punch_press view object>
#                              <design_press_flywheel> <design_press view object>
set -uo pipefail
source "$(dirname "$0")/../view_compare.sh"  # view_tool, fixed_tool, object, fail, $root (entered)
same() { same_as_tool punch_press_flywheel flywheel "$@"; }  # same <name> <expected status> <args...>
same check 0 --rpm 300 --cs 0.02 --samples 3600 --csv loop.csv
[[ $(grep -vc '^#' check/view/loop.csv) -eq 3601 ]] || fail "check: $(grep -vc '^#' check/view/loop.csv) CSV lines"
grep -q 'simulated C_s = ' check/view.out || fail "check: no simulated C_s: $(cat check/view.out)"
grep -q 'switches of the loads located' check/view.out || fail "check: no switches located: $(cat check/view.out)"
same shunt 0 --rpm 120 --cs 0.05 --samples 720 --motor shunt --slip 0.04 --csv loop.csv
same plain 0 --rpm 300 --samples 3600 --no-switch-breaks --no-check --csv loop.csv
same break 0 --break 7.25deg --samples 360 --rpm 60 --no-check --csv loop.csv
printf 'delta = 0.004  # a shallower punch\nF0: 15000\n' > "$root/press.params"
same set 0 --rpm 300 --samples 1800 --set delta=0.004 --set F0=15000 --csv loop.csv
same params 0 --rpm 300 --samples 1800 --params "$root/press.params" --csv loop.csv
cmp -s set/view/loop.csv params/view/loop.csv || fail "--set and --params: the CSVs differ"
same defaults 0 --rpm 300 --samples 1800 --csv loop.csv
cmp -s set/view/loop.csv defaults/view/loop.csv && fail "--set: the CSV is the defaults'"
grep -q '^parameters set: delta = 0.004 (default 0.006), F0 = 15000 (default 20000)$' set/view.out ||
  fail "--set: no 'parameters set' line: $(head -2 set/view.out)"
same no_load 1 --set F0=-20000 --no-check --csv loop.csv
[[ -z $(ls -A no_load/view) ]] || fail "no load: wrote $(ls -A no_load/view)"
same bad_set 2 --set s_p=0.3 --csv loop.csv
same design 2 --design --csv loop.csv
grep -q "error: --design: the model has no \`design\` section" design/view.err || fail "design: $(cat design/view.err)"

# --design on the design press (its tool and object: the 4th and 5th arguments)
[[ $# -eq 5 ]] || { fail "usage: the design press's tool and object are missing"; exit 1; }
fixed_tool=$(realpath "$4") object=$(realpath "$5")
same_press() { same_as_tool design_press_flywheel flywheel "$@"; }
same_press press_design 0 --rpm 120 --cs 0.05 --samples 360 --design --csv loop.csv
grep -q '^  design sensitivities of T_mean = ' press_design/view.out ||
  fail "press --design: no sensitivities: $(cat press_design/view.out)"
grep -q 'simulated C_s = ' press_design/view.out || fail "press --design: no simulated check"
# (every parameter: a, b, e, m1, m2, m3, xH, c, k, L0, g)
[[ $(grep -v '^#' press_design/view/loop.csv | head -1 | grep -o 'dT_req/d' | wc -l) -eq 11 ]] ||
  fail "press --design: $(grep -v '^#' press_design/view/loop.csv | head -1)"
same_press press_design_set 0 --rpm 200 --cs 0.02 --samples 720 --no-check --design --set c=650 --set m3=9 \
  --csv loop.csv
cmp -s press_design/view/loop.csv press_design_set/view/loop.csv && fail "press --design --set: the defaults' CSV"
same_press press_plain 0 --rpm 120 --cs 0.05 --samples 360 --no-check --csv loop.csv
grep -q 'dT_req/d' press_plain/view/loop.csv && fail "press without --design: design columns"

[[ $failures -eq 0 ]] && echo "flywheel through the view: the per-model tool's bytes"
exit $((failures > 0))
