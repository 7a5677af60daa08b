#!/usr/bin/env bash
# Issue 58 points 2 and 3 on a machine that has a bundle from lab/scripts/many_core_bundle.sh
# (built here with the benchmarks) but not the build's packages: bench_projection on bear, one
# thread, the sequential and the coloured batched projections of every membrane material and both
# bendings, --rounds times (each 9 repetitions, medians), with the machine's CPU and its vector
# extensions. Results to the results folder (machine.txt, kernels.md, raw JSON per round).
# Usage: lab/scripts/kernels_on_device.sh [bundle-dir] [results-dir] [rounds]
set -euo pipefail
cd "$(dirname "$0")/../.."
bundle=$(cd "${1:-.bundle}" && pwd)
results=${2:-kernels-results}
rounds=${3:-3}
mkdir -p "$results"
export LD_LIBRARY_PATH="$bundle/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
{
  echo "# $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) CPUs"
  grep -m1 "model name" /proc/cpuinfo || true
  grep -m1 -o -w -E "avx512f|avx2" /proc/cpuinfo | sort -u | tr '\n' ' '; echo
} > "$results/machine.txt"
cat "$results/machine.txt"
filter='Pbd$|PbdColouredOrder/batched:1$'
for r in $(seq 1 "$rounds"); do
  taskset -c 0 "$bundle/bench_projection" --mesh="$bundle/bear.off" --benchmark_filter="$filter" \
    --benchmark_repetitions=9 --benchmark_report_aggregates_only=true \
    --benchmark_format=json > "$results/round$r.json"
done
python3 - "$results" "$rounds" <<'PY' | tee "$results/kernels.md"
import json, statistics, sys
folder, rounds = sys.argv[1], int(sys.argv[2])
per = {}
for r in range(1, rounds + 1):
    for b in json.load(open(f"{folder}/round{r}.json"))["benchmarks"]:
        if b.get("aggregate_name") == "median" and "per_projection" in b:
            per.setdefault(b["run_name"], []).append(b["per_projection"] * 1e9)
print("| projection, bear, 1 thread | " + " | ".join(f"round {r}" for r in range(1, rounds + 1))
      + " | median (ns) |")
print("|---|" + "---:|" * (rounds + 1))
for name, v in per.items():
    print(f"| {name} | " + " | ".join(f"{x:.2f}" for x in v) + f" | {statistics.median(v):.2f} |")
PY
