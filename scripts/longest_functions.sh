#!/usr/bin/env bash
# The longest functions of the given C++ files (by universal-ctags' start and end lines), the
# figure issue 46 bounds for runtime/include/mechgen/dynamics/ (no function over ~100 lines).
# usage: bash scripts/longest_functions.sh [count] FILE...   (e.g. 8 runtime/include/mechgen/dynamics/*.h
#        runtime/include/mechgen/dynamics/witness/*.h); needs universal-ctags (Debian: universal-ctags).
set -euo pipefail
count=8
if [[ ${1:-} =~ ^[0-9]+$ ]]; then count=$1; shift; fi
ctags-universal --language-force=C++ --kinds-C++=f --fields=+ne -o - "$@" |
  awk -F'\t' '{line = ""; end = ""
               for (i = 4; i <= NF; i++) { if ($i ~ /^line:/) line = substr($i, 6); if ($i ~ /^end:/) end = substr($i, 5) }
               if (end != "") printf "%5d %s:%s %s\n", end - line + 1, $2, line, $1}' |
  sort -rn | head -n "$count"
