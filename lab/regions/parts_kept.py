#!/usr/bin/python3
"""Issue 55 point 2 for the part finder's regions at best: `regions --method parts`, sunk once
(`run --regions FILE -p 0`), then only the regions that sank at least 1 % of the diagonal kept and
measured again with sink.py; point 1 (labels.py's parts, sink_fix.ious) on the kept regions (the
eight keeps all of its own). The regions dropped are chosen from the measured sinks, so this is
the best a rule dropping shallow regions could do (lab/regions/fit_clip.md).

Usage: /usr/bin/python3 lab/regions/parts_kept.py   (build/shellcontract; lists in /tmp/parts1pc)
"""
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from sink import per_region_sink, run  # noqa: E402
from sink_fix import ious  # noqa: E402

MESHES = ["bear", "hand", "elk", "kitten", "bumpy_sphere"]


def main():
    exe = os.path.join(common.ROOT, "build", "shellcontract")
    keep = "/tmp/parts1pc"
    os.makedirs(keep, exist_ok=True)
    lists, point1 = {}, []
    with tempfile.TemporaryDirectory() as tmp:
        for name, path, rest, faces, diag in common.each_mesh(MESHES):
            regions, _, _ = common.auto_regions(exe, path, tmp, ["--method", "parts"])
            every = os.path.join(keep, name + "_parts.txt")
            with open(every, "w") as f:
                f.writelines(" ".join(map(str, r)) + "\n" for r in regions)
            _, end = run(exe, path, tmp, ["--regions", every, "-p", "0"])
            sinks = per_region_sink(rest, faces, end, regions)
            kept = [r for r, s in zip(regions, sinks) if s >= 0.01 * diag]
            print(name, "sinks / diag", [round(s / diag, 4) for s in sinks], "kept", len(kept), "of",
                  len(regions), flush=True)
            lists[name] = os.path.join(keep, name + "_kept.txt")
            with open(lists[name], "w") as f:
                f.writelines(" ".join(map(str, r)) + "\n" for r in kept)
            iou = ious(name, kept)
            if iou is not None:
                point1.append((name, iou))
        regions, _, _ = common.auto_regions(exe, common.mesh_path("eight"), tmp, ["--method", "parts"])
    point1.append(("eight", ious("eight", regions)))
    every = [x for _, iou in point1 for x in iou]
    print(f"point 1: mean IoU {np.mean(every):.3f}, parts >= 0.5: {sum(x >= 0.5 for x in every)} of "
          f"{len(every)}", [(n, round(float(np.mean(i)), 2)) for n, i in point1], flush=True)
    out = subprocess.run([sys.executable, os.path.join(common.ROOT, "lab", "regions", "sink.py"), "--build",
                          os.path.join(common.ROOT, "build"), "--out", os.path.join(keep, "sink.md"), "--title",
                          "parts kept"] + [f"--face-list={m}={f}" for m, f in lists.items()],
                         capture_output=True, text=True).stdout
    print("\n".join(dict.fromkeys(line for line in out.splitlines()
                                  if line.startswith("| ") and not line.startswith("| mesh"))))


if __name__ == "__main__":
    main()
