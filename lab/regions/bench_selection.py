#!/usr/bin/python3
"""Benchmark of the region selection (issue "Regions a person would choose", item 6: bear within
0.5 s, bear split in sixteen, 442k faces, within 5 s). Runnable, not a timed test: it prints the
wall time of `shellcontract regions` (median and best of --repeat runs; the time includes reading
the mesh and writing the PLY) on bear and on bear split in sixteen (two 1-to-4 midpoint
subdivisions, written to a temporary OFF), with the load average before and after. Given several
--build folders, their runs alternate (A B A B ...), so a before/after comparison on a shared
machine sees the same load. --stages prints the finder's stage times of one more run
(`regions --stage-times`, builds from 2026-12-06 on; older builds read SC_REGION_TIMING=1: wall
and processor seconds per stage).

--regions-args ARGS (repeatable) adds arguments to `shellcontract regions` ("--method tips"; ""
for none): every build runs with every one, alternating as above.

Usage: /usr/bin/python3 lab/regions/bench_selection.py [--build build ...] [--repeat 5] [--stages]
       [--regions-args "ARGS" ...]
"""
import argparse
import os
import shlex
import statistics
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


def one_run(exe, mesh, tmp, env=None, extra=()):
    t0 = time.perf_counter()
    out = subprocess.run([exe, "regions", mesh, "-o", os.path.join(tmp, "b.ply")] + list(extra), check=True,
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env)
    return time.perf_counter() - t0, out.stderr


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", action="append", default=None, help="build folder (repeatable)")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--stages", action="store_true")
    ap.add_argument("--regions-args", action="append", default=None, help="extra arguments (repeatable)")
    a = ap.parse_args()
    builds = a.build or [os.path.join(common.ROOT, "build")]
    variants = [(os.path.join(b, "shellcontract"), args) for b in builds for args in (a.regions_args or [""])]
    bear = common.mesh_path("bear")
    if not os.path.exists(bear):
        sys.exit("bear.off is absent: scripts/fetch_paper_meshes.sh")
    with tempfile.TemporaryDirectory() as tmp:
        v, f = common.read_off(bear)
        v16, f16 = split_in_four(*split_in_four(v, f))
        bear16 = os.path.join(tmp, "bear16.off")
        write_off(bear16, v16, f16)
        for label, mesh, n in (("bear", bear, len(f)), ("bear split in sixteen", bear16, len(f16))):
            load0 = os.getloadavg()[0]
            times = {v: [] for v in variants}
            for _ in range(a.repeat):
                for exe, args in variants:
                    times[(exe, args)].append(one_run(exe, mesh, tmp, extra=shlex.split(args))[0])
            load1 = os.getloadavg()[0]
            for exe, args in variants:
                t = sorted(times[(exe, args)])
                shown = exe + (" " + args if args else "")
                print(f"{label}: {n} faces, {shown}: median {statistics.median(t):.2f} s, best {t[0]:.2f} s "
                      f"of {a.repeat} (load average {load0:.1f} -> {load1:.1f})")
                if a.stages:
                    print("".join("    " + line + "\n"
                                  for line in one_run(exe, mesh, tmp, None,
                                                      shlex.split(args) + ["--stage-times"])[1].splitlines()
                                  if line.startswith("stage ")), end="")


if __name__ == "__main__":
    main()
