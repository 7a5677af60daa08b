#!/usr/bin/env python3
"""Old against new batched kernels, alternating, in one sitting (issue 58 points 2 and 3).

Runs two bench_projection binaries (the base commit's and this branch's) one after the other,
`--rounds` times, each run with --benchmark_repetitions=9 --benchmark_report_aggregates_only=true,
and prints the median of each run's per-projection time (ns) and the median over the rounds, with
the ratio old / new. Cases missing from a binary (kernels the old one has not got) are shown as -.

  python3 lab/kernels/measure.py --old /tmp/kernels_old/bench_projection \
      --new build/lab/benchmarks/bench_projection --rounds 3 [--filter REGEX] [--mesh PATH]
"""
import argparse
import json
import statistics
import subprocess
import sys


def run(binary, flt, mesh):
    cmd = [binary, "--benchmark_repetitions=9", "--benchmark_report_aggregates_only=true",
           "--benchmark_format=json", f"--benchmark_filter={flt}"]
    if mesh:
        cmd.append(f"--mesh={mesh}")
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    res = {}
    for b in json.loads(out)["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        name = b["run_name"]
        if "per_projection" in b:
            res[name] = b["per_projection"] * 1e9  # s per projection -> ns
    return res


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--old", required=True)
    ap.add_argument("--new", required=True)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--filter", default="PbdColouredOrder|Pbd$")
    ap.add_argument("--mesh", default="")
    a = ap.parse_args()
    old, new = {}, {}
    for r in range(a.rounds):
        for label, binary, store in (("old", a.old, old), ("new", a.new, new)):
            for k, v in run(binary, a.filter, a.mesh).items():
                store.setdefault(k, []).append(v)
            print(f"round {r + 1} {label} done", file=sys.stderr)
    names = sorted(set(old) | set(new))
    print("| case | old ns (per round) | new ns (per round) | old median | new median | old/new |")
    print("|---|---|---|---|---|---|")
    for n in names:
        o, w = old.get(n), new.get(n)
        om = statistics.median(o) if o else None
        nm = statistics.median(w) if w else None
        fmt = lambda xs: ", ".join(f"{x:.1f}" for x in xs) if xs else "-"
        ratio = f"{om / nm:.2f}" if om and nm else "-"
        print(f"| {n} | {fmt(o)} | {fmt(w)} | {om and f'{om:.1f}' or '-'} | "
              f"{nm and f'{nm:.1f}' or '-'} | {ratio} |")


if __name__ == "__main__":
    main()
