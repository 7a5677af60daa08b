#!/usr/bin/python3
"""Issue 55 point 2: would regions sunk to EQUAL depths pass where the default strength (every
region loses the same share of its cap volume) does not? (lab/regions/equal_depth.md)

For each mesh: the finder's regions (`shellcontract regions MESH --face-list`), each region's
mirror-at-rest sink m_i (sink_why.geometry: its dimple's mirror image at rest, mean along the
rest normals, / diag; computed from the rest shape alone, as the product could at setup), and a
strength per region s_i = (min_j m_j / m_i) ** P, written as 'S: ids' face-list lines; then
sink.py's measures and pass rule on `run MESH --regions FILE -p 0` (sink.py --face-list).

Usage: /usr/bin/python3 lab/regions/equal_depth.py [--build build] [--meshes ...] [--p 0.5,1]
       [--out FILE]
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import common  # noqa: E402
import sink_why  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--meshes", default="bear,hand,elk,kitten,bumpy_sphere")
    ap.add_argument("--p", default="0.5,1")
    ap.add_argument("--out", default="")
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    keep = tempfile.mkdtemp(prefix="equal_depth.")
    lists = {}
    for name, path, rest, faces, diag in common.each_mesh(a.meshes.split(",")):
        regions, _, _ = common.auto_regions(exe, path, keep)
        normals = common.rest_normals(rest, faces)
        m = [sink_why.geometry(rest, faces, r, normals, diag, 0.7)["mirror"] for r in regions]
        print(f"{name}: mirror-at-rest sinks " + ", ".join(f"{x:.4f}" for x in m))
        for p in a.p.split(","):
            s = [min(1.0, (min(m) / x) ** float(p)) if x > 0 else 1.0 for x in m]
            fl = os.path.join(keep, f"{name}_p{p}.txt")
            with open(fl, "w") as f:
                f.write("".join(f"{si:.4f}: " + " ".join(map(str, r)) + "\n" for si, r in zip(s, regions)))
            print(f"  p {p}: strengths " + ", ".join(f"{x:.3f}" for x in s))
            lists.setdefault(p, []).append(f"{name}={fl}")
    for p, fls in lists.items():
        cmd = [sys.executable, os.path.join(HERE, "sink.py"), "--build", a.build,
               "--title", f"Equal depths, strengths (min m / m_i)^{p}"]
        for fl in fls:
            cmd += ["--face-list", fl]
        if a.out:
            cmd += ["--out", a.out, "--append"]
        subprocess.run(cmd, check=True)


if __name__ == "__main__":
    main()
