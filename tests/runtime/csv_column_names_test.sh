#!/usr/bin/env bash
# CSV column names unique by construction (issue 12): models whose coordinate names would
# give the sweep's CSV two equal columns are refused by `mechgen generate` with one line
# `file:line:column: error: ...; rename ...` pointing at the link to rename, exit status 1,
# and nothing written; near misses are accepted.
# usage: csv_column_names_test.sh <mechgen> <templates dir> <models/fourbar.yaml>
set -uo pipefail
mechgen=$1 templates=$2 fourbar=$3
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# refused <name> <new coupler name> <column> <line of the coupler's definition>
refused() {
  local name=$1 coupler=$2 column=$3
  local model="$root/$name.yaml"
  sed "s/coupler/$coupler/g" "$fourbar" > "$model"
  local line
  line=$(grep -n "^  $coupler:" "$model" | cut -d: -f1)
  "$mechgen" generate "$model" --out-dir "$root/out_$name" --templates "$templates" \
    > "$root/$name.out" 2> "$root/$name.err"
  local status=$?
  local err
  err=$(cat "$root/$name.err")
  [ "$status" -eq 1 ] || fail "$name: exit status $status"
  [ "$(printf '%s' "$err" | grep -c '')" -eq 1 ] || fail "$name: not one line: $err"
  printf '%s\n' "$err" | grep -Eqx "$model:$line:3: error: the sweep's CSV would have two columns named '$column' \(.*\); rename link '$coupler' .*" \
    || fail "$name: message $err"
  [ ! -e "$root/out_$name" ] || fail "$name: wrote $root/out_$name"
  [ ! -s "$root/$name.out" ] || fail "$name: stdout $(cat "$root/$name.out")"
  echo "ok $name: $err"
}
refused velocity rocker_dot theta_rocker_dot
refused acceleration rocker_ddot theta_rocker_ddot
refused crank_velocity crank_dot theta_crank_dot

# Near misses: accepted.
for coupler in rocker_dots dot_rocker rocker_dotdot; do
  sed "s/coupler/$coupler/g" "$fourbar" > "$root/$coupler.yaml"
  "$mechgen" generate "$root/$coupler.yaml" --out-dir "$root/ok_$coupler" --templates "$templates" \
    > /dev/null 2> "$root/$coupler.err" || fail "$coupler refused: $(cat "$root/$coupler.err")"
done
[ "$failures" -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
echo PASS
