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
#  - what the view does not do yet (flywheel --design, and the flywheel command's --design on
#    this model with a `design` section) is refused: exit 2, one line naming the per-model tool,
#    nothing written; run by mechgen (MECHGEN_VIEW_FALLBACK=1) exit 120, nothing said or written.
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

# What the view does not do yet: --design (the generated DynamicsDesign).
mkdir design && (cd design && "$view_tool" engine "$object" flywheel --design --table "$root/table.csv" \
  --loop l.csv --sweep s.csv --wittenbauer w.csv > ../design.out 2> ../design.err)
status=$?
[[ $status -eq 2 ]] || fail "--design through the view: exit $status, expected 2"
[[ $(wc -l < design.err) -eq 1 ]] || fail "--design: stderr is not one line: $(cat design.err)"
grep -q '^engine_single_engine_view: error: --design: .* not reached through the model view yet; engine_single_engine has it$' \
  design.err || fail "--design: $(cat design.err)"
[[ -z $(ls -A design) && ! -s design.out ]] || fail "--design: something was written"
mkdir fallback && (cd fallback && MECHGEN_VIEW_FALLBACK=1 "$view_tool" engine "$object" flywheel --design \
  --table "$root/table.csv" --loop l.csv > ../fallback.out 2> ../fallback.err)
status=$?
[[ $status -eq 120 ]] || fail "the fallback: exit $status, expected 120"
[[ ! -s fallback.out && ! -s fallback.err && -z $(ls -A fallback) ]] || fail "the fallback said or wrote something"
# the flywheel command's --design alike (engine_single: a model with forces and a design section)
mkdir fw_design && (cd fw_design && "$view_tool" flywheel "$object" --rpm 2000 --design --csv x.csv \
  > ../fw_design.out 2> ../fw_design.err)
status=$?
[[ $status -eq 2 ]] || fail "flywheel --design through the view: exit $status, expected 2: $(cat fw_design.err)"
grep -q '^engine_single_flywheel_view: error: --design: .* not reached through the model view yet; engine_single_flywheel has it$' \
  fw_design.err || fail "flywheel --design: $(cat fw_design.err)"
[[ -z $(ls -A fw_design) && ! -s fw_design.out ]] || fail "flywheel --design: something was written"
# and the per-model tool has it
(cd design && "$fixed_tool" flywheel --design --table "$root/table.csv" --loop l.csv --sweep s.csv \
  --wittenbauer w.csv > ../design_fixed.out 2>&1) || fail "engine_single_engine flywheel --design: $(cat design_fixed.out)"
grep -q 'design sensitivities' design_fixed.out || fail "engine_single_engine --design: no sensitivities"

[[ $failures -eq 0 ]] && echo "engine through the view: the per-model tool's bytes"
exit $((failures > 0))
