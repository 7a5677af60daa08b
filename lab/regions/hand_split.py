#!/usr/bin/python3
"""The hand's automatic regions with region 0 (one cap over several finger ends) replaced by
labelled finger-end balls (lab/regions/hand_elk.md, section 7): writes a face list of the finder's
regions 1..n-1 followed by the named parts of labels.py's parts_of (each the faces whose centroid
lies within the part's radius of its point), leaving out faces an earlier region or ball took.

Usage: /usr/bin/python3 lab/regions/hand_split.py AUTO_FACELIST OUT "fingertip 2,fingertip 3"
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import labels  # noqa: E402


def main():
    auto, out_path, wanted = sys.argv[1], sys.argv[2], sys.argv[3].split(",")
    rest, faces = common.read_off(common.mesh_path("hand"))
    regions = common.read_face_list(auto)
    out = list(regions[1:])
    taken = {f for r in out for f in r}
    cent = common.face_centroids(rest, faces)
    for name, p, r in labels.parts_of("hand", rest):
        if name in wanted:
            ball = [int(i) for i in np.flatnonzero(np.linalg.norm(cent - p, axis=1) <= r) if int(i) not in taken]
            out.append(ball)
            taken |= set(ball)
    with open(out_path, "w") as f:
        f.write("".join(" ".join(map(str, r)) + "\n" for r in out))
    print("faces per region:", [len(r) for r in out])


if __name__ == "__main__":
    main()
