#!/usr/bin/env bash
# `mechgen sweep <model.yaml> [sweep options]` (generator/driver/tool_command.cc), run in a
# temporary directory outside the source tree with a private cache (MECHGEN_CACHE_DIR).
# usage: sweep_command_test.sh errors <mechgen> <source dir>
#   a model with an error: its file:line:column line, exit 1, no cache entry, nothing left in
#   the cache's tmp/; no compiler (CXX names none): exit 1, one line naming it; a compile
#   that fails (CXX adds -include of a missing file): exit 1, the compiler's message, no
#   cache entry; no model: a usage error (exit 2, one line); --help and a bad option of sweep and simulate with
#   no compiler on the PATH: answered (0, 2) before anything is generated, no cache; killed by
#   SIGTERM while compiling: no compiler process left, exit status 143, no cache entry.
# usage: sweep_command_test.sh full <mechgen> <source dir> <fourbar_sweep> <fourbar_crossed_sweep>
#   the first run compiles (says so on stderr) and its CSV and SVG are byte-identical to those
#   of build's fourbar_sweep (the Ceres-assembled <model>_sweep) with the same options, the
#   table and summary lines too (only the timing line differs); a second run uses the cache
#   (no "compiling" on stderr, the program's modification time unchanged); the options after
#   the model (or after "--") reach the driver unchanged, its exit status comes back
#   (--steps 0: 2); a cached program truncated or with a byte changed (its recorded size and
#   SHA-256 differ) is said damaged and built again, never run, and so is the CLI11 object;
#   --no-cache leaves no cache; --rebuild compiles again; --mode NAME sweeps a
#   named assembly mode (against fourbar_crossed_sweep), an unknown name is a usage error.
#   The checks above are of the per-model program (MECHGEN_VIEW=0, and what --svg and --mode
#   ask for); then the route through the runtime compiled once (issue 43, mechgen_view): the
#   model alone compiled into a shared object (said on stderr), the CSV, SVG and printed table
#   byte-identical to fourbar_sweep's, a second run and a second option set cached (stderr
#   empty), a damaged object (truncated, one byte changed) said damaged and rebuilt, never
#   loaded, --no-cache and --rebuild, an edited model a new entry whose sweep follows the edit,
#   MECHGEN_VIEW=0 the per-model program again, --design through the view (no fallback, no
#   per-model compile) with fourbar_sweep --design's CSV, and --mode a named assembly mode through the
#   view as fourbar_crossed_sweep sweeps it.
#   In the errors mode, a compile of the model's object that fails: exit 1, the compiler's
#   message, no entry.
set -uo pipefail
mode=$1 mechgen=$(realpath "$2") source_dir=$(realpath "$3")
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
cd "$root" || exit 1
case "$root" in "$source_dir"/*) echo "FAIL: $root is inside the source tree"; exit 1 ;; esac
export MECHGEN_CACHE_DIR=$root/cache
cp "$source_dir/models/fourbar.yaml" fourbar.yaml
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { echo "ok $*"; }
# damage truncate|flip <file> <size>: the file cut to half its size, or one byte changed at the
# same size (only its SHA-256 tells).
damage() {
  if [ "$1" = truncate ]; then
    truncate -s $(($3 / 2)) "$2"
  else
    printf '\x5a' | dd of="$2" bs=1 seek=$(($3 / 3)) conv=notrunc status=none
    [ "$(stat -c %s "$2")" = "$3" ] || fail "$1: the size of $2 changed"
  fi
}
entries() { find "$MECHGEN_CACHE_DIR/sweep" -mindepth 1 -maxdepth 1 -type d ! -name tmp 2>/dev/null | wc -l; }
tmp_left() { find "$MECHGEN_CACHE_DIR/sweep/tmp" -mindepth 1 2>/dev/null | head -3; }

if [ "$mode" = errors ]; then
  # The per-model program's errors (its compile is long enough to be killed in); the view's
  # at the end.
  export MECHGEN_VIEW=0
  # A model with an unknown key on line 3: the generator's one line, exit 1, no entry.
  sed 's/^description: |/descripton: |/' fourbar.yaml > bad.yaml
  "$mechgen" sweep bad.yaml --steps 10 > bad.out 2> bad.err
  status=$?
  [ "$status" -eq 1 ] || fail "bad model: exit status $status, expected 1"
  grep -Eq '^bad\.yaml:3:1: error: .*descripton' bad.err || fail "bad model: stderr $(cat bad.err)"
  [ "$(grep -c '' bad.err)" -eq 1 ] || fail "bad model: more than one line: $(cat bad.err)"
  [ ! -s bad.out ] || fail "bad model: stdout $(cat bad.out)"
  [ "$(entries)" -eq 0 ] || fail "bad model: a cache entry was made"
  [ -z "$(tmp_left)" ] || fail "bad model: left $(tmp_left)"
  [ "$failures" -ne 0 ] || ok "bad model: $(cat bad.err)"

  before=$failures
  CXX=/nonexistent/c++ "$mechgen" sweep fourbar.yaml > nocxx.out 2> nocxx.err
  status=$?
  [ "$status" -eq 1 ] || fail "no compiler: exit status $status"
  grep -Eq "^mechgen: error: no C\+\+ compiler: cannot find '/nonexistent/c\+\+' \(from CXX\)" nocxx.err ||
    fail "no compiler: stderr $(cat nocxx.err)"
  [ "$(entries)" -eq 0 ] || fail "no compiler: a cache entry was made"
  [ "$failures" -ne "$before" ] || ok "no compiler: $(cat nocxx.err)"

  before=$failures
  CXX="c++ -include $root/missing.h" "$mechgen" sweep fourbar.yaml > cc.out 2> cc.err
  status=$?
  [ "$status" -eq 1 ] || fail "failed compile: exit status $status"
  grep -q "^mechgen: error: compiling the sweep command of 'fourbar' failed" cc.err ||
    fail "failed compile: stderr $(cat cc.err)"
  grep -q "missing.h" cc.err || fail "failed compile: the compiler's message is not shown"
  # The first error line comes first, before the compiler's output (issue 25).
  grep -A1 "^the compiler's first error" cc.err | tail -n 1 | grep -q "error:.*missing.h" ||
    fail "failed compile: the first error line is not shown first: $(cat cc.err)"
  [ "$(entries)" -eq 0 ] || fail "failed compile: a cache entry was made"
  [ -z "$(find "$MECHGEN_CACHE_DIR/sweep" -name 'args-*' 2>/dev/null)" ] ||
    fail "failed compile: an args object was cached"
  [ -z "$(tmp_left)" ] || fail "failed compile: left $(tmp_left)"
  [ "$failures" -ne "$before" ] || ok "failed compile"

  # Options are answered by the tool's own parser (runtime/tools/<tool>_args.cc, linked into
  # mechgen) before anything is generated or compiled: with no compiler on the PATH (PATH holds
  # an empty directory, CXX unset) --help exits 0 with the tool's help on stdout and a bad
  # option exits 2 with the tool's one line, and no cache is made. A check that needs the
  # model (a --drive of an input the model may lack) is the tool's: it goes on to the compile,
  # which then finds no compiler.
  before=$failures
  mkdir -p empty_bin
  cp "$source_dir/models/slider_crank_motor.yaml" motor.yaml
  bare() { env -u CXX PATH="$root/empty_bin" MECHGEN_CACHE_DIR="$root/cache_options" "$mechgen" "$@"; }
  bare sweep fourbar.yaml --help > help.out 2> help.err
  status=$?
  [ "$status" -eq 0 ] || fail "sweep --help without a compiler: exit status $status: $(cat help.err)"
  grep -q "^Usage: mechgen sweep fourbar.yaml \[OPTIONS\]" help.out && grep -q -- "--no-animation" help.out &&
    grep -q "the mechgen model 'fourbar'" help.out || fail "sweep --help: not the sweep's help: $(head -5 help.out)"
  [ ! -s help.err ] || fail "sweep --help: stderr $(cat help.err)"
  bare simulate motor.yaml --help > shelp.out 2> shelp.err
  status=$?
  { [ "$status" -eq 0 ] && grep -q -- "--drive" shelp.out && grep -q "the mechgen model 'motor'" shelp.out &&
    [ ! -s shelp.err ]; } || fail "simulate --help without a compiler: exit status $status: $(cat shelp.err)"
  bare simulate motor.yaml --t-end 1 --bad-option > opt.out 2> opt.err
  status=$?
  [ "$status" -eq 2 ] || fail "simulate --bad-option: exit status $status, expected 2"
  [ "$(cat opt.err)" = "mechgen simulate: error: The following argument was not expected: --bad-option" ] ||
    fail "simulate --bad-option: stderr $(cat opt.err)"
  [ ! -s opt.out ] || fail "simulate --bad-option: stdout $(cat opt.out)"
  bare simulate motor.yaml --dt 0 > dt.out 2> dt.err
  status=$?
  { [ "$status" -eq 2 ] && [ "$(cat dt.err)" = "mechgen simulate: error: --dt: bad value '0': expected a number in (0, 1e+06]" ]; } ||
    fail "simulate --dt 0: exit status $status, stderr $(cat dt.err)"
  cp "$source_dir/models/slider_crank_friction.yaml" friction.yaml
  bare statics friction.yaml --help > sthelp.out 2> sthelp.err
  status=$?
  { [ "$status" -eq 0 ] && grep -q -- "--dead-zones" sthelp.out && grep -q "the mechgen model 'friction'" sthelp.out &&
    [ ! -s sthelp.err ]; } || fail "statics --help without a compiler: exit status $status: $(cat sthelp.err)"
  bare statics friction.yaml --speed abc > sp.out 2> sp.err
  status=$?
  { [ "$status" -eq 2 ] && grep -q "^mechgen statics: error: --speed: bad value 'abc'" sp.err &&
    [ "$(wc -l < sp.err)" -eq 1 ] && [ ! -s sp.out ]; } ||
    fail "statics --speed abc: exit status $status, stderr $(cat sp.err)"
  cp "$source_dir/models/engine_single.yaml" engine.yaml
  for cmd in "engine engine.yaml" "flywheel friction.yaml" "study fourbar.yaml" "synthesize fourbar.yaml"; do
    tool=${cmd%% *}
    bare $cmd --help > th.out 2> th.err
    status=$?
    { [ "$status" -eq 0 ] && grep -q "^Usage: mechgen $cmd \[OPTIONS\]" th.out && [ ! -s th.err ]; } ||
      fail "$tool --help without a compiler: exit status $status: $(head -2 th.out) $(cat th.err)"
  done
  for cmd in "engine engine.yaml flywheel" "flywheel friction.yaml"; do
    tool=${cmd%% *}
    bare $cmd --cs 1e-300 > cs.out 2> cs.err
    status=$?
    { [ "$status" -eq 2 ] && grep -q "^mechgen $tool: error: --cs: bad value '1e-300'" cs.err &&
      [ "$(wc -l < cs.err)" -eq 1 ] && [ ! -s cs.out ]; } ||
      fail "$tool --cs 1e-300 without a compiler: exit status $status, stderr $(cat cs.err)"
  done
  # A directory where the model (or the task or study file that names it) goes: one line, no
  # cache made (checked below).
  mkdir -p a_dir
  for cmd in "synthesize a_dir --task a_dir" "study a_dir --study a_dir" "sweep a_dir"; do
    MECHGEN_CACHE_DIR="$root/cache_options" "$mechgen" $cmd > d.out 2> d.err
    status=$?
    { [ "$status" -eq 1 ] && [ "$(cat d.err)" = "a_dir: error: the path is a directory, not a model file; give the path of a .yaml file" ]; } ||
      fail "mechgen $cmd: exit status $status, stderr $(cat d.err)"
  done
  bare synthesize fourbar.yaml --task t.yaml --seed -1 > sy.out 2> sy.err
  status=$?
  { [ "$status" -eq 2 ] && grep -q "^mechgen synthesize: error: --seed: bad value '-1'" sy.err && [ ! -s sy.out ]; } ||
    fail "synthesize --seed -1 without a compiler: exit status $status, stderr $(cat sy.err)"
  bare sweep fourbar.yaml --steps 0 > st.out 2> st.err
  status=$?
  { [ "$status" -eq 2 ] &&
    [ "$(cat st.err)" = "mechgen sweep: error: --steps: bad value '0': expected an integer from 1 to 10000000" ]; } ||
    fail "sweep --steps 0: exit status $status, stderr $(cat st.err)"
  [ ! -e "$root/cache_options" ] || fail "the options made a cache: $(find "$root/cache_options" | head -3)"
  bare simulate motor.yaml --drive no_such_input=speed:1 > drive.out 2> drive.err
  status=$?
  { [ "$status" -eq 1 ] && grep -q "^mechgen: error: no C++ compiler" drive.err; } ||
    fail "a --drive the parser cannot judge: exit status $status, stderr $(cat drive.err)"
  [ "$failures" -ne "$before" ] || ok "--help and a bad option answered with no compiler and no cache"

  # Killed while it compiles (issue 45): SIGTERM after a second of the compile ends every
  # compiler process (each runs in a process group of its own, which mechgen kills and waits
  # for), removes the temporary build directory and ends by the signal (status 143), with no
  # cache entry. mechgen runs in a session of its own (setsid) so that every process it
  # started, and what they started, is found by its session id in /proc.
  before=$failures
  session() {  # "<pid> <name>" of each process of session $1
    local f line rest
    for f in /proc/[0-9]*/stat; do
      line=$(cat "$f" 2> /dev/null) || continue
      rest=${line##*) }
      read -r _ _ _ sid _ <<< "$rest"
      [ "$sid" = "$1" ] || continue
      name=${line#*(}
      echo "${f//[^0-9]/} ${name%%)*}"
    done
  }
  export MECHGEN_CACHE_DIR=$root/cache_killed
  setsid "$mechgen" sweep fourbar.yaml --steps 4 > killed.out 2> killed.err &
  pid=$!
  for _ in $(seq 1 600); do
    grep -q "^mechgen: compiling" killed.err && break
    sleep 0.1
  done
  sleep 1
  line=$(cat "/proc/$pid/stat" 2> /dev/null)
  read -r _ _ _ sid _ <<< "${line##*) }"
  [ "${sid:-}" = "$pid" ] || fail "SIGTERM: mechgen ($pid) is not the leader of its own session (session ${sid:-none})"
  compilers=$(session "$pid" | grep -c "cc1plus")
  [ "$compilers" -ge 1 ] || fail "SIGTERM: no compiler running after a second of the compile: $(session "$pid") $(cat killed.err)"
  kill -TERM "$pid"
  wait "$pid"
  status=$?
  [ "$status" -eq 143 ] || fail "SIGTERM: exit status $status, expected 143 (128 + SIGTERM): $(cat killed.err)"
  sleep 2
  [ -z "$(session "$pid")" ] || fail "SIGTERM: 2 s later still running: $(session "$pid" | tr '\n' ' ')"
  [ "$(entries)" -eq 0 ] || fail "SIGTERM: a cache entry was made"
  [ -z "$(tmp_left)" ] || fail "SIGTERM: left $(tmp_left)"
  [ -z "$(find "$MECHGEN_CACHE_DIR/sweep" -name 'args-*' 2> /dev/null)" ] || fail "SIGTERM: an args object was cached"
  [ "$failures" -ne "$before" ] || ok "SIGTERM while compiling: $compilers compiler(s) ended, exit status 143, no cache entry"

  # The model's object for the runtime compiled once: a failed compile is said, no entry.
  before=$failures
  export MECHGEN_CACHE_DIR=$root/cache_view
  CXX="c++ -include $root/missing.h" MECHGEN_VIEW=1 "$mechgen" sweep fourbar.yaml > vcc.out 2> vcc.err
  status=$?
  [ "$status" -eq 1 ] || fail "view, failed compile: exit status $status"
  grep -q "^mechgen: error: compiling the model 'fourbar' failed" vcc.err || fail "view, failed compile: stderr $(cat vcc.err)"
  grep -q "missing.h" vcc.err || fail "view, failed compile: the compiler's message is not shown"
  [ -z "$(find "$MECHGEN_CACHE_DIR/view" -mindepth 1 -maxdepth 1 -type d ! -name tmp 2> /dev/null)" ] ||
    fail "view, failed compile: an entry was made"
  [ -z "$(find "$MECHGEN_CACHE_DIR/view/tmp" -mindepth 1 2> /dev/null | head -3)" ] || fail "view, failed compile: left files in tmp/"
  [ "$failures" -ne "$before" ] || ok "view: a failed compile of the model's object"

  before=$failures
  "$mechgen" sweep > nomodel.out 2> nomodel.err
  status=$?
  [ "$status" -eq 2 ] || fail "no model: exit status $status, expected 2"
  [ "$(cat nomodel.err)" = "mechgen: error: model is required" ] || fail "no model: stderr $(cat nomodel.err)"
  [ "$failures" -ne "$before" ] || ok "no model: exit status $status"
  exit $((failures > 0))
fi

[ "$mode" = full ] || { echo "unknown mode $mode"; exit 2; }
tool=$(realpath "$4")
export MECHGEN_VIEW=0  # the per-model program first; the view's route at the end
options=(--steps 360 --qd 2 --range theta_crank:10deg:370deg --table 9)
mkdir -p a b
(cd a && "$mechgen" sweep ../fourbar.yaml "${options[@]}" --csv out.csv --svg out.svg > ../a.out 2> ../a.err)
status=$?
[ "$status" -eq 0 ] || fail "first run: exit status $status: $(cat a.err)"
grep -q "^mechgen: compiling the sweep command of 'fourbar'" a.err || fail "first run: no compile message: $(cat a.err)"
(cd b && "$tool" "${options[@]}" --csv out.csv --svg out.svg > ../b.out 2> ../b.err)
[ $? -eq 0 ] || fail "fourbar_sweep: $(cat b.err)"
cmp a/out.csv b/out.csv || fail "the CSV differs from fourbar_sweep's"
cmp a/out.svg b/out.svg || fail "the SVG differs from fourbar_sweep's"
[ "$(grep -vc '^#' a/out.csv)" -eq 362 ] || fail "the CSV has $(grep -vc '^#' a/out.csv) lines, expected 362"
# stdout: the same but for the timing line.
diff <(grep -v '^time per row:' a.out) <(grep -v '^time per row:' b.out) > stdout.diff ||
  fail "stdout differs from fourbar_sweep's: $(head -20 stdout.diff)"
grep -q '^time per row: .* us solving' a.out || fail "no timing line: $(cat a.out)"
[ "$failures" -ne 0 ] || ok "first run: the same CSV, SVG and table as fourbar_sweep"

before=$failures
program=$(find "$MECHGEN_CACHE_DIR/sweep" -mindepth 2 -maxdepth 2 -name sweep -type f)
[ "$(printf '%s\n' "$program" | grep -c .)" -eq 1 ] || fail "expected one cached program: $program"
[ "$(entries)" -eq 1 ] || fail "expected one cache entry, found $(entries)"
[ -z "$(tmp_left)" ] || fail "left in tmp/: $(tmp_left)"
stamp=$(stat -c %Y.%i "$program")
sleep 1
(cd a && "$mechgen" sweep ../fourbar.yaml "${options[@]}" --csv again.csv > ../c.out 2> ../c.err)
status=$?
[ "$status" -eq 0 ] || fail "second run: exit status $status: $(cat c.err)"
[ ! -s c.err ] || fail "second run: stderr $(cat c.err)"
[ "$(stat -c %Y.%i "$program")" = "$stamp" ] || fail "second run: the program was built again"
cmp a/again.csv b/out.csv || fail "second run: the CSV differs"
[ "$failures" -ne "$before" ] || ok "second run: cached"

before=$failures
# A damaged entry is built again, never run: the program truncated (it segfaulted when run),
# then overwritten with one byte changed at the same size (only the SHA-256 tells).
size=$(stat -c %s "$program")
read -r recorded_size recorded_hash < "$program.sha256" || fail "no record beside $program"
[ "$recorded_size" = "$size" ] || fail "the record's size $recorded_size is not the program's $size"
[ "$recorded_hash" = "$(sha256sum "$program" | cut -d' ' -f1)" ] || fail "the record's SHA-256 is not sha256sum's"
for damage in truncate flip; do
  damage "$damage" "$program" "$size"
  (cd a && "$mechgen" sweep ../fourbar.yaml "${options[@]}" --csv damaged.csv > ../t.out 2> ../t.err)
  status=$?
  [ "$status" -eq 0 ] || fail "$damage: exit status $status: $(cat t.err)"
  grep -q "^mechgen: the cached sweep command .* is damaged" t.err || fail "$damage: not said damaged: $(cat t.err)"
  grep -q "^mechgen: compiling the sweep command of 'fourbar'" t.err || fail "$damage: not built again: $(cat t.err)"
  cmp a/damaged.csv b/out.csv || fail "$damage: the CSV differs from fourbar_sweep's"
  [ "$(stat -c %s "$program")" = "$size" ] || fail "$damage: the rebuilt program is $(stat -c %s "$program") bytes"
  [ "$(entries)" -eq 1 ] || fail "$damage: $(entries) entries"
  [ -z "$(tmp_left)" ] || fail "$damage: left $(tmp_left)"
done
# The rebuilt entry is used as it is.
(cd a && "$mechgen" sweep ../fourbar.yaml --steps 4 --table 0 > ../u.out 2> ../u.err) || fail "after rebuild: $(cat u.err)"
[ ! -s u.err ] || fail "after rebuild: stderr $(cat u.err)"
# A damaged CLI11 object is compiled again (its record says so), not linked. The run is also the
# check of --rebuild: the program's entry is sound (rebuilt above, used as it is), so only
# --rebuild makes it compile, into the one entry, nothing left in tmp/ (one per-model compile
# for both checks).
args_object=$(find "$MECHGEN_CACHE_DIR/sweep" -maxdepth 1 -name 'args-*.o')
[ -n "$args_object" ] && [ -s "$args_object.sha256" ] || fail "no args object with its record: $args_object"
truncate -s 100 "$args_object"
"$mechgen" sweep --rebuild fourbar.yaml --steps 4 --table 0 > w.out 2> w.err || fail "damaged args object: $(cat w.err)"
grep -q "^mechgen: the cached object .*args-.* is damaged" w.err || fail "damaged args object: $(cat w.err)"
[ "$(stat -c %s "$args_object")" -gt 100 ] || fail "the args object was not replaced"
grep -q "^mechgen: compiling" w.err || fail "--rebuild did not compile: $(cat w.err)"
[ "$(entries)" -eq 1 ] || fail "--rebuild: $(entries) entries"
[ -z "$(tmp_left)" ] || fail "--rebuild left $(tmp_left)"
[ "$failures" -ne "$before" ] || ok "a damaged entry (truncated, one byte changed) is rebuilt, not run"

before=$failures
# Options after the model reach the driver as they are; "--" after the model is dropped;
# the driver's exit status comes back.
(cd a && "$mechgen" sweep ../fourbar.yaml -- --steps 4 --table 5 > ../d.out 2> ../d.err)
[ $? -eq 0 ] || fail "after --: $(cat d.err)"
[ "$(grep -Ec '^ +(0|90|180|270|360)\.0000 ' d.out)" -eq 5 ] || fail "--table 5 of 4 steps: $(cat d.out)"
"$mechgen" sweep fourbar.yaml --steps 0 > e.out 2> e.err
status=$?
[ "$status" -eq 2 ] || fail "--steps 0: exit status $status"
grep -qx "mechgen sweep: error: --steps: bad value '0': expected an integer from 1 to 10000000" e.err ||
  fail "--steps 0: $(cat e.err)"
"$mechgen" sweep fourbar.yaml --help > h.out 2>&1 || fail "--help: exit status $?"
grep -q -- "--no-animation" h.out || fail "--help is not the driver's: $(head -5 h.out)"
# mechgen's own options before the model: --verbose says where the cache is.
"$mechgen" sweep --verbose fourbar.yaml --steps 4 --table 0 > v.out 2> v.err || fail "--verbose: $(cat v.err)"
grep -q "^mechgen: cache $MECHGEN_CACHE_DIR" v.err || fail "--verbose: $(cat v.err)"
[ "$failures" -ne "$before" ] || ok "arguments pass through"

before=$failures
MECHGEN_CACHE_DIR=$root/nocache "$mechgen" sweep --no-cache fourbar.yaml --steps 36 --csv n.csv > n.out 2> n.err
[ $? -eq 0 ] || fail "--no-cache: $(cat n.err)"
[ ! -e "$root/nocache" ] || fail "--no-cache made a cache"
[ "$(grep -vc '^#' n.csv)" -eq 38 ] || fail "--no-cache: the CSV has $(grep -vc '^#' n.csv) lines"
[ "$failures" -ne "$before" ] || ok "--no-cache (--rebuild: with the damaged CLI11 object above)"

# Named assembly modes: tests/kinematics/models/fourbar_named_modes.yaml is models/fourbar.yaml
# with its two modes named; --mode crossed sweeps what the shipped fourbar_crossed_sweep does
# (the same links assembled crossed): the same CSV. An unknown name is a usage error listing
# the model's modes; --mode on a model without named modes says so.
before=$failures
crossed_tool=$(realpath "$5")
cp "$source_dir/tests/kinematics/models/fourbar_named_modes.yaml" named.yaml
mkdir -p m
"$mechgen" sweep named.yaml --mode crossed --steps 72 --csv m/named.csv --table 0 > m.out 2> m.err
[ $? -eq 0 ] || fail "--mode crossed: $(cat m.err)"
(cd m && "$crossed_tool" --steps 72 --csv crossed.csv --table 0 > ../mc.out 2> ../mc.err) ||
  fail "fourbar_crossed_sweep: $(cat mc.err)"
# The same CSV but for its first comment line, which names the model that wrote it.
cmp <(tail -n +2 m/named.csv) <(tail -n +2 m/crossed.csv) ||
  fail "--mode crossed: the CSV differs from fourbar_crossed_sweep's"
head -n 1 m/named.csv | grep -q '^# fourbar_named_modes_sweep, model fourbar_named_modes: ' ||
  fail "--mode crossed: first line $(head -n 1 m/named.csv)"
head -n 1 m/crossed.csv | grep -q '^# fourbar_crossed_sweep, model fourbar_crossed: ' ||
  fail "fourbar_crossed_sweep: first line $(head -n 1 m/crossed.csv)"
"$mechgen" sweep named.yaml --mode open --steps 72 --csv m/open.csv --table 0 > mo.out 2> mo.err ||
  fail "--mode open: $(cat mo.err)"
cmp -s m/open.csv m/named.csv && fail "--mode open gave the crossed CSV"
"$mechgen" sweep named.yaml --mode inverted --steps 4 > mu.out 2> mu.err
status=$?
{ [ "$status" -eq 2 ] && grep -q "no assembly mode 'inverted' (its modes: open, crossed)" mu.err; } ||
  fail "--mode inverted: exit status $status, $(cat mu.err)"
"$mechgen" sweep fourbar.yaml --mode crossed --steps 4 > mn.out 2> mn.err
status=$?
{ [ "$status" -eq 2 ] && grep -q "names no assembly modes" mn.err; } ||
  fail "--mode on fourbar: exit status $status, $(cat mn.err)"
[ "$failures" -ne "$before" ] || ok "--mode: a named assembly mode, by name"

# ---- through the runtime compiled once (mechgen_view) ----
unset MECHGEN_VIEW
export MECHGEN_CACHE_DIR=$root/cache_view
view_entries() { find "$MECHGEN_CACHE_DIR/view" -mindepth 1 -maxdepth 1 -type d ! -name tmp 2>/dev/null | wc -l; }
view_options=(--steps 360 --qd 2 --range theta_crank:10deg:370deg --table 9)
before=$failures
mkdir -p v
(cd v && "$mechgen" sweep ../fourbar.yaml "${view_options[@]}" --csv out.csv --svg out.svg > ../va.out 2> ../va.err)
status=$?
[ "$status" -eq 0 ] || fail "view: first run: exit status $status: $(cat va.err)"
grep -q "^mechgen: compiling the model 'fourbar' (.*the runtime is compiled once" va.err || fail "view: first run: $(cat va.err)"
[ -z "$(find "$MECHGEN_CACHE_DIR" -path '*/sweep/*' 2> /dev/null | head -1)" ] || fail "view: the per-model program was built"
(cd v && "$tool" "${view_options[@]}" --csv fixed.csv --svg fixed.svg > ../vb.out 2> ../vb.err) || fail "fourbar_sweep: $(cat vb.err)"
cmp v/out.csv v/fixed.csv || fail "view: the CSV differs from fourbar_sweep's"
cmp v/out.svg v/fixed.svg || fail "view: the SVG differs from fourbar_sweep's"
diff <(grep -v '^time per row:' va.out) <(grep -v '^time per row:' vb.out | sed 's/fixed\.\(csv\|svg\)/out.\1/') > vstdout.diff ||
  fail "view: stdout differs from fourbar_sweep's: $(head -20 vstdout.diff)"
object=$(find "$MECHGEN_CACHE_DIR/view" -mindepth 2 -maxdepth 2 -name model.so -type f)
[ "$(printf '%s\n' "$object" | grep -c .)" -eq 1 ] || fail "view: expected one object: $object"
stamp=$(stat -c %Y.%i "$object")
sleep 1
(cd v && "$mechgen" sweep ../fourbar.yaml --steps 90 --set b=3.6 --csv second.csv > ../vc.out 2> ../vc.err)
[ $? -eq 0 ] || fail "view: second run: $(cat vc.err)"
[ ! -s vc.err ] || fail "view: second run (other options): stderr $(cat vc.err)"
[ "$(stat -c %Y.%i "$object")" = "$stamp" ] || fail "view: second run: the object was built again"
(cd v && "$tool" --steps 90 --set b=3.6 --csv second_fixed.csv > /dev/null) || fail "fourbar_sweep --set"
cmp v/second.csv v/second_fixed.csv || fail "view: --set b=3.6: the CSV differs from fourbar_sweep's"
[ "$failures" -ne "$before" ] || ok "view: the model's object compiled once, its CSV and table fourbar_sweep's, cached"

before=$failures
size=$(stat -c %s "$object")
read -r recorded_size _ < "$object.sha256" || fail "view: no record beside $object"
[ "$recorded_size" = "$size" ] || fail "view: the record's size $recorded_size is not the object's $size"
for damage in truncate flip; do
  damage "$damage" "$object" "$size"
  (cd v && "$mechgen" sweep ../fourbar.yaml "${view_options[@]}" --csv damaged.csv > ../vt.out 2> ../vt.err)
  status=$?
  [ "$status" -eq 0 ] || fail "view, $damage: exit status $status: $(cat vt.err)"
  grep -q "^mechgen: the cached model object .*model.so is damaged" vt.err || fail "view, $damage: not said damaged: $(cat vt.err)"
  grep -q "^mechgen: compiling the model 'fourbar'" vt.err || fail "view, $damage: not built again: $(cat vt.err)"
  cmp v/damaged.csv v/fixed.csv || fail "view, $damage: the CSV differs"
  [ "$(view_entries)" -eq 1 ] || fail "view, $damage: $(view_entries) entries"
done
[ "$failures" -ne "$before" ] || ok "view: a damaged object (truncated, one byte changed) is rebuilt, not loaded"

before=$failures
MECHGEN_CACHE_DIR=$root/nocache_view "$mechgen" sweep --no-cache fourbar.yaml --steps 36 --csv vn.csv > vn.out 2> vn.err
[ $? -eq 0 ] || fail "view --no-cache: $(cat vn.err)"
[ ! -e "$root/nocache_view" ] || fail "view --no-cache made a cache"
[ "$(grep -vc '^#' vn.csv)" -eq 38 ] || fail "view --no-cache: the CSV has $(grep -vc '^#' vn.csv) lines"
"$mechgen" sweep --rebuild fourbar.yaml --steps 4 --table 0 > vr.out 2> vr.err || fail "view --rebuild: $(cat vr.err)"
grep -q "^mechgen: compiling the model" vr.err || fail "view --rebuild did not compile: $(cat vr.err)"
[ "$(view_entries)" -eq 1 ] || fail "view --rebuild: $(view_entries) entries"
# An edited model is a new one: the crank made longer, the sweep follows (as --set does).
sed 's/^  a:   {value: 1.0,/  a:   {value: 1.1,/' fourbar.yaml > edited.yaml
grep -q "value: 1.1" edited.yaml || fail "the edit of fourbar.yaml did not apply"
"$mechgen" sweep edited.yaml --steps 36 --table 0 --csv ve.csv > ve.out 2> ve.err || fail "edited: $(cat ve.err)"
grep -q "^mechgen: compiling the model 'fourbar'" ve.err || fail "edited: not compiled: $(cat ve.err)"
[ "$(view_entries)" -eq 2 ] || fail "edited: $(view_entries) entries, expected 2"
"$tool" --steps 36 --table 0 --set a=1.1 --csv ve_fixed.csv > /dev/null || fail "fourbar_sweep --set a=1.1"
cmp <(grep -v '^#' ve.csv) <(grep -v '^#' ve_fixed.csv) || fail "edited: the rows differ from fourbar_sweep --set a=1.1's"
# MECHGEN_VIEW=0: the per-model program (cached above).
MECHGEN_VIEW=0 MECHGEN_CACHE_DIR=$root/cache "$mechgen" sweep fourbar.yaml "${view_options[@]}" --csv v/per_model.csv > vp.out 2> vp.err ||
  fail "MECHGEN_VIEW=0: $(cat vp.err)"
cmp v/per_model.csv v/fixed.csv || fail "MECHGEN_VIEW=0: the CSV differs"
# --design (the design derivatives) goes through the view too: no fallback to the per-model
# program (which the per-model checks above cached in $root/cache), none compiled, the answer
# fourbar_sweep's.
MECHGEN_CACHE_DIR=$root/cache "$mechgen" sweep --verbose fourbar.yaml --design --steps 8 --table 0 --csv v/design.csv > vd.out 2> vd.err ||
  fail "view, --design: $(cat vd.err)"
grep -q "not through the model view" vd.err && fail "view, --design: fell back to the per-model program: $(cat vd.err)"
grep -q "^mechgen: compiling the sweep command" vd.err && fail "view, --design: the per-model program was compiled: $(cat vd.err)"
(cd v && "$tool" --design --steps 8 --table 0 --csv design_fixed.csv > /dev/null) || fail "fourbar_sweep --design"
cmp v/design.csv v/design_fixed.csv || fail "view, --design: the CSV differs from fourbar_sweep's"
# Named assembly modes through the view: --mode crossed sweeps what fourbar_crossed_sweep does.
"$mechgen" sweep named.yaml --mode crossed --steps 72 --csv m/view_named.csv --table 0 > vm.out 2> vm.err ||
  fail "view --mode crossed: $(cat vm.err)"
grep -q "^mechgen: compiling the model 'fourbar_named_modes'" vm.err || fail "view --mode crossed: not through the view: $(cat vm.err)"
cmp <(tail -n +2 m/view_named.csv) <(tail -n +2 m/crossed.csv) || fail "view --mode crossed: the CSV differs from fourbar_crossed_sweep's"
"$mechgen" sweep named.yaml --mode inverted --steps 4 > vmu.out 2> vmu.err
status=$?
{ [ "$status" -eq 2 ] && grep -q "no assembly mode 'inverted' (its modes: open, crossed)" vmu.err; } ||
  fail "view --mode inverted: exit status $status, $(cat vmu.err)"
[ "$failures" -ne "$before" ] || ok "view: --no-cache, --rebuild, an edited model, MECHGEN_VIEW=0, --mode"
exit $((failures > 0))
