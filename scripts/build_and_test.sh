#!/usr/bin/env bash
# Sets up, builds (Release) and runs the default test suite. This is what .ci/run calls.
# Usage: scripts/build_and_test.sh [extra ctest args]   (e.g. -L long for the long scenarios)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/fetch_paper_meshes.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
ctest --test-dir build --output-on-failure -j"$(nproc)" -LE long "$@"
