#!/usr/bin/env bash
# Prints a model of N four-bar loops in series (loop i's rocker is loop i+1's crank) for
# scaling tests and benchmarks:  tools/make_chain.sh N [order [output.yaml]] > chain_N.yaml
# Every loop is the shipped crank-rocker (a = 1, b = 3.5, c = 3, d = 4): loop 1 is driven
# by the crank at O0 = (0, 0); loop i has its rocker pivoted at Oi = (4 i, 0) and carries,
# at distance a from its pivot, the crank pin of loop i + 1. Each rocker swings through
# about 60 degrees, and a crank-rocker assembles at any crank angle, so every N assembles
# over a full turn of the input. Mobility 3 (2N + 2 - 1) - 2 (3N + 1) = 1.
set -euo pipefail
N=${1:?usage: make_chain.sh N [order]}
ORDER=${2:-2}
if [ -n "${3:-}" ]; then exec > "$3"; fi
[[ "$N" =~ ^[0-9]+$ ]] && [ "$N" -ge 1 ] || { echo "make_chain.sh: N must be a positive integer" >&2; exit 2; }
echo "name: chain_$N"
echo "title: Chain of $N four-bar loops in series (scaling model, tools/make_chain.sh)"
echo "parameters:"
echo "  a: {value: 1.0, doc: crank of every loop}"
echo "  b: {value: 3.5, doc: coupler of every loop}"
echo "  c: {value: 3.0, doc: rocker of every loop}"
echo "  d: {value: 4.0, doc: ground distance between consecutive pivots}"
echo "links:"
printf "  ground: {ground: true, points: {O0: [0, 0]"
for ((i = 1; i <= N; i++)); do printf ", O%d: [%d*d, 0]" "$i" "$i"; done
echo "}}"
echo "  crank: {points: {O: [0, 0], B: [a, 0]}}"
for ((i = 1; i <= N; i++)); do
  echo "  coupler$i: {points: {B: [0, 0], C: [b, 0]}}"
  echo "  rocker$i: {points: {D: [0, 0], C: [c, 0], B: [a, 0]}}"
done
echo "joints:"
echo "  O0: {revolute: [ground.O0, crank.O]}"
for ((i = 1; i <= N; i++)); do
  prev=$([ "$i" -eq 1 ] && echo crank || echo "rocker$((i - 1))")
  echo "  B$i: {revolute: [$prev.B, coupler$i.B]}"
  echo "  C$i: {revolute: [coupler$i.C, rocker$i.C]}"
  echo "  O$i: {revolute: [ground.O$i, rocker$i.D]}"
done
echo "inputs:"
echo "  - {joint: O0, range: [0, 360*deg]}"
echo "outputs:"
echo "  order: $ORDER"
echo "  points: [rocker$N.C]"
echo "  scene: false"
echo "assembly:"
echo "  theta_crank: 90*deg"
for ((i = 1; i <= N; i++)); do
  echo "  theta_coupler$i: 30*deg"
  echo "  theta_rocker$i: 115*deg"
done
