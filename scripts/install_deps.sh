#!/usr/bin/env bash
# Installs the Debian packages ShellContract needs to build and test, only those that are missing.
# Usage: scripts/install_deps.sh            (needs root or sudo; apt-get update runs first)
set -euo pipefail

PACKAGES=(
  build-essential cmake
  libcgal-dev libeigen3-dev libgmp-dev libmpfr-dev
  libboost-dev libboost-program-options-dev libboost-graph-dev
  libtbb-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  gnuplot-nox
  pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib python3-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install_deps: installing ${missing[*]}"
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
