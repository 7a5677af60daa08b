#!/usr/bin/python3
"""A rule for the regions `--regions auto` sinks, tested on issue 55 points 1 and 2: each region
clipped to the widest cap whose mirrored dimple fits inside the shell (lab/regions/fit_clip.md).
Not in the product.

sink_why.md found that the limb ends' hemispheres (bear's arm and foot ends, the elk's board and
ring) have mirror images that leave the shell; the contacts then push the shell and move the rest.
The rules tried there (sink_fix.py) lowered the strength (a smaller dimple inside the same
region) or dropped the region. This one keeps every part but makes its region smaller: for each
region of `shellcontract regions MESH`, the sphere fitted to its face centroids (area-weighted,
as tips_clip.py) and its axis (the area-weighted mean direction from the centre), the region is
clipped to the faces within theta of the axis, for theta = 90, 80, ..., 30 degrees; the widest
clip whose dimple at the default strength (--region-shrink 0.7) has its mirror image inside the
rest shell (sink_why.image_outside: no interior vertex deeper than an edge with its image
outside) is kept; a region with none is left out.

Measured with sink.py (point 2) and with labels.py's parts (point 1, sink_fix.ious).

Usage: /usr/bin/python3 lab/regions/fit_clip.py [--build DIR] [--meshes bear,hand,elk,kitten,bumpy_sphere]
       [--keep DIR]
"""
import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from sink_fix import ious, point1_summary, sink_rows  # noqa: E402
from sink_why import dimple_image, dimple_order, image_outside  # noqa: E402
from tips_clip import sphere  # noqa: E402

SHRINK = 0.7  # the default --region-shrink
ANGLES = [90, 80, 70, 60, 50, 40, 30]


def fits(rest, faces, region):
    """Whether the dimple of `region` at the default strength has its mirror image inside."""
    if len(region) < 3:
        return False
    order, limit, _, edge = dimple_order(rest, faces, list(region))
    _, _, interior, d, pn = dimple_image(rest, faces, list(region), order, limit, SHRINK)
    return len(interior) > 0 and image_outside(rest, faces, interior, d, pn, edge)[0] == 0


def fit_clip(rest, faces, region):
    """(clipped region, its angle) of the widest clip that fits; (None, 0) if none."""
    region = np.asarray(sorted(set(region)))
    cent = common.face_centroids(rest, faces)[region]
    area = common.face_areas(rest, faces)[region]
    c, _ = sphere(cent, area)
    d = cent - c
    dist = np.linalg.norm(d, axis=1)
    axis = (area[:, None] * d / np.maximum(dist, 1e-300)[:, None]).sum(0)
    if not np.linalg.norm(axis) > 0:
        return None, 0
    axis /= np.linalg.norm(axis)
    cosang = (d @ axis) / np.maximum(dist, 1e-300)
    for theta in ANGLES:
        clipped = region[cosang >= np.cos(np.radians(theta)) - 1e-12]
        if fits(rest, faces, clipped):
            return [int(i) for i in clipped], theta
    return None, 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--meshes", default="bear,hand,elk,kitten,bumpy_sphere")
    ap.add_argument("--keep", default="")
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    keep = a.keep or tempfile.mkdtemp()
    os.makedirs(keep, exist_ok=True)
    lists, point1 = {}, []
    with tempfile.TemporaryDirectory() as tmp:
        for name, path, rest, faces, diag in common.each_mesh(a.meshes.split(",")):
            regions, _, _ = common.auto_regions(exe, path, tmp)
            out = [fit_clip(rest, faces, r) for r in regions]
            print(f"{name}: angle kept per region (0 = left out): {[t for _, t in out]}; "
                  f"faces {[len(r) for r in regions]} -> {[len(c) if c else 0 for c, _ in out]}", flush=True)
            kept = [c for c, _ in out if c]
            fl = os.path.join(keep, f"{name}_fit_clip.txt")
            with open(fl, "w") as f:
                f.writelines(" ".join(map(str, r)) + "\n" for r in kept)
            lists[name] = fl
            iou = ious(name, kept)
            if iou is not None:
                point1.append((name, iou))
    for name in common.PAPER:  # point 1 counts every labelled mesh: the others keep the finder's
        if name not in lists and os.path.exists(common.mesh_path(name)):
            with tempfile.TemporaryDirectory() as tmp:
                regions, _, _ = common.auto_regions(exe, common.mesh_path(name), tmp)
            point1.append((name, ious(name, regions)))
    print("\n" + point1_summary(point1), flush=True)
    print("\n".join(sink_rows(a.build, lists, os.path.join(keep, "sink.md"), "fit clip")))


if __name__ == "__main__":
    main()
