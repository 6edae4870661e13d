#!/usr/bin/env bash
# A tool's outputs that cannot be written (issue 24): the tool exits 1 with one line on
# stderr naming the path and the reason, and leaves no partial file.
#  - OPTION /dev/full (every write fails with ENOSPC): exit 1, the one line
#    "[<prefix>: ]error: cannot write /dev/full: No space left on device".
#  - OPTION f.out under a file-size limit hit mid-file (as on a nearly full disk: EFBIG):
#    exit 1, "... cannot write f.out: File too large"; the previous f.out stays whole and no
#    temporary file is left beside it.
#  - the standard output on /dev/full: exit 1, "... cannot write the standard output"
#    (with --stdout; tools whose summary is written after their files).
# usage: failed_writes_test.sh [--stdout] OPTION COMMAND [ARGS...]
#   e.g. failed_writes_test.sh --csv ./slider_crank_motor_simulate --t-end 1
set -uo pipefail
check_stdout=0
if [ "$1" = "--stdout" ]; then
  check_stdout=1
  shift
fi
option=$1
shift
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# Exactly one line on stderr, matching the extended regular expression $1 (after an
# optional "<tool>: " prefix).
one_line() {
  local pattern=$1 file=$2 what=$3
  [ "$(grep -c '' "$file")" -eq 1 ] || fail "$what: stderr is not one line: $(cat "$file")"
  grep -Eqx "([a-z_]+: )?$pattern" "$file" || fail "$what: message $(cat "$file")"
}

# /dev/full
mkdir -p "$root/full"
(cd "$root/full" && "$@" "$option" /dev/full > ../full.out 2> ../full.err)
status=$?
[ "$status" -eq 1 ] || fail "/dev/full: exit status $status ($(cat "$root/full.err"))"
one_line "error: cannot write /dev/full: No space left on device" "$root/full.err" "/dev/full"
echo "ok /dev/full: $(cat "$root/full.err")"

# A file-size limit hit mid-file.
dir="$root/limit"
mkdir -p "$dir"
printf 'previous,file\n1,2\n' > "$dir/f.out"
(cd "$dir" && trap '' XFSZ && ulimit -f 16 && "$@" "$option" f.out > ../limit.out 2> ../limit.err)
status=$?
[ "$status" -eq 1 ] || fail "limit: exit status $status ($(cat "$root/limit.err"))"
one_line "error: cannot write f.out: File too large" "$root/limit.err" "limit"
[ "$(cat "$dir/f.out")" = "$(printf 'previous,file\n1,2')" ] || fail "limit: f.out changed"
left=$(cd "$dir" && ls -A | grep -v '^f\.out$' | grep '\.tmp\.' || true)
[ -z "$left" ] || fail "limit: left $left"
echo "ok limit: $(cat "$root/limit.err")"

# The standard output.
if [ "$check_stdout" -eq 1 ]; then
  mkdir -p "$root/stdout"
  (cd "$root/stdout" && "$@" "$option" ok.out > /dev/full 2> ../stdout.err)
  status=$?
  [ "$status" -eq 1 ] || fail "stdout: exit status $status ($(cat "$root/stdout.err"))"
  one_line "error: cannot write the standard output" "$root/stdout.err" "stdout"
  echo "ok stdout: $(cat "$root/stdout.err")"
fi
echo PASS
