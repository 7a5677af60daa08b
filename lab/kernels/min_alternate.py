#!/usr/bin/env python3
"""Several bench_projection binaries, alternating, on a loaded machine (lab/kernels/fp_hold.md).

Each round runs every binary once (--benchmark_repetitions=7, --benchmark_min_time=0.1, every
repetition kept) in the order given; after ROUNDS rounds it prints, per case and binary, the
minimum, the 25th percentile and the median of the ns per projection over all repetitions.
Under load the minimum and the lower quartile are the least disturbed figures; medians of
alternating runs (measure.py) need a quiet machine.

  python3 lab/kernels/min_alternate.py FILTER ROUNDS NAME=BINARY [NAME=BINARY ...]

The binaries load bear from their own build's source tree unless MESH is set in the environment
(passed as --mesh=MESH to every binary, so that copies of binaries from removed trees still run).
"""
import json
import os
import subprocess
import sys

MESH = [f"--mesh={os.environ['MESH']}"] if os.environ.get("MESH") else []


def main():
    flt, rounds = sys.argv[1], int(sys.argv[2])
    bins = dict(a.split("=", 1) for a in sys.argv[3:])
    res = {}
    for _ in range(rounds):
        for tag, binary in bins.items():
            out = subprocess.run([binary, "--benchmark_repetitions=7", "--benchmark_format=json", *MESH,
                                  f"--benchmark_filter={flt}", "--benchmark_min_time=0.1"],
                                 capture_output=True, text=True, check=True).stdout
            for b in json.loads(out)["benchmarks"]:
                if b.get("run_type") == "iteration":
                    res.setdefault((b["run_name"], tag), []).append(b["per_projection"] * 1e9)
    print("| case | binary | min | p25 | median | n |")
    print("|---|---|---:|---:|---:|---:|")
    for (name, tag), v in sorted(res.items()):
        v.sort()
        print(f"| {name} | {tag} | {v[0]:.2f} | {v[len(v) // 4]:.2f} | {v[len(v) // 2]:.2f} | {len(v)} |")


if __name__ == "__main__":
    main()
