#!/usr/bin/python3
"""What --region-shrink S sets and what a region's cap volume reaches (lab/regions/shrink_scale.md).

For each S in --shrink, runs `run MESH -o OUT -p 0 --regions FILE --region-shrink S -q` with the
binary --build/shellcontract and measures each region's cap volume (docs/math/local-contraction.md
section 2: its faces closed by the fan from the mean of its rim vertices) on the result over its
value on the input, against the 1 - 2S the docs promised before this page.

With a binary built with lab/regions/shrink_scale.patch (prints only; the run's output is the
same bytes) and SC_DIMPLE_DEBUG set, it also prints, per dimple at the last frame, what S sets at
rest: the dimple's share of the region's rest cap volume (V_k / V_R: at least S), and the cap
volume of the shape the mirror places, the dimple's interior vertices on their rest images with
its rim and the rest of the region at rest, over the dimple's own rest volume (-1 for a rim that
is a plane section) and over the region's (1 - 2 V_k / V_R if it were -1).

Usage: /usr/bin/python3 lab/regions/shrink_scale.py --build DIR --mesh MESH --regions FILE
       [--shrink 0.25,0.5,0.7,1] [--frames N] [--extra '--dimple volume'] [--probe]
"""
import argparse
import os
import subprocess
import sys
import tempfile
from collections import Counter

import numpy as np


def read_off(path):
    with open(path) as f:
        words = " ".join(line.split("#")[0] for line in f).split()
    assert words[0] == "OFF"
    nv, nf = int(words[1]), int(words[2])
    v = np.array(words[4:4 + 3 * nv], dtype=float).reshape(nv, 3)
    at, faces = 4 + 3 * nv, []
    for _ in range(nf):
        k = int(words[at])
        faces.append([int(t) for t in words[at + 1:at + 1 + k]])
        at += 1 + k
    return v, np.array(faces, dtype=int)


def read_regions(path):
    out = []
    for line in open(path):
        line = line.split("#")[0].strip()
        if line:
            out.append([int(t) for t in line.split(":")[-1].split()])
    return out


def cap_volume(v, faces, region):
    fr = faces[region]
    edges = Counter()
    for f in fr:
        for i in range(3):
            edges[(f[i], f[(i + 1) % 3])] += 1
    rim = [e for e in edges if (e[1], e[0]) not in edges]
    c = v[sorted({x for e in rim for x in e})].mean(0)
    a, b, d = v[fr[:, 0]] - c, v[fr[:, 1]] - c, v[fr[:, 2]] - c
    return np.einsum("ij,ij->i", a, np.cross(b, d)).sum() / 6.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True)
    ap.add_argument("--mesh", required=True)
    ap.add_argument("--regions", required=True)
    ap.add_argument("--shrink", default="0.25,0.5,0.7,1")
    ap.add_argument("--frames", type=int, default=0)
    ap.add_argument("--probe", action="store_true", help="binary patched with shrink_scale.patch")
    ap.add_argument("--extra", default="", help="more run options, e.g. '--dimple volume'")
    a = ap.parse_args()
    v0, faces = read_off(a.mesh)
    regions = read_regions(a.regions)
    rest = np.array([cap_volume(v0, faces, r) for r in regions])
    env = dict(os.environ)
    if a.probe:
        env["SC_DIMPLE_DEBUG"] = "1"
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.off")
        for s in [float(t) for t in a.shrink.split(",")]:
            cmd = [os.path.join(a.build, "shellcontract"), "run", a.mesh, "-o", out, "-p", "0",
                   "--regions", a.regions, "--region-shrink", str(s), "-q"]
            cmd += a.extra.split()
            if a.frames:
                cmd += ["--frames", str(a.frames)]
            r = subprocess.run(cmd, env=env, capture_output=True, text=True)
            if r.returncode != 0:
                sys.exit(f"{' '.join(cmd)}: exit {r.returncode}\n{r.stderr}")
            v, _ = read_off(out)
            now = np.array([cap_volume(v, faces, reg) for reg in regions])
            print(f"S {s}: region cap / rest at the end", " ".join(f"{x:.3f}" for x in now / rest),
                  f"(1 - 2S = {1 - 2 * s:.2f})")
            for line in r.stderr.splitlines():
                if line.startswith("REST "):
                    print("   ", line)


if __name__ == "__main__":
    main()
