#!/usr/bin/python3
"""Candidate rules for the regions `--regions auto` sinks, tested on issue 55 points 1 and 2
(lab/regions/sink_why.md, "Fixes tried"). None is in the product.

A region's dimple is its cap mirrored through its rim's plane (region_mirror.cpp). On a limb, a
thin board or an ear the mirror image of a deep dimple passes through the other side of the
shell; the contacts then stop it and push the shell around it (sink_why.md). For each region of
`shellcontract regions MESH`, sink_why.inside_strength gives the largest strength (of the default
--region-shrink) whose image stays inside the rest shell. The rules, each written as a face list:
  capped:       every region, with that strength (a "t:" column; 0 leaves the region out);
  capped, 1 %:  as capped, without the regions that sink < 1 % of the diagonal in the capped run
                (measured, not predicted: what such a rule could give at best);
  inside:       only the regions whose image at full strength stays inside.
Each list is measured with sink.py (point 2) and with labels.py's parts (point 1: the per-part
IoU by area of the best region, as labels.py computes it; the other meshes keep the finder's).

Usage: /usr/bin/python3 lab/regions/sink_fix.py [--build DIR] [--meshes bear,hand,elk,kitten,bumpy_sphere]
       [--keep DIR]   (writes the lists to DIR; prints the sink.py rows and the IoU summary)
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import labels  # noqa: E402
from sink import per_region_sink, run  # noqa: E402
from sink_why import inside_strength  # noqa: E402

RULES = ["finder", "capped", "capped, 1 %", "inside"]


def write(path, regions, strengths):
    with open(path, "w") as f:
        for r, t in zip(regions, strengths):
            if t > 0:
                f.write((f"{t}: " if t < 1 else "") + " ".join(map(str, r)) + "\n")


def ious(name, regions):
    """labels.py's per-part IoU (by area) of the best region; None without labels."""
    v, f = common.read_off(common.mesh_path(name))
    parts = labels.parts_of(name, v)
    if parts is None:
        return None
    area, cent = common.face_areas(v, f), common.face_centroids(v, f)
    out = []
    for _, p, r in parts:
        mask = np.linalg.norm(cent - p, axis=1) <= r
        best = 0.0
        for reg in regions:
            rm = np.zeros(len(f), bool)
            rm[reg] = True
            best = max(best, area[mask & rm].sum() / max(area[mask | rm].sum(), 1e-300))
        out.append(best)
    return out


def point1_summary(point1):
    """labels.py's point-1 summary of [(mesh, per-part IoUs)]: mean IoU, parts >= 0.5, per mesh."""
    every = [x for _, iou in point1 for x in iou]
    return (f"point 1: mean IoU {np.mean(every):.3f}, parts >= 0.5: {sum(x >= 0.5 for x in every)} of "
            f"{len(every)} (" + ", ".join(f"{n} {np.mean(i):.2f}" for n, i in point1) + ")")


def sink_rows(build, lists, out, title):
    """sink.py's table rows for the face lists {mesh: file} (it writes its page to `out`). sink.py
    prints each row twice (as it goes, then the section): each is returned once."""
    args = [f"--face-list={m}={fl}" for m, fl in lists.items()]
    text = subprocess.run([sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "sink.py"),
                           "--build", build, "--out", out, "--title", title] + args,
                          capture_output=True, text=True).stdout
    return list(dict.fromkeys(line for line in text.splitlines()
                              if line.startswith("| ") and not line.startswith("| mesh")))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--meshes", default="bear,hand,elk,kitten,bumpy_sphere")
    ap.add_argument("--keep", default="")
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    keep = a.keep or tempfile.mkdtemp()
    os.makedirs(keep, exist_ok=True)
    lists = {rule: {} for rule in RULES}
    point1 = {rule: [] for rule in RULES}
    with tempfile.TemporaryDirectory() as tmp:
        for name, path, rest, faces, diag in common.each_mesh(a.meshes.split(",")):
            regions, _, _ = common.auto_regions(exe, path, tmp)
            t = [inside_strength(rest, faces, r) for r in regions]
            print(f"{name}: largest strength inside the shell per region: {t}", flush=True)
            chosen = {"finder": [1.0] * len(regions), "capped": t,
                      "inside": [1.0 if x == 1.0 else 0.0 for x in t]}
            capped = os.path.join(keep, f"{name}_capped.txt")
            write(capped, regions, t)
            _, end = run(exe, path, tmp, ["--regions", capped, "-p", "0"])
            kept = [r for r, x in zip(regions, t) if x > 0]
            sinks = iter(per_region_sink(rest, faces, end, kept))
            chosen["capped, 1 %"] = [x if x > 0 and next(sinks) >= 0.01 * diag else 0.0 for x in t]
            for rule in RULES:
                fl = os.path.join(keep, f"{name}_{rule.replace(', 1 %', '_1pc')}.txt")
                write(fl, regions, chosen[rule])
                lists[rule][name] = fl
                iou = ious(name, [r for r, x in zip(regions, chosen[rule]) if x > 0])
                if iou is not None:
                    point1[rule].append((name, iou))
    for name in common.PAPER:  # point 1 counts every labelled mesh: the others keep the finder's
        if name not in a.meshes.split(",") and os.path.exists(common.mesh_path(name)):
            with tempfile.TemporaryDirectory() as tmp:
                regions, _, _ = common.auto_regions(exe, common.mesh_path(name), tmp)
            for rule in RULES:
                point1[rule].append((name, ious(name, regions)))
    for rule in RULES:
        print(f"\n{rule}: " + point1_summary(point1[rule]))
        print("\n".join(sink_rows(a.build, lists[rule], os.path.join(keep, "sink.md"), rule)))


if __name__ == "__main__":
    main()
