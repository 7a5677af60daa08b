#!/usr/bin/python3
"""Per exported frame of a run (lab/regions/hand_elk.md): each region's sink (sink.py's measure)
and the rest: the mean displacement of the vertices outside ALL the regions of AUTO_FACELIST and
their one-ring band, so runs of a subset of the regions are measured on the same vertices as the
run of all of them; both / the bounding-box diagonal. IDS (comma-separated, default all): the
regions of AUTO_FACELIST whose sink to print.

Usage: /usr/bin/python3 lab/regions/sinks_over_time.py MESH AUTO_FACELIST FRAMES_DIR [IDS]
"""
import glob
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import sink  # noqa: E402



def frame_number(path):
    return os.path.splitext(path)[0].rsplit("_", 1)[-1]


def main():
    name, auto, frames = sys.argv[1:4]
    rest, faces = common.read_off(common.mesh_path(name))
    regions = common.read_face_list(auto)
    ids = [int(i) for i in sys.argv[4].split(",")] if len(sys.argv) > 4 else list(range(len(regions)))
    diag = np.linalg.norm(rest.max(0) - rest.min(0))
    in_region = np.zeros(len(rest), bool)
    for r in regions:
        in_region[faces[r].ravel()] = True
    band = in_region.copy()
    band[faces[in_region[faces].any(1)].ravel()] = True
    print("| frame | " + " | ".join(f"sink {i}" for i in ids) + " | rest |")
    # Only the exported frames (NAME_NNNN.off), not an output that may share the folder.
    for fn in sorted(f for f in glob.glob(os.path.join(frames, "*_*.off")) if frame_number(f).isdigit()):
        x = common.read_off(fn)[0]
        sinks = sink.per_region_sink(rest, faces, x, [regions[i] for i in ids])
        moved = np.linalg.norm(x - rest, axis=1)[~band].mean()
        print(f"| {frame_number(fn)} | " + " | ".join(f"{v / diag:.4f}" for v in sinks) + f" | {moved / diag:.5f} |")


if __name__ == "__main__":
    main()
