#!/usr/bin/env bash
# Prints the N-loop chain of tools/make_chain.sh (N crank-rocker four-bars in series, loop i's
# rocker drives loop i+1; one input) with masses and gravity, asking for the dynamics:
#   make_dyn_chain.sh N [output.yaml]
# Every bar is uniform, density rho (m = rho L, centre mid-length, J = m L^2 / 12; a rocker is
# the bar DC of length c, its pin B at a on it); gravity g along -y. bench/dynamics_multi uses it
# for the growth of one right-hand side with N (generated code against Simbody).
set -euo pipefail
N=${1:?usage: make_dyn_chain.sh N [output.yaml]}
if [ -n "${2:-}" ]; then exec > "$2"; fi
[[ "$N" =~ ^[0-9]+$ ]] && [ "$N" -ge 1 ] || { echo "make_dyn_chain.sh: N must be a positive integer" >&2; exit 2; }
echo "name: dyn_chain_$N"
echo "title: Chain of $N massive four-bar loops in series (bench/dynamics_multi/make_dyn_chain.sh)"
echo "parameters:"
echo "  a: {value: 1.0, doc: crank of every loop}"
echo "  b: {value: 3.5, doc: coupler of every loop}"
echo "  c: {value: 3.0, doc: rocker of every loop}"
echo "  d: {value: 4.0, doc: ground distance between consecutive pivots}"
echo "  rho: {value: 2.0, doc: linear density of the bars (kg/m)}"
echo "  g: {value: 9.81, doc: gravity along -y}"
echo "links:"
printf "  ground: {ground: true, points: {O0: [0, 0]"
for ((i = 1; i <= N; i++)); do printf ", O%d: [%d*d, 0]" "$i" "$i"; done
echo "}}"
echo "  crank: {points: {O: [0, 0], B: [a, 0]}, mass: rho*a, center: [a/2, 0], inertia: rho*a^3/12}"
for ((i = 1; i <= N; i++)); do
  echo "  coupler$i: {points: {B: [0, 0], C: [b, 0]}, mass: rho*b, center: [b/2, 0], inertia: rho*b^3/12}"
  echo "  rocker$i: {points: {D: [0, 0], C: [c, 0], B: [a, 0]}, mass: rho*c, center: [c/2, 0], inertia: rho*c^3/12}"
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
echo "gravity: [0, -g]"
echo "outputs:"
echo "  quantities: [K, L, dynamics]"
echo "assembly:"
echo "  theta_crank: 90*deg"
for ((i = 1; i <= N; i++)); do
  echo "  theta_coupler$i: 30*deg"
  echo "  theta_rocker$i: 115*deg"
done
