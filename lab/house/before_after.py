#!/usr/bin/python3
"""Side by side, one sitting (issue "A house a newcomer reads in an afternoon", item 7: nothing a
user sees changes; bench_projection and bear's default step time stay within noise).

Alternates two builds A and B (A B A B ...) for --rounds rounds:
  - bear's run, --threads 2, --frames 60, under each order: the summary's mean_step_ms;
  - bench_projection's per-projection kernels (one thread): cpu_time per benchmark.
Prints medians, the B/A ratios and the spread of A against itself between rounds (the noise).

Usage: lab/house/before_after.py --a DIR --b DIR [--mesh data/meshes/bear.off] [--rounds 5]
DIR holds `shellcontract` and `bench_projection` (copied there, so no rebuild changes them).
"""
import argparse
import json
import os
import statistics
import subprocess
import tempfile

KERNELS = ["BM_MembraneStvkPbd", "BM_IsometricBendingPbd", "BM_DihedralBendingPbd",
           "BM_MembraneStvkPbdColouredOrder/batched:1", "BM_DihedralBendingPbdColouredOrder/batched:1"]


def step_ms(build, mesh, order, work):
    summary = os.path.join(work, "s.json")
    subprocess.run([os.path.join(build, "shellcontract"), "run", mesh, "-o", os.path.join(work, "o.off"),
                    "--threads", "2", "-n", "60", "--order", order, "--summary", summary],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(summary) as f:
        return json.load(f)["mean_step_ms"]


def kernels(build):
    out = subprocess.run([os.path.join(build, "bench_projection"), "--benchmark_format=json",
                          "--benchmark_filter=^(" + "|".join(k.replace("/", "/") for k in KERNELS) + ")$"],
                         check=True, capture_output=True, text=True).stdout
    return {b["name"]: b["cpu_time"] for b in json.loads(out)["benchmarks"]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--a", required=True)
    ap.add_argument("--b", required=True)
    ap.add_argument("--mesh", default="data/meshes/bear.off")
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    rows = {}  # (what, build) -> list
    with tempfile.TemporaryDirectory() as work:
        print("load average at the start:", open("/proc/loadavg").read().split()[:3])
        for r in range(args.rounds):
            for name, build in (("A", args.a), ("B", args.b)):
                for order in ("sequential", "coloured"):
                    rows.setdefault((f"bear step ms, --order {order}", name), []).append(
                        step_ms(build, args.mesh, order, work))
                for k, v in kernels(build).items():
                    rows.setdefault((k + " (cpu_time)", name), []).append(v)
            print(f"round {r + 1} done")
        print("load average at the end:", open("/proc/loadavg").read().split()[:3])
    print(f"\nA = {args.a}, B = {args.b}, {args.rounds} alternating rounds\n")
    print("| what | A median | B median | B / A | A's spread (max/min) | B's spread |")
    print("|---|---:|---:|---:|---:|---:|")
    for what in dict.fromkeys(w for w, _ in rows):
        a, b = rows[(what, "A")], rows[(what, "B")]
        ma, mb = statistics.median(a), statistics.median(b)
        print(f"| {what} | {ma:.4g} | {mb:.4g} | {mb / ma:.3f} | {max(a) / min(a):.3f} | {max(b) / min(b):.3f} |")


if __name__ == "__main__":
    main()
