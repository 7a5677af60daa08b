#!/usr/bin/python3
"""Per-region depth of the shallow image for lab/regions/mirror_depth.patch (lab/regions/mirror_depth.md).

The patch replaces the mirror M(p) = p - 2((p - c) . n) n of a region's dimple by
M_s(p) = p - (1 + s)((p - c) . n) n. For each of the finder's regions of each mesh this script takes
the dimple at the default strength and rho = 1 (sink_why.py's dimple_image: the same dimple order,
cut and plane as region_dimple.cpp / region_mirror.cpp), and for s in --depths (largest first)
counts the dimple's interior vertices more than an edge above the plane whose depth-s image lies
outside the rest shell (generalized winding number < 0.25, sink_why.py's test). The chosen s of a
region is the largest with none outside (the smallest tried when none fits). It prints a markdown
table and writes the chosen values, one per region line in the finder's order, to
DIR/MESH.depth, the file SC_MIRROR_DEPTH_FILE names for the patched binary.

With --sinks it instead runs sink.py's point-2 run (`run MESH --regions auto -p 0`, --frames N
if given, the environment passed on, so SC_MIRROR_DEPTH / SC_MIRROR_DEPTH_FILE apply) and prints
each region's sink (sink.py's measure) and the rest, both / the diagonal: which region is the
smallest.

Usage: /usr/bin/python3 lab/regions/mirror_depth.py --build DIR [--meshes bear,hand,elk]
       [--depths 1,0.75,0.5,0.25,0] [--shrink 0.7] --out-dir DIR
       /usr/bin/python3 lab/regions/mirror_depth.py --build DIR --meshes bear --sinks [--frames N]
"""
import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from sink import per_region_sink, rest_motion, run  # noqa: E402
from sink_why import dimple_image, dimple_order, winding  # noqa: E402


def outside(rest, faces, interior, d, pn, edge, s):
    """(vertices more than an edge deep whose depth-s image is outside the rest shell, of those)."""
    deep = d > edge
    if not deep.any():
        return 0, 0
    img = rest[interior][deep] - (1.0 + s) * d[deep][:, None] * pn
    w = np.concatenate([winding(img[k:k + 200], rest, faces) for k in range(0, len(img), 200)])
    return int((w < 0.25).sum()), int(deep.sum())


def sinks(a):
    exe = os.path.join(a.build, "shellcontract")
    env = " ".join(f"{k}={os.environ[k]}" for k in ("SC_MIRROR_DEPTH", "SC_MIRROR_DEPTH_FILE") if k in os.environ)
    with tempfile.TemporaryDirectory() as tmp:
        for name, path, rest, faces, diag in common.each_mesh(a.meshes.split(",")):
            regions, _, _ = common.auto_regions(exe, path, tmp)
            frames = ["--frames", str(a.frames)] if a.frames else []
            _, end = run(exe, path, tmp, ["--regions", "auto", "-p", "0"] + frames)
            sink = per_region_sink(rest, faces, end, regions)
            rest_mean, _ = rest_motion(rest, faces, end, regions)
            print(f"| {name} | {env or 'default'} | " + ", ".join(f"{x / diag:.4f}" for x in sink)
                  + f" | {rest_mean / diag:.5f} | {rest_mean / min(sink):.3f} |", flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--meshes", default="bear,hand,elk")
    ap.add_argument("--depths", default="1,0.75,0.5,0.25,0")
    ap.add_argument("--shrink", type=float, default=0.7, help="the run's --region-shrink (the default)")
    ap.add_argument("--out-dir", default="")
    ap.add_argument("--sinks", action="store_true", help="per-region sinks of one -p 0 run")
    ap.add_argument("--frames", type=int, default=0, help="with --sinks: 0 = the tool's default")
    a = ap.parse_args()
    if a.sinks:
        return sinks(a)
    depths = sorted((float(x) for x in a.depths.split(",")), reverse=True)
    exe = os.path.join(a.build, "shellcontract")
    if not a.out_dir:
        ap.error("--out-dir is required without --sinks")
    os.makedirs(a.out_dir, exist_ok=True)
    print("| mesh | region | deep vertices | image outside at s = " + ", ".join(f"{s:g}" for s in depths)
          + " | chosen s |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, path, rest, faces, _ in common.each_mesh(a.meshes.split(",")):
            regions, _, _ = common.auto_regions(exe, path, tmp)
            chosen = []
            for i, region in enumerate(regions):
                order, limit, _, edge = dimple_order(rest, faces, region)
                _, _, interior, d, pn = dimple_image(rest, faces, region, order, limit, a.shrink)
                counts = [outside(rest, faces, interior, d, pn, edge, s) for s in depths]
                pick = next((s for s, (o, _) in zip(depths, counts) if o == 0), depths[-1])
                chosen.append(pick)
                print(f"| {name} | {i} | {counts[0][1]} | " + ", ".join(str(o) for o, _ in counts)
                      + f" | {pick:g} |")
            with open(os.path.join(a.out_dir, name + ".depth"), "w") as f:
                f.write("".join(f"{s:g}\n" for s in chosen))


if __name__ == "__main__":
    main()
