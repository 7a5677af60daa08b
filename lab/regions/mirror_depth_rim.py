#!/usr/bin/python3
"""Why the flattened dimple (s = 0 in lab/regions/mirror_depth.patch) leaves bear's limb ends
(lab/regions/mirror_depth.md, "Which images stay inside").

For bear's finder regions 2-7, the dimple at the default strength (sink_why.py's dimple_image), its
interior vertices more than an edge above the plane projected onto the plane (the s = 0 image),
those outside the rest shell (winding < 0.25), and how many of those lie farther from the rim's
centroid, in the plane, than the rim vertex of the nearest azimuth: a cap wider than its rim
(a paw wider than the ankle) projects outside the rim and so outside the limb.

Usage: /usr/bin/python3 lab/regions/mirror_depth_rim.py --build DIR
"""
import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from sink_why import dimple_image, dimple_order, winding  # noqa: E402


def in_plane(v, n):
    return v - np.outer(v @ n, n)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    a = ap.parse_args()
    path = common.mesh_path("bear")
    rest, faces = common.read_off(path)
    with tempfile.TemporaryDirectory() as tmp:
        regions, _, _ = common.auto_regions(os.path.join(a.build, "shellcontract"), path, tmp)
    print("| region | deep vertices | s = 0 image outside | of those, beyond the rim | inside, beyond the rim |")
    print("|---|---|---|---|---|")
    for i in range(2, min(8, len(regions))):
        order, limit, _, edge = dimple_order(rest, faces, regions[i])
        _, rim, interior, d, pn = dimple_image(rest, faces, regions[i], order, limit, 0.7)
        deep = d > edge
        img = rest[interior][deep] - d[deep][:, None] * pn
        w = np.concatenate([winding(img[k:k + 200], rest, faces) for k in range(0, len(img), 200)])
        out = w < 0.25
        c = rest[rim].mean(0)
        q, qr = in_plane(img - c, pn), in_plane(rest[rim] - c, pn)
        r, rr = np.linalg.norm(q, axis=1), np.linalg.norm(qr, axis=1)
        nearest = np.argmax((q / r[:, None]) @ (qr / rr[:, None]).T, axis=1)
        beyond = r > rr[nearest]
        print(f"| {i} | {len(out)} | {int(out.sum())} | {int((beyond & out).sum())} | {int((beyond & ~out).sum())} |")


if __name__ == "__main__":
    main()
