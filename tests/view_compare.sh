# Sourced by the view tests of tests/engine and tests/flywheel: one comparison of a per-model
# tool and mechgen_view running the same command on the model's object.
# same_as_tool <tool's name> <view command> <case name> <expected status> <args...>: both run in
# a directory of their own with the same arguments (mechgen_view --name: the tool's name in the
# messages); the exit statuses, every file written, stdout and stderr compared byte for byte.
# Reads $fixed_tool, $view_tool and $object; calls fail() on each difference.
#
# Sourced with the test's arguments <mechgen_view> <per-model tool> <view object>: sets
# view_tool, fixed_tool and object, counts failures in $failures (fail <message>), and enters a
# temporary directory $root, removed on exit.
view_tool=$(realpath "$1") fixed_tool=$(realpath "$2") object=$(realpath "$3")
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
cd "$root" || exit 1

same_as_tool() {
  local tool=$1 command=$2 name=$3 expected=$4
  shift 4
  mkdir -p "$name/fixed" "$name/view"
  (cd "$name/fixed" && "$fixed_tool" "$@" > ../fixed.out 2> ../fixed.err)
  local fixed_status=$?
  (cd "$name/view" && "$view_tool" --name "$tool" "$command" "$object" "$@" > ../view.out 2> ../view.err)
  local view_status=$?
  [[ $fixed_status -eq $expected ]] || fail "$name: $tool exited $fixed_status: $(head -3 "$name/fixed.err")"
  [[ $view_status -eq $fixed_status ]] ||
    fail "$name: mechgen_view $command exited $view_status, the tool $fixed_status: $(head -3 "$name/view.err")"
  diff -r "$name/fixed" "$name/view" > /dev/null || fail "$name: the files differ: $(diff -r "$name/fixed" "$name/view" | head -4)"
  cmp -s "$name/fixed.out" "$name/view.out" || fail "$name: stdout differs: $(diff "$name/fixed.out" "$name/view.out" | head -6)"
  cmp -s "$name/fixed.err" "$name/view.err" || fail "$name: stderr differs: $(diff "$name/fixed.err" "$name/view.err" | head -4)"
}
