#!/usr/bin/env bash
# Installs the Debian packages mechgen needs, only those that are missing.
# Sourced by scripts/quickstart.sh and scripts/test.sh; safe to run again.
set -euo pipefail
MECHGEN_PACKAGES=(
  cmake ninja-build g++ pkg-config
  libeigen3-dev libginac-dev libcln-dev libceres-dev libgtest-dev libbenchmark-dev
  libyaml-cpp-dev libkainjow-mustache-dev libcli11-dev
  gnuplot-nox python3
  libsimbody-dev  # bench/dynamics: the Simbody comparison (Debian's build; see its README part)
  librsvg2-bin  # rsvg-convert: the test that renders every shipped model's SVG drawing to PNG
  libopenmpi-dev openmpi-bin  # MPI for `mechgen study` across ranks (docs/studies.md)
  texlive-latex-base  # pdflatex for the test that compiles `mechgen report --latex --standalone` (39 MB download)
)
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
