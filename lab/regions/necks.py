#!/usr/bin/python3
"""Parts cut at a neck found from the level sets of a geodesic distance: a lab prototype for
issue 55 point 1, measured on the labelled set (labels.py), bumpy_sphere's bumps and bear
against bear split in four. Its rule, written before measuring, and the tables: necks.md.

From each seed, grow {d < r} with d the heat-method geodesic distance (necks_geo.py) and watch
the length L(r) of its boundary. Cut at the first neck past where L stops growing (L narrows by
at least 15 % and widens again), or, with no neck, where L stops growing (L' down to a quarter
of its largest value so far: a limb's round end). Seeds: the deepest vertex of each region of
`shellcontract regions MESH --method parts` (default) or the persistent maxima of a sampled
mean geodesic distance (--seeds maxima). Columns: necks (the rule alone), necks+fb (a parts
region whose seed's region fails is kept as it is), the variants nest, nest+fb, wrap+fb and
neck-only+fb (chosen after the first measurement; neck_regions), parts (the finder alone).

Usage: /usr/bin/python3 lab/regions/necks.py [--build build] [--seeds parts|maxima] [--curves MESH]
       [--time] [--neck 0.85] [--stop 0.25] [--distance heat|dijkstra] [--label-seeds]
(--curves MESH: print each seed's L(r), r_stop, neck and cut on MESH and stop; --time: time the
stages on bear and bear split in sixteen and stop; --neck, --stop: the two thresholds, for the
sensitivity runs of necks.md; --distance dijkstra: edge-graph distances instead of the heat method;
--label-seeds: the diagnostics of necks.md with seeds placed from the labels, on the elk and
kitten, and of labels.py's elk feet)
"""
import argparse
import os
import sys
import tempfile
import time

import numpy as np
from scipy.ndimage import gaussian_filter1d

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_selection  # noqa: E402
import common  # noqa: E402
import labels  # noqa: E402
import necks_geo as G  # noqa: E402

STEP, SIGMA = 0.002, 0.01          # level spacing and smoothing, in bounding-box diagonals
STOP, NECK = 0.25, 0.85            # L' down to a quarter; a neck narrows L to 0.85 or less
MIN_FACES, LO, HI, COMPACT = 10, 0.002, 0.25, 2.0  # the other finders' filters
WRAP = 0.75                        # variant wrap: a region has wrapped round its end


def profile(mesh, d):
    """Levels, smoothed L and L' of the distance d."""
    levels = np.arange(0.0, d.max(), STEP)
    L = gaussian_filter1d(mesh.level_length(d, levels), SIGMA / STEP)
    return levels, L, np.gradient(L, STEP)


def cut_radius(mesh, d, total_area):
    """(cut, r_stop, neck or None) of the rule in necks.md, steps 4 and 5."""
    levels, L, dL = profile(mesh, d)
    start = int(round(2 * SIGMA / STEP))
    run = np.maximum.accumulate(dL)
    stop = next((k for k in range(start, len(levels)) if dL[k] <= STOP * run[k]), len(levels) - 1)
    face_d = d[mesh.f].mean(axis=1)
    for k in range(stop + 1, len(levels) - 1):
        if not (L[k] <= L[k - 1] and L[k] < L[k + 1]):
            continue
        if L[k] > NECK * L[:k + 1].max() or L[k + 1:].max() < L[k] / NECK:
            continue
        if mesh.area[face_d < levels[k]].sum() > HI * total_area:
            break  # every later neck holds more
        return levels[k], levels[stop], levels[k]
    return levels[stop], levels[stop], None


def deepest_vertex(mesh, mask):
    """The vertex of a face set farthest from the set's boundary vertices (Mesh.distance)."""
    inside = mesh.edge_face @ mask.astype(float)
    rim = np.unique(mesh.edge_vertices[inside == 1])
    verts = np.unique(mesh.f[mask])
    if len(rim) == 0:
        return int(verts[0])
    d = mesh.distance(rim)
    return int(verts[np.argmax(d[verts])])


def maxima_seeds(mesh, count=8, tau=0.01):
    c = (mesh.area[:, None] * mesh.centroid).sum(0) / mesh.area.sum()
    cur = int(np.argmax(mesh.distance(int(np.argmin(np.linalg.norm(mesh.v - c, axis=1))))))
    acc, dmin = np.zeros(len(mesh.v)), np.full(len(mesh.v), np.inf)
    for _ in range(count):
        dk = mesh.distance(cur)
        acc += dk
        dmin = np.minimum(dmin, dk)
        cur = int(np.argmax(dmin))
    return [int(s) for s, _ in G.persistent_maxima(mesh.adj, acc / count, tau)]


def passes(mesh, m):
    share = mesh.area[m].sum() / mesh.area.sum()
    return m.sum() >= MIN_FACES and LO <= share <= HI and mesh.compactness(m) <= COMPACT


def neck_regions(mesh, seeds, fallback=None, nest=False, wrap=False, neck_only=False):
    """Steps 6-8: one region per seed, merged (in seed order), then filtered. fallback[i], when
    given, is kept in place of seed i's region when that one fails. Variants chosen after the
    first measurement (necks.md); with any of them a failing region is dropped before merging:
    nest: regions are taken smallest first, merged only when their IoU exceeds 1/2 (two seeds of
    one part), and a larger region loses the faces of the smaller ones inside it (a head less
    its ears); wrap: a region must have wrapped round its end (P^2 / (4 pi A) <= WRAP, a
    spherical cap's (1 + cos theta) / 2 at 60 degrees); neck_only: only a cut at a neck makes a
    region (a seed without a neck gives its fallback or nothing)."""
    total = mesh.area.sum()
    cand = []
    for i, s in enumerate(seeds):
        d = mesh.distance(s)
        cut, _, neck = cut_radius(mesh, d, total)
        region = mesh.largest_piece(d[mesh.f].mean(axis=1) < cut)
        ok = passes(mesh, region) and (not wrap or mesh.compactness(region) <= WRAP) and \
            (not neck_only or neck is not None)
        if fallback is not None and not ok:
            region, ok = fallback[i].copy(), True
        if ok or not (nest or wrap or neck_only):
            cand.append(region)
    if nest:
        cand.sort(key=lambda m: mesh.area[m].sum())
    kept = []
    for region in cand:
        merged = False
        for j, k in enumerate(kept):
            ov = mesh.area[region & k].sum()
            small = min(mesh.area[region].sum(), mesh.area[k].sum())
            if (ov > 0.5 * mesh.area[region | k].sum()) if nest else (ov > 0.5 * small):
                kept[j] = k | region
                merged = True
                break
            region = region & ~k
        if not merged and region.any():
            kept.append(mesh.largest_piece(region))
    return [m for m in kept if passes(mesh, m)]


def load(path):
    v, f = common.read_off(path)
    lo, D = v.min(0), float(np.linalg.norm(v.max(0) - v.min(0)))
    return v, f, G.Mesh((v - lo) / D, f)


def all_columns(exe, path, tmp, seeds_rule):
    """{column: list of face masks} of one mesh."""
    v, f, mesh = load(path)
    parts = common.face_masks(common.auto_regions(exe, path, tmp, ["--method", "parts"])[0], len(f))
    seeds = [deepest_vertex(mesh, m) for m in parts] if seeds_rule == "parts" else maxima_seeds(mesh)
    fb = parts if seeds_rule == "parts" else None
    return v, f, mesh, {"necks": neck_regions(mesh, seeds), "necks+fb": neck_regions(mesh, seeds, fb),
                        "nest": neck_regions(mesh, seeds, nest=True),
                        "nest+fb": neck_regions(mesh, seeds, fb, nest=True),
                        "wrap+fb": neck_regions(mesh, seeds, fb, nest=True, wrap=True),
                        "neck-only+fb": neck_regions(mesh, seeds, fb, neck_only=True),
                        "parts": parts}


def curves(exe, name, seeds_rule):
    path = common.mesh_path(name)
    v, f, mesh = load(path)
    with tempfile.TemporaryDirectory() as tmp:
        parts = common.face_masks(common.auto_regions(exe, path, tmp, ["--method", "parts"])[0], len(f))
    seeds = [deepest_vertex(mesh, m) for m in parts] if seeds_rule == "parts" else maxima_seeds(mesh)
    for s in seeds:
        d = mesh.distance(s)
        levels, L, _ = profile(mesh, d)
        cut, stop, neck = cut_radius(mesh, d, mesh.area.sum())
        share = mesh.area[d[f].mean(1) < cut].sum() / mesh.area.sum()
        print(f"seed {s} at {np.round(v[s], 3).tolist()}: r_stop {stop:.3f}, neck {neck}, cut {cut:.3f}, "
              f"area share {share:.3f}")
        print("  L every 0.01: " + " ".join(f"{x:.2f}" for x in L[::5][:60]))


def label_seeds(names):
    """A diagnostic, not a rule: the cut from a seed placed with the labels (the labelled ball's
    lowest vertex for a foot or the paws, its highest for the kitten's head), to tell a seed that
    misses a part from a part whose L(r) has no neck."""
    for name in names:
        v, f, mesh = load(common.mesh_path(name))
        cent = common.face_centroids(v, f)
        for part, P, r in labels.parts_of(name, v):
            ball = np.flatnonzero(np.linalg.norm(v - P, axis=1) <= r)
            if "foot" in part or "paws" in part:
                s = int(ball[np.argmin(v[ball, 1])])
            elif name == "kitten" and part == "head":
                s = int(ball[np.argmax(v[ball, 1])])
            else:
                continue
            d = mesh.distance(s)
            cut, stop, neck = cut_radius(mesh, d, mesh.area.sum())
            reg = mesh.largest_piece(d[f].mean(axis=1) < cut)
            lab = np.linalg.norm(cent - P, axis=1) <= r
            L = profile(mesh, d)[1]
            print(f"{name} {part}: seed {s}, r_stop {stop:.3f}, neck {neck}, cut {cut:.3f}, area share "
                  f"{mesh.area[reg].sum() / mesh.area.sum():.3f}, IoU {common.best_iou(lab, [reg], mesh.area):.2f}")
            print("  L every 0.02: " + " ".join(f"{x:.2f}" for x in L[::10][:30]))


def elk_feet(exe):
    """A diagnostic of labels.py's elk feet: the lowest vertex of each quadrant about the median
    (x, z) is a foot's bottom only if each quadrant holds one foot. Prints, per labelled foot,
    whether its bottom is the lowest vertex within 15 units (in x, z), and scores each column
    against the foot the quadrants miss: labels.py's ball (25 up, radius 27) about the lowest
    vertex within 15 of (26.8, 28.3), read off the neck regions' lowest vertices."""
    path = common.mesh_path("elk")
    with tempfile.TemporaryDirectory() as tmp:
        v, f, mesh, regs = all_columns(exe, path, tmp, "parts")
        parts = common.face_masks(common.auto_regions(exe, path, tmp, ["--method", "parts"])[0], len(f))
    for p in parts:  # each neck region: its seed, the centre and mean radius of its rim, its span
        s = deepest_vertex(mesh, p)
        d = mesh.distance(s)
        cut, _, neck = cut_radius(mesh, d, mesh.area.sum())
        if neck is None:
            continue
        reg = mesh.largest_piece(d[f].mean(axis=1) < cut)
        rim = v[np.unique(mesh.edge_vertices[(mesh.edge_face @ reg.astype(float)) == 1])]
        span = v[np.unique(f[reg])]
        print(f"neck region of seed {s} at {np.round(v[s], 1).tolist()}: rim centre "
              f"{np.round(rim.mean(0), 1).tolist()}, "
              f"rim radius {np.linalg.norm(rim - rim.mean(0), axis=1).mean():.1f}, "
              f"span {np.round(span.min(0), 1).tolist()} to {np.round(span.max(0), 1).tolist()}")
    for part, P, r in labels.parts_of("elk", v)[:4]:
        near = np.linalg.norm(v[:, [0, 2]] - P[[0, 2]], axis=1) < 15
        print(f"elk {part}: bottom y {P[1] - 25:.1f}, lowest y within 15 in (x, z) {v[near, 1].min():.1f}")
    near = np.flatnonzero(np.linalg.norm(v[:, [0, 2]] - np.array([26.8, 28.3]), axis=1) < 15)
    bottom = v[near[np.argmin(v[near, 1])]]
    part = np.linalg.norm(common.face_centroids(v, f) - (bottom + [0, 25.0, 0]), axis=1) <= 27.0
    print(f"unlabelled foot at {np.round(bottom, 1).tolist()}, {int(part.sum())} faces: " +
          ", ".join(f"{c} {common.best_iou(part, rs, mesh.area):.2f}" for c, rs in regs.items()))


def timing(exe):
    """Stage times on bear and bear split in sixteen (the seeds' parts regions not timed)."""
    v, f = common.read_off(common.mesh_path("bear"))
    v16, f16 = bench_selection.split_in_four(*bench_selection.split_in_four(v, f))
    with tempfile.TemporaryDirectory() as tmp:
        for label, (vv, ff) in (("bear", (v, f)), ("bear x16", (v16, f16))):
            path = os.path.join(tmp, "m.off")
            bench_selection.write_off(path, vv, ff)
            parts = common.auto_regions(exe, path, tmp, ["--method", "parts"])[0]
            t0 = time.perf_counter()
            D = float(np.linalg.norm(vv.max(0) - vv.min(0)))
            mesh = G.Mesh((vv - vv.min(0)) / D, ff)
            if not G.Mesh.dijkstra:
                mesh.distance(0)  # the factorisations, timed with the set-up
            t1 = time.perf_counter()
            pm = common.face_masks(parts, len(ff))
            seeds = [deepest_vertex(mesh, m) for m in pm]
            t2 = time.perf_counter()
            regs = neck_regions(mesh, seeds)
            t3 = time.perf_counter()
            print(f"{label}: {len(ff)} faces, {len(seeds)} seeds, {len(regs)} regions: set-up and "
                  f"factorisations {t1 - t0:.2f} s, seeds {t2 - t1:.2f} s, necks {t3 - t2:.2f} s "
                  f"({(t3 - t2) / max(len(seeds), 1):.2f} s per seed), total {t3 - t0:.2f} s")


def main():
    global NECK, STOP
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--seeds", choices=["parts", "maxima"], default="parts")
    ap.add_argument("--curves")
    ap.add_argument("--time", action="store_true")
    ap.add_argument("--distance", choices=["heat", "dijkstra"], default="heat")
    ap.add_argument("--label-seeds", action="store_true", help="diagnostic: seeds placed with the labels")
    ap.add_argument("--neck", type=float, default=NECK, help="sensitivity: the neck ratio (0.85)")
    ap.add_argument("--stop", type=float, default=STOP, help="sensitivity: the stop share of L' (0.25)")
    a = ap.parse_args()
    NECK, STOP = a.neck, a.stop
    G.Mesh.dijkstra = a.distance == "dijkstra"
    exe = os.path.join(a.build, "shellcontract")
    if a.curves:
        return curves(exe, a.curves, a.seeds)
    if a.time:
        return timing(exe)
    if a.label_seeds:
        label_seeds(["elk", "kitten"])
        return elk_feet(exe)
    cols = ["necks", "necks+fb", "nest", "nest+fb", "wrap+fb", "neck-only+fb", "parts"]
    res = {c: {"parts": [], "bumps": [], "comp": [], "n": []} for c in cols}
    with tempfile.TemporaryDirectory() as tmp:
        for name in common.PAPER + ["bumpy_sphere"]:
            path = common.mesh_path(name)
            v, f, mesh, regs = all_columns(exe, path, tmp, a.seeds)
            area, cent = mesh.area, common.face_centroids(v, f)
            for c in cols:
                res[c]["n"].append(len(regs[c]))
                res[c]["comp"] += [mesh.compactness(m) for m in regs[c]]
                if name == "bumpy_sphere":
                    listed = os.path.join(common.ROOT, "meshes", "bumpy_sphere.bumps.txt")
                    bumps = common.face_masks(common.read_face_list(listed), len(f))
                    res[c]["bumps"] = [common.best_iou(b, regs[c], area) for b in bumps]
                    continue
                for part, P, r in labels.parts_of(name, v):
                    mask = np.linalg.norm(cent - P, axis=1) <= r
                    res[c]["parts"].append((name, part, common.best_iou(mask, regs[c], area)))
        v, f = common.read_off(common.mesh_path("bear"))
        v4, f4 = bench_selection.split_in_four(v, f)
        fine = os.path.join(tmp, "bear4.off")
        bench_selection.write_off(fine, v4, f4)
        _, _, _, coarse = all_columns(exe, common.mesh_path("bear"), tmp, a.seeds)
        _, _, mesh4, finer = all_columns(exe, fine, tmp, a.seeds)
        for c in cols:
            cm = [np.repeat(m, 4) for m in coarse[c]]
            ious = ([common.best_iou(m, finer[c], mesh4.area) for m in cm]
                    + [common.best_iou(m, cm, mesh4.area) for m in finer[c]])
            res[c]["sub"] = min(ious) if ious else 0.0
    common.print_rule_table(res, cols, [f"{m} {p}" for m, p, _ in res["parts"]["parts"]],
                            lambda c: " ".join(map(str, res[c]["n"])))


if __name__ == "__main__":
    main()
