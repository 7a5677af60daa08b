#!/usr/bin/python3
"""Issue 55 points 1 and 2 for the part finder's regions without its shallow caps: `regions
--method parts`, keeping only the regions whose angle (the printed table's last column: the
half-angle of the region's cap on its fitted sphere, in degrees) is at least A. Unlike
parts_kept.py, the rule is geometric: a region is dropped before any run, from its shape alone.

Point 1: labels.py's parts (sink_fix.ious) on the kept regions, the eight included. Point 2:
sink.py on the kept regions' face lists (bear, hand, elk, kitten, bumpy_sphere).

Usage: /usr/bin/python3 lab/regions/parts_angle.py [--build B] [--angles 30,40,45] [--keep DIR]
"""
import argparse
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from sink_fix import ious, point1_summary, sink_rows  # noqa: E402

MESHES = ["bear", "hand", "elk", "kitten", "bumpy_sphere", "eight"]


def angles_of(table):
    """The angle column of `regions`' printed table, one per region in the face list's order."""
    rows = []
    started = False
    for line in table.splitlines():
        if line.strip().startswith("id "):
            started = True
            continue
        if started and line.strip() and line.split()[0].isdigit():
            rows.append(float(line.split()[-1]))
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--angles", default="30,40,45")
    ap.add_argument("--keep", default="/tmp/parts_angle")
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    os.makedirs(a.keep, exist_ok=True)
    found = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name in MESHES:
            regions, table, _ = common.auto_regions(exe, common.mesh_path(name), tmp, ["--method", "parts"])
            angle = angles_of(table)
            assert len(angle) == len(regions), (name, len(angle), len(regions))
            found[name] = (regions, angle)
            print(name, "angles", angle, flush=True)
    for threshold in [float(x) for x in a.angles.split(",")]:
        lists, point1 = {}, []
        for name, (regions, angle) in found.items():
            kept = [r for r, t in zip(regions, angle) if t >= threshold]
            iou = ious(name, kept)
            if iou is not None:
                point1.append((name, iou))
            if name == "eight":
                continue
            lists[name] = os.path.join(a.keep, f"{name}_{threshold:g}.txt")
            with open(lists[name], "w") as f:
                f.writelines(" ".join(map(str, r)) + "\n" for r in kept)
            print(f"angle >= {threshold:g}: {name} keeps {len(kept)} of {len(regions)}", flush=True)
        print(f"angle >= {threshold:g}:", point1_summary(point1), flush=True)
        rows = sink_rows(a.build, lists, os.path.join(a.keep, f"sink_{threshold:g}.md"),
                         f"parts, angle >= {threshold:g}")
        print("\n".join(rows), flush=True)


if __name__ == "__main__":
    main()
