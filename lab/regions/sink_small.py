#!/usr/bin/python3
"""locality.md, "Only the finder's small regions": the finder's regions (`shellcontract regions MESH`)
below an area share, run at -p 0 with --dimple volume and --dimple mirror; prints per mesh the
smallest and mean region sink / diagonal and the rest's mean motion (sink.py's measures; the
dropped regions count in the rest).

Usage: /usr/bin/python3 lab/regions/sink_small.py MESHES LIMIT [--build build]
  e.g. lab/regions/sink_small.py hand,bear,elk,kitten,bumpy_sphere 0.05
"""
import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import sink  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("meshes")
    ap.add_argument("limit", type=float, help="keep the regions below this share of the area")
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    for name, path, rest, faces, diag in common.each_mesh(a.meshes.split(",")):
        e1, e2 = rest[faces[:, 1]] - rest[faces[:, 0]], rest[faces[:, 2]] - rest[faces[:, 0]]
        area = 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)
        with tempfile.TemporaryDirectory() as tmp:
            regions, _, _ = common.auto_regions(exe, path, tmp)
            kept = [r for r in regions if area[r].sum() / area.sum() < a.limit]
            if not kept:
                print(f"{name}: no region below {a.limit}")
                continue
            listed = os.path.join(tmp, "kept.txt")
            with open(listed, "w") as f:
                f.write("\n".join(" ".join(map(str, r)) for r in kept) + "\n")
            for dimple in ("volume", "mirror"):
                s, end = sink.run(exe, path, tmp, ["--regions", listed, "-p", "0", "--dimple", dimple])
                sk = sink.per_region_sink(rest, faces, end, kept)
                rest_mean, _ = sink.rest_motion(rest, faces, end, kept)
                print(f"{name} kept {len(kept)}/{len(regions)} {dimple}: smallest {min(sk) / diag:.4f} "
                      f"mean {np.mean(sk) / diag:.4f} rest {rest_mean / diag:.5f} "
                      f"rest/smallest {rest_mean / min(sk):.3f} new intersections "
                      f"{s.get('new_intersections')} V/V0 {s.get('final_volume_ratio'):.3f}", flush=True)


if __name__ == "__main__":
    main()
