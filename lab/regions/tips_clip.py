#!/usr/bin/python3
"""Issue 55, point 2 with the tip finder: do the tip regions sink better when each is clipped to
a hemisphere of its fitted sphere, as the cap finder's regions are (docs/math/cap-finder.md)?
Writes, for each mesh, the tip finder's face list (`shellcontract regions MESH --method tips
--face-list`) and the same regions clipped: an area-weighted least-squares sphere through each
region's face centroids, its axis the area-weighted mean direction from the centre to those
centroids, and only the faces whose centroid lies within 90 degrees of the axis kept. Then run
lab/regions/sink.py on both lists (its --face-list MESH=FILE).

Usage: /usr/bin/python3 lab/regions/tips_clip.py [--build build] [--meshes bear,hand,elk,kitten] DIR
"""
import argparse
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402


def sphere(points, weights):
    """Algebraic least-squares sphere |p|^2 = 2 c.p + k, weighted; (centre, radius)."""
    a = np.hstack([2 * points, np.ones((len(points), 1))]) * np.sqrt(weights)[:, None]
    b = (points ** 2).sum(1) * np.sqrt(weights)
    sol = np.linalg.lstsq(a, b, rcond=None)[0]
    c = sol[:3]
    return c, float(np.sqrt(max(sol[3] + c @ c, 0.0)))


def clip(v, f, region):
    region = np.asarray(region)
    cent = common.face_centroids(v, f)[region]
    area = common.face_areas(v, f)[region]
    c, _ = sphere(cent, area)
    d = cent - c
    axis = (area[:, None] * d / np.linalg.norm(d, axis=1)[:, None]).sum(0)
    if np.linalg.norm(axis) == 0:
        return region
    axis /= np.linalg.norm(axis)
    return region[(d @ axis) >= 0.0]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--meshes", default="bear,hand,elk,kitten")
    ap.add_argument("dir")
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    os.makedirs(a.dir, exist_ok=True)
    for name in a.meshes.split(","):
        path = common.mesh_path(name)
        v, f = common.read_off(path)
        regions, _, _ = common.auto_regions(exe, path, a.dir, ["--method", "tips"])
        area = common.face_areas(v, f)
        with open(os.path.join(a.dir, name + ".tips.txt"), "w") as out:
            out.writelines(" ".join(map(str, r)) + "\n" for r in regions)
        clipped = [clip(v, f, r) for r in regions]
        with open(os.path.join(a.dir, name + ".clipped.txt"), "w") as out:
            out.writelines(" ".join(map(str, r)) + "\n" for r in clipped if len(r))
        kept = [area[c].sum() / area[r].sum() for r, c in zip(regions, clipped)]
        print(f"{name}: {len(regions)} regions, area kept by the clip: "
              + ", ".join(f"{k:.2f}" for k in kept))


if __name__ == "__main__":
    main()
