#!/usr/bin/env bash
# The many-core measurement of the large-mesh benchmark in one command, for a machine that has the
# repository and a bundle from lab/scripts/many_core_bundle.sh but not the build's packages: the tool
# is checked to start, then lab/scripts/scale_benchmark.py runs bear and bear x16 for ten frames at 1,
# 2, 4, 8 and 16 threads (coloured order, with the phase table), and its tables, every run's
# summary (summaries.tgz) and the machine's description go to the results folder.
# Usage: lab/scripts/many_core_scale.sh [bundle-dir] [results-dir] [threads] [levels]
#   defaults: .bundle, many-core-results, 1,2,4,8,16, 0,2
set -euo pipefail
cd "$(dirname "$0")/../.."
bundle=$(cd "${1:-.bundle}" && pwd)
results=${2:-many-core-results}
threads=${3:-1,2,4,8,16}
levels=${4:-0,2}
mkdir -p "$results"
export LD_LIBRARY_PATH="$bundle/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
"$bundle/shellcontract" --version >/dev/null ||
  { echo "many_core_scale: the bundled tool does not start here (see ldd below)" >&2;
    ldd "$bundle/shellcontract" >&2; exit 2; }
# scale_benchmark.py makes the subdivided meshes from data/meshes/bear.off.
if [ ! -f data/meshes/bear.off ]; then
  mkdir -p data/meshes
  cp "$bundle/bear.off" data/meshes/bear.off
fi
{
  echo "# $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) CPUs"
  grep -m1 "model name" /proc/cpuinfo || true
  grep -E "MemTotal" /proc/meminfo || true
} > "$results/machine.txt"
saved=$(mktemp -d)
PYTHONUNBUFFERED=1 python3 lab/scripts/scale_benchmark.py --tool "$bundle/shellcontract" \
  --frames 10 --threads "$threads" --levels "$levels" --phases --save "$saved" |
  tee "$results/scale.md"
# One archive of the summaries: three files in all (a device tool may bring back only a few).
tar czf "$results/summaries.tgz" -C "$saved" .
rm -rf "$saved"
