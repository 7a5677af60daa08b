#!/usr/bin/python3
"""Per labelled part (labels.py parts_of), the IoU by area of the best CGAL SDF segment: an upper
bound on what any choice among those segments could score (lab/regions/sdf.md).
Usage: /usr/bin/python3 lab/regions/sdf_iou.py SEG_DIR (SEG_DIR/NAME.seg from sdf_segments.cpp)
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import labels  # noqa: E402


def main():
    scores = []
    for name in ["eight", "hand", "elk", "bear", "kitten"]:
        v, f = common.read_off(common.mesh_path(name))
        seg = np.loadtxt(os.path.join(sys.argv[1], name + ".seg"), dtype=int)
        c, area = common.face_centroids(v, f), common.face_areas(v, f)
        row = []
        for part, p, r in labels.parts_of(name, v):
            inside = np.linalg.norm(c - p, axis=1) < r
            best = max(area[inside & (seg == s)].sum() / area[inside | (seg == s)].sum()
                       for s in np.unique(seg))
            row.append((part, round(best, 2)))
            scores.append(best)
        print(name, len(np.unique(seg)), "segments", row)
    print("mean IoU %.3f, parts >= 0.5: %d of %d" % (np.mean(scores), sum(x >= 0.5 for x in scores), len(scores)))


if __name__ == "__main__":
    main()
