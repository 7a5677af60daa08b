#!/usr/bin/python3
"""Benchmark of the region selection (issue "Regions a person would choose", item 6: bear within
0.5 s, bear split in sixteen, 442k faces, within 5 s). Runnable, not a timed test: it prints the
wall time of `shellcontract regions` (best of --repeat runs; the time includes reading the mesh and
writing the PLY) on bear and on bear split in sixteen (two 1-to-4 midpoint subdivisions,
written to a temporary OFF). Measure on an idle machine; timings on a shared, loaded machine mean
nothing.

Usage: /usr/bin/python3 lab/regions/bench_selection.py [--build build] [--repeat 3]
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402


def split_in_four(v, f):
    edges = {}
    verts = list(v)

    def mid(a, b):
        key = (min(a, b), max(a, b))
        if key not in edges:
            edges[key] = len(verts)
            verts.append(0.5 * (v[a] + v[b]))
        return edges[key]

    out = []
    for a, b, c in f:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    return np.array(verts), np.array(out)


def write_off(path, v, f):
    with open(path, "w") as o:
        o.write(f"OFF\n{len(v)} {len(f)} 0\n")
        o.write("\n".join("%.17g %.17g %.17g" % tuple(p) for p in v) + "\n")
        o.write("\n".join("3 %d %d %d" % tuple(t) for t in f) + "\n")


def best_time(exe, mesh, tmp, repeat):
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        subprocess.run([exe, "regions", mesh, "-o", os.path.join(tmp, "b.ply")], check=True, stdout=subprocess.DEVNULL)
        best = min(best, time.perf_counter() - t0)
    return best


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    bear = common.mesh_path("bear")
    if not os.path.exists(bear):
        sys.exit("bear.off is absent: scripts/fetch_paper_meshes.sh")
    with tempfile.TemporaryDirectory() as tmp:
        v, f = common.read_off(bear)
        v16, f16 = split_in_four(*split_in_four(v, f))
        bear16 = os.path.join(tmp, "bear16.off")
        write_off(bear16, v16, f16)
        for label, mesh, n in (("bear", bear, len(f)), ("bear split in sixteen", bear16, len(f16))):
            print(f"{label}: {n} faces, best of {a.repeat}: {best_time(exe, mesh, tmp, a.repeat):.2f} s")


if __name__ == "__main__":
    main()
