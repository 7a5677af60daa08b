#!/usr/bin/python3
"""Where the rest of the shell moves when the regions sink (issue 55, item 2; lab/regions/locality.md).

Given the rest mesh, a run's output mesh and the face list of its regions, prints
  - the mean displacement of the vertices outside the regions and their one-ring band ("rest"),
    raw and after removing the best rigid motion of those vertices (Kabsch), / bbox diagonal;
  - that rigid-removed displacement by distance to the nearest region vertex;
  - per region the mean and largest inward displacement along the rest vertex normal.

Usage: /usr/bin/python3 lab/regions/rest_motion.py REST.off OUT.off REGIONS.txt
"""
import os
import sys

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402


def kabsch(p, q):
    cp, cq = p.mean(0), q.mean(0)
    u, _, vt = np.linalg.svd((p - cp).T @ (q - cq))
    d = np.diag([1.0, 1.0, np.sign(np.linalg.det(vt.T @ u.T))])
    return vt.T @ d @ u.T, cp, cq


def main():
    rest, faces = common.read_off(sys.argv[1])
    end, _ = common.read_off(sys.argv[2])
    regions = common.read_face_list(sys.argv[3])
    diag = np.linalg.norm(rest.max(0) - rest.min(0))
    n = common.rest_normals(rest, faces)
    in_region = np.zeros(len(rest), bool)
    for r in regions:
        in_region[faces[r].ravel()] = True
    band = in_region.copy()
    band[faces[in_region[faces].any(1)].ravel()] = True
    out = ~band
    r, cp, cq = kabsch(rest[out], end[out])
    aligned = (rest - cp) @ r.T + cq
    moved = np.linalg.norm(end - aligned, axis=1)
    print("rest / diag: raw mean %.4f, rigid motion removed: mean %.4f, 95 %% %.4f, max %.4f" % (
        np.linalg.norm(end - rest, axis=1)[out].mean() / diag, moved[out].mean() / diag,
        np.percentile(moved[out], 95) / diag, moved[out].max() / diag))
    dist, _ = cKDTree(rest[in_region]).query(rest[out])
    for lo, hi in [(0, .05), (.05, .1), (.1, .2), (.2, .4), (.4, 9)]:
        m = (dist >= lo * diag) & (dist < hi * diag)
        if m.any():
            print("  %.2f-%.2f diag from a region: %d vertices, mean %.4f" % (lo, hi, m.sum(), moved[out][m].mean() / diag))
    for i, f in enumerate(regions):
        vs = np.unique(faces[f].ravel())
        s = -np.einsum("ij,ij->i", end[vs] - rest[vs], n[vs])
        print("  region %d (%d faces): sink mean %.4f, max %.4f" % (i, len(f), s.mean() / diag, s.max() / diag))


if __name__ == "__main__":
    main()
