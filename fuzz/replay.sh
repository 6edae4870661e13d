#!/usr/bin/env bash
# Replays model files through the mechgen program and fails on anything but a clean exit:
# 0 (valid model) or 1/2 (a message on stderr). A signal (crash, abort, sanitizer), a
# timeout or a silent failure fails the test. Used by the ctests fuzz_regressions (the
# inputs libFuzzer found, fuzz/regressions/) and degenerate_models (fuzz/degenerate/).
#
#   bash fuzz/replay.sh <mechgen> <seconds per file> <memory limit KiB> <file>...
set -uo pipefail
mechgen=$1 seconds=$2 memory=$3
shift 3
failed=0
checked=0
for file in "$@"; do
  [ -f "$file" ] || continue
  checked=$((checked + 1))
  out=$(mktemp -d)
  start=$(date +%s.%N)
  if [ -n "${ASAN_OPTIONS:-}" ]; then
    # AddressSanitizer reserves terabytes of shadow address space, so ulimit -v cannot be
    # used; its own hard RSS limit bounds the memory instead.
    ASAN_OPTIONS="$ASAN_OPTIONS:hard_rss_limit_mb=$((memory / 1024))" \
      timeout "$seconds" "$mechgen" generate "$file" --out-dir "$out" -q \
      >"$out/stdout" 2>"$out/stderr"
  else
    (ulimit -v "$memory"; timeout "$seconds" "$mechgen" generate "$file" --out-dir "$out" -q) \
      >"$out/stdout" 2>"$out/stderr"
  fi
  rc=$?
  elapsed=$(echo "$(date +%s.%N) - $start" | bc)
  message=$(head -c 300 "$out/stderr" | head -n 2)
  case $rc in
    0) echo "ok      ${elapsed}s $file: generated" ;;
    1|2)
      if [ -s "$out/stderr" ]; then
        echo "ok      ${elapsed}s $file: rejected: $message"
      else
        echo "FAIL    $file: exit $rc without a message"; failed=1
      fi ;;
    124) echo "FAIL    $file: no answer within ${seconds}s"; failed=1 ;;
    *) echo "FAIL    $file: exit $rc: $message"; failed=1 ;;
  esac
  rm -rf "$out"
done
echo "$checked file(s) checked"
exit $failed
