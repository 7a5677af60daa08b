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
  libtinygltf-dev nlohmann-json3-dev
  chromium
  blender
  pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib python3-dev
  python3-distributed
  pkgconf man-db  # the package test's pkg-config consumer; the man page test renders with man
)
# The viewer's tests and scripts/view.py's page need node and npm; an existing install (any
# source) is kept.
if ! command -v node >/dev/null 2>&1; then PACKAGES+=(nodejs); fi
if ! command -v npm >/dev/null 2>&1; then PACKAGES+=(npm); fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all packages present"
else
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  echo "install_deps: installing ${missing[*]}"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

# The viewer's npm modules (three.js, and for the tests gltf-validator and puppeteer-core, which
# drives Debian's chromium: no browser is downloaded), exactly as pinned in viewer/package-lock.json,
# from the npm registry. Reinstalled only when node_modules is missing or the lockfile changed.
viewer="$(cd "$(dirname "${BASH_SOURCE[0]}")/../viewer" && pwd)"
stamp="$viewer/node_modules/.installed-lockfile.sha256"
want="$(sha256sum "$viewer/package-lock.json" | cut -d' ' -f1)"
if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ]; then
  echo "install_deps: viewer/node_modules up to date"
else
  echo "install_deps: npm ci in viewer/"
  (cd "$viewer" && PUPPETEER_SKIP_DOWNLOAD=1 npm ci --no-audit --no-fund)
  echo "$want" > "$stamp"
fi
