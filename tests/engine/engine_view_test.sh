#!/usr/bin/env bash
# mechgen_view engine (issue 43): engine_single compiled into a shared object with its view's
# entry point (tests/runtime's mechgen_view_object()), loaded and run through the machines of the
# runtime compiled once (mechgen_runtime_view: machines/view_machines.h):
#  - each subcommand (cycle with its shaking and rocking couple, flywheel with its shooting and
#    C_s sweep, runup) writes the same CSVs, byte for byte, and the same standard output and
#    standard error as the per-model tool engine_single_engine with the same options, run in a
#    directory of its own (the outputs name the same relative paths);
#  - --set and --params through the view's parameter table: the same bytes as the tool's, and
#    not those of the defaults;
#  - a computation that fails (no flywheel needed) fails alike: exit 1, the same one line;
#  - a usage error the same line (mechgen_view --name: the tool's name in the messages);
#  - flywheel --design (the design sensitivities at the samples, machines/engine/cycle.h's
#    RunCycleDesign through ModelCalls: the view's Design and DynamicsDesign), also with --set
#    and as mechgen runs it (MECHGEN_VIEW_FALLBACK=1: through the view now, no fallback), and its
#    usage error without --table: the tool's bytes; the flywheel command's --design on this model
#    (no per-model flywheel tool to compare with) runs through the view and prints a
#    sensitivity per design parameter.
# usage: engine_view_test.sh <mechgen_view> <engine_single_engine> <engine_single view object>
set -uo pipefail
source "$(dirname "$0")/../view_compare.sh"  # view_tool, fixed_tool, object, fail, $root (entered)
same() { same_as_tool engine_single_engine engine "$@"; }  # same <name> <expected status> <args...>
same cycle 0 cycle --rpm 3000 --samples 720 --csv cycle.csv
[[ $(grep -vc '^#' cycle/view/cycle.csv) -eq 721 ]] || fail "cycle: $(grep -vc '^#' cycle/view/cycle.csv) CSV lines"
grep -q ',shake_F_x,shake_F_y,shake_M,M_rock_x,M_rock_y$' cycle/view/cycle.csv || fail "cycle: no shaking columns"
grep -q 'rocking couple about the cylinders.* primary .* secondary ' cycle/view.out || fail "cycle: no rocking couple"
same flywheel 0 flywheel --rpm 2000 --cs 0.05 --samples 720 --loop loop.csv --sweep sweep.csv --wittenbauer witt.csv
grep -q 'simulated steady cycle' flywheel/view.out || fail "flywheel: no simulated steady cycle: $(cat flywheel/view.out)"
same runup 0 runup --rpm 2000 --idle-rpm 1500 --steady-tol 1e-4 --dt 0.0005 --csv runup.csv
grep -q '^  steady at' runup/view.out || fail "runup: not steady: $(cat runup/view.out)"
# a pressure table instead of the Wiebe cycle
printf 'angle_deg,p_Pa\n0,5e6\n20,4.5e6\n60,2e6\n120,6e5\n180,2e5\n360,0\n540,0\n660,3e5\n700,1.5e6\n' > "$root/table.csv"
same table 0 cycle --samples 360 --table "$root/table.csv" --csv t.csv
# the parameters through the view's table
printf 'm_pis = 0.6  # a heavier piston\nJ_fly: 0.3\n' > "$root/engine.params"
same set 0 cycle --samples 360 --set m_pis=0.6 --set J_fly=0.3 --csv p.csv
same params 0 cycle --samples 360 --params "$root/engine.params" --csv p.csv
cmp -s set/view/p.csv params/view/p.csv || fail "--set and --params: the CSVs differ"
same defaults 0 cycle --samples 360 --csv p.csv
cmp -s set/view/p.csv defaults/view/p.csv && fail "--set: the CSV is the defaults'"
grep -q '^parameters set: m_pis = 0.6 (default ' set/view.out || fail "--set: no 'parameters set' line: $(head -2 set/view.out)"
same set_flywheel 0 flywheel --rpm 1500 --cs 0.03 --samples 360 --set c_load=2 --set J_fly=0.25 \
  --loop l.csv --sweep s.csv --wittenbauer w.csv
# a computation that fails: exit 1, the same line, nothing written
same no_flywheel 1 flywheel --rpm 3000 --cs 0.9 --loop l.csv --sweep s.csv --wittenbauer w.csv
[[ -z $(ls -A no_flywheel/view) ]] || fail "no flywheel: wrote $(ls -A no_flywheel/view)"
[[ $(wc -l < no_flywheel/view.err) -eq 1 ]] || fail "no flywheel: stderr is not one line: $(cat no_flywheel/view.err)"
same bad_set 2 cycle --set nosuch=1 --csv x.csv

# flywheel --design: the sensitivities (the pressure trace of --table held)
same design 0 flywheel --design --table "$root/table.csv" --rpm 2000 --cs 0.05 --samples 720 \
  --loop l.csv --sweep s.csv --wittenbauer w.csv
grep -q '^  design sensitivities (the pressure trace held) of T_mean = ' design/view.out ||
  fail "--design: no sensitivities: $(head -3 design/view.out)"
# (one row per design parameter: r, l, e, m_rod, l_G, J_rod, m_pis)
[[ $(grep -cE '^    (r|l|e|m_rod|l_G|J_rod|m_pis) ' design/view.out) -eq 7 ]] || fail "--design: $(cat design/view.out)"
same design_set 0 flywheel --design --table "$root/table.csv" --rpm 1500 --cs 0.03 --samples 360 \
  --set m_pis=0.6 --set J_rod=0.02 --loop l.csv --sweep s.csv --wittenbauer w.csv
same design_no_table 2 flywheel --design --loop l.csv --sweep s.csv --wittenbauer w.csv
export MECHGEN_VIEW_FALLBACK=1  # (as mechgen runs it: no refusal left to fall back on)
same design_mechgen 0 flywheel --design --table "$root/table.csv" --rpm 2000 --cs 0.05 --samples 360 \
  --loop l.csv --sweep s.csv --wittenbauer w.csv
unset MECHGEN_VIEW_FALLBACK
# the flywheel command's --design on engine_single (a model with forces, dynamics and a design
# section) through the view
mkdir fw_design && (cd fw_design && "$view_tool" flywheel "$object" --rpm 2000 --design --no-check --csv x.csv \
  > ../fw_design.out 2> ../fw_design.err)
status=$?
[[ $status -eq 0 ]] || fail "flywheel --design through the view: exit $status: $(cat fw_design.err)"
[[ ! -s fw_design.err ]] || fail "flywheel --design: stderr $(cat fw_design.err)"
grep -q '^  design sensitivities of T_mean = ' fw_design.out || fail "flywheel --design: $(cat fw_design.out)"
[[ $(grep -v '^#' fw_design/x.csv | head -1 | grep -o 'dT_req/d' | wc -l) -eq 7 ]] ||
  fail "flywheel --design: $(grep -v '^#' fw_design/x.csv | head -1)"

[[ $failures -eq 0 ]] && echo "engine through the view: the per-model tool's bytes"
exit $((failures > 0))
