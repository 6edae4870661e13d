#!/usr/bin/env bash
# The balancing charts of the README (docs/pictures/fourbar_balancing_*.png): runs
# fourbar_balancing (models/fourbar_balanced.yaml with and without its counterweights over one
# crank revolution at constant speed; it prints the peaks) and tools/plot_balancing.gnuplot.
#   tools/balance_fourbar.sh [build-dir [omega-rad-per-s]]
# Needs the fourbar_balancing tool built (ninja -C build fourbar_balancing) and gnuplot >= 5
# with pngcairo.
set -euo pipefail
build=${1:-build}
omega=${2:-100}
root=$(cd "$(dirname "$0")/.." && pwd)
out="$root/docs/pictures"
mkdir -p "$out"
command -v gnuplot > /dev/null || { echo "balance_fourbar.sh: gnuplot not found" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$build/models/fourbar_balancing" --omega "$omega" "$tmp"
gnuplot -e "dir='$tmp'; pictures='$out'" "$root/tools/plot_balancing.gnuplot"
for f in force moment reactions; do echo "wrote $out/fourbar_balancing_$f.png"; done
