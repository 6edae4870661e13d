#!/usr/bin/env bash
# The output layers include only lower ones (issue 24): table/ (the column table) the
# standard library alone; io/ (CSV writer, printed table, SVG, output files) table/, core/
# and itself, never sweep/, statics/, dynamics/ or the machines that declare columns.
# usage: io_layering_test.sh <runtime/include/mechgen>
set -uo pipefail
root=$1
status=0
check() {  # <folder> <allowed include prefixes, a regex>
  local folder=$1 allowed=$2 header line
  for header in "$root/$folder"/*.h; do
    while IFS= read -r line; do
      if ! [[ $line =~ ^#include\ \"mechgen/($allowed)/ ]]; then
        echo "FAIL: $folder/$(basename "$header") includes a higher layer: $line"
        status=1
      fi
    done < <(grep -E '^#include "mechgen/' "$header")
  done
}
[ -d "$root/table" ] && [ -d "$root/io" ] || { echo "FAIL: no $root/table or $root/io"; exit 1; }
check table 'table'
check io 'core|table|io'
[ "$status" -eq 0 ] && echo PASS
exit "$status"
