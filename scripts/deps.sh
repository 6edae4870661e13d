#!/usr/bin/env bash
# Installs the Debian packages mechgen needs, only those that are missing; safe to run again.
#   bash scripts/deps.sh [main|all]
# main: what the README's first command (scripts/quickstart.sh) needs to build the generator and
#   the shipped models' tools and run the main job: the compiler and CMake, Eigen, GiNaC, CLN,
#   Ceres, yaml-cpp, mustache, CLI11, and gnuplot for its plots.
# all (the default; scripts/build.sh, scripts/test.sh): main, plus what the test suite and the
#   benchmarks need: GoogleTest, Google Benchmark, Python (test scripts), Simbody (the bench peer),
#   rsvg-convert, OpenMPI (studies across ranks) and pdflatex (the LaTeX report test).
set -euo pipefail
set_name=${1:-all}
MECHGEN_PACKAGES=(
  cmake ninja-build g++ pkg-config
  libeigen3-dev libginac-dev libcln-dev libceres-dev
  libyaml-cpp-dev libkainjow-mustache-dev libcli11-dev
  gnuplot-nox
)
case "$set_name" in
  main) ;;
  all)
    MECHGEN_PACKAGES+=(
      libgtest-dev libbenchmark-dev
      python3
      ccache  # scripts/build.sh and sanitize.sh use it when present: rebuilds compile what changed
      libsimbody-dev  # bench/dynamics: the Simbody comparison (Debian's build; see its README part)
      librsvg2-bin  # rsvg-convert: the test that renders every shipped model's SVG drawing to PNG
      libopenmpi-dev openmpi-bin  # MPI for `mechgen study` across ranks (docs/studies.md)
      phcpack  # phc: the independent solver the exact synthesis' root counts are checked against
      texlive-latex-base  # pdflatex for the test that compiles `mechgen report --latex --standalone` (39 MB download)
    ) ;;
  *) echo "scripts/deps.sh: error: unknown set '$set_name' (main or all)" >&2; exit 2 ;;
esac
missing=()
for p in "${MECHGEN_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "mechgen: installing missing packages: ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
