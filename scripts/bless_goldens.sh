#!/bin/sh
# Re-records tests/goldens/runs.txt from the current code (tests/scenario/test_goldens.cpp). Run it
# only for an intended change of behaviour, and say why in the commit that changes the file.
# Usage: scripts/bless_goldens.sh [build-dir]
set -eu
cd "$(dirname "$0")/.."
build=${1:-build}
cmake --build "$build" --target test_scenario
SHELLCONTRACT_BLESS_GOLDENS=1 "$build/tests/test_scenario" --gtest_filter='Goldens.*'
git --no-pager diff --stat -- tests/goldens/runs.txt
