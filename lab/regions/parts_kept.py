#!/usr/bin/python3
"""Issue 55 point 2 for the part finder's regions at best: `regions --method parts`, sunk once
(`run --regions FILE -p 0`), then only the regions that sank at least 1 % of the diagonal kept and
measured again with sink.py; point 1 (labels.py's parts, sink_fix.ious) on the kept regions (the
eight keeps all of its own). The regions dropped are chosen from the measured sinks, so this is
the best a rule dropping shallow regions could do (lab/regions/fit_clip.md).

Usage: /usr/bin/python3 lab/regions/parts_kept.py   (build/shellcontract; lists in /tmp/parts1pc)
"""
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from sink import per_region_sink, run  # noqa: E402
from sink_fix import ious, point1_summary, sink_rows  # noqa: E402

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
    print(point1_summary(point1), flush=True)
    print("\n".join(sink_rows(os.path.join(common.ROOT, "build"), lists, os.path.join(keep, "sink.md"),
                               "parts kept")))


if __name__ == "__main__":
    main()
