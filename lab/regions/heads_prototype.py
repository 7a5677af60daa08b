#!/usr/bin/python3
"""Heads and bumps as well as limb ends: rules that combine the two finders' regions, measured
on the labelled set (labels.py's parts), on bumpy_sphere's bumps and on bear against bear x4.
A study for lab/regions/heads.md, not product code.

It runs `shellcontract regions MESH --face-list F` (the cap finder) and the same with
`--method tips`, then applies each rule of RULES to the two lists of regions:

- tips:  the tip finder's regions alone (the baseline, iou_table_tips.md);
- union: the tip regions plus every cap region outside them, faces in both to the tip region
  (the naive hybrid of the brief);
- cover: a cap region is kept when at most half of its area is covered by tip regions; a tip
  region is then dropped when more than half of its area lies in a kept cap region, and the
  remaining tip regions win the faces they share with a kept cap region;
- cover1: cover, but a cap region that holds the greater part of two or more tip regions is
  dropped (it spans several ends, as main's cap over three fingertips: a body patch, not a part);
- caps:  the cap finder's regions alone;
- ballF: cover, but each kept cap region (in the cap finder's id order) grows to the faces
  edge-connected to it whose centroid lies within F x R of its fitted sphere's centre (centre,
  R from the `regions` table), taking no face of a kept tip region, of another cap region or of
  a ball grown before; then its largest piece and the filters (at least 10 faces, area share in
  [0.002, 0.25], compactness <= 2); a ball that fails them is dropped;
- ballfF: ballF, but a ball that fails the filters falls back to its cap less the tip faces;
- ballfr: ballf with F = 1 + the cap's fit residual (RMS distance / R, from the table): the
  sphere and the band of its fit's scatter. This is what `--method parts` does
  (src/geometry/part_finder.cpp);
- ballfr+tips: ballfr, then each kept tip region (tip id order) adds the free faces edge-connected
  to it within (1 + residual) R of its own fitted sphere (the tip finder's table), kept when the
  grown region passes the filters;
- ballfr+tips0.03: the same only for tip regions whose fit residual is at most 0.03 (a
  threshold read off these meshes' residuals: not a rule to port);
- ballfr+tipshell: ballfr, then each kept tip region adds the free faces edge-connected to it
  whose three corners lie within a band of its sphere (clamp(2 residual, 0.02, 0.1) R, the band
  of the cap finder's shape_cap): it continues over its sphere, not into the ball.

Every rule's output goes through the same filters (largest piece, faces, area share,
compactness) where it cuts a region. Columns: mean IoU over the 21 labelled parts, parts at
IoU >= 0.5, best IoU of each bumpy_sphere bump (meshes/bumpy_sphere.bumps.txt), the smallest
IoU of a region with its best match on bear split in four (both ways), the largest
compactness P^2 / (4 pi A) of a region, and the region counts.

Usage: /usr/bin/python3 lab/regions/heads_prototype.py [--build build] [--cover C]
(--build: a build of main's finders; --cover: the share C of the cover rules, 0.5 by default)
"""
import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_selection  # noqa: E402
import common  # noqa: E402
import labels  # noqa: E402


def rule_union(caps, tips, area):
    taken = np.zeros_like(caps[0]) if caps else None
    for t in tips:
        taken = t if taken is None else (taken | t)
    out = list(tips)
    for c in caps:
        rest = c & ~taken if taken is not None else c
        if rest.any():
            out.append(rest)
    return out


def rule_cover(caps, tips, area, cover=0.5, several=False):
    tip_any = np.zeros(len(area), bool)
    for t in tips:
        tip_any |= t
    kept_caps = []
    for c in caps:
        covered = area[c & tip_any].sum() / area[c].sum()
        if covered > cover:
            continue
        if several:
            held = sum(area[c & t].sum() > 0.5 * area[t].sum() for t in tips)
            if held >= 2:
                continue
        kept_caps.append(c)
    cap_any = np.zeros(len(area), bool)
    for c in kept_caps:
        cap_any |= c
    kept_tips = [t for t in tips if not any(area[t & c].sum() > 0.5 * area[t].sum() for c in kept_caps)]
    tip_any = np.zeros(len(area), bool)
    for t in kept_tips:
        tip_any |= t
    out = list(kept_tips)
    for c in kept_caps:
        piece = largest_piece(c & ~tip_any, area)
        if piece is not None and passes(piece, area):
            out.append(piece)
    return out


FACES = None  # the current mesh's faces (set in main), for pieces and perimeters


def edge_map():
    """Per face its three edge neighbours (-1 on a border) and the edge lengths' owner keys."""
    f = FACES
    edges = {}
    for i, t in enumerate(f):
        for k in range(3):
            a, b = sorted((t[k], t[(k + 1) % 3]))
            edges.setdefault((a, b), []).append(i)
    return edges


def largest_piece(mask, area):
    """The largest edge-connected piece of mask by area (ties: smallest face), as the product."""
    if not mask.any():
        return None
    edges = EDGES
    nbr = {}
    for fs in edges.values():
        if len(fs) == 2 and mask[fs[0]] and mask[fs[1]]:
            nbr.setdefault(fs[0], []).append(fs[1])
            nbr.setdefault(fs[1], []).append(fs[0])
    seen = np.zeros(len(mask), bool)
    best, best_area = None, -1.0
    for s in np.flatnonzero(mask):
        if seen[s]:
            continue
        comp, stack = [s], [s]
        seen[s] = True
        while stack:
            u = stack.pop()
            for w in nbr.get(u, []):
                if not seen[w]:
                    seen[w] = True
                    comp.append(w)
                    stack.append(w)
        a = area[comp].sum()
        if a > best_area:
            best, best_area = comp, a
    out = np.zeros(len(mask), bool)
    out[best] = True
    return out


def compactness(mask):
    per = 0.0
    for (a, b), fs in EDGES.items():
        if sum(mask[x] for x in fs) == 1:
            per += np.linalg.norm(VERTS[a] - VERTS[b])
    ar = AREA[mask].sum()
    return per * per / (4 * np.pi * ar)


def passes(mask, area, min_faces=10, lo=0.002, hi=0.25, comp=2.0):
    share = area[mask].sum() / area.sum()
    return mask.sum() >= min_faces and lo <= share <= hi and compactness(mask) <= comp


RULES = {
    "tips": lambda c, t, a, k: t,
    "caps": lambda c, t, a, k: c,
    "union": lambda c, t, a, k: rule_union(c, t, a),
    "cover": lambda c, t, a, k: rule_cover(c, t, a, k),
    "cover1": lambda c, t, a, k: rule_cover(c, t, a, k, several=True),
    "ball1.0": lambda c, t, a, k: rule_ball(c, t, a, k, 1.0),
    "ball1.1": lambda c, t, a, k: rule_ball(c, t, a, k, 1.1),
    "ball1.2": lambda c, t, a, k: rule_ball(c, t, a, k, 1.2),
    "ballf1.0": lambda c, t, a, k: rule_ball(c, t, a, k, 1.0, True),
    "ballf1.1": lambda c, t, a, k: rule_ball(c, t, a, k, 1.1, True),
    "ballfr": lambda c, t, a, k: rule_ball(c, t, a, k, "residual", True),
    "ballfr+tips": lambda c, t, a, k: rule_ball(c, t, a, k, "residual", True, True),
    "ballfr+tips0.03": lambda c, t, a, k: rule_ball(c, t, a, k, "residual", True, True, 0.03),
    "ballfr+tipshell": lambda c, t, a, k: rule_ball(c, t, a, k, "residual", True, True, np.inf, True),
}


def spheres(table):
    """(centre, radius) per region from the printed table of `shellcontract regions`."""
    out = []
    for line in table.splitlines():
        t = line.replace(",", " ").split()
        if len(t) >= 9 and t[0].isdigit():
            out.append((np.array([float(t[1]), float(t[2]), float(t[3])]), float(t[4]), float(t[8])))
    return out


def both(exe, path, tmp, nf):
    global CAP_SPHERES, TIP_SPHERES
    caps, table, _ = common.auto_regions(exe, path, tmp)
    CAP_SPHERES = spheres(table)
    tips, table, _ = common.auto_regions(exe, path, tmp, ["--method", "tips"])
    TIP_SPHERES = spheres(table)
    return common.face_masks(caps, nf), common.face_masks(tips, nf)


def rule_ball(caps, tips, area, cover=0.5, factor=1.0, fallback=False, tip_balls=False, tip_fit=np.inf,
              tip_shell=False):
    """cover, then each kept cap region grows to the faces edge-connected to it whose centroid
    lies within factor x R of its fitted sphere's centre (a head is a ball, more than the
    hemisphere the cap finder clips it to), not entering another cap region or a kept tip."""
    tip_any = np.zeros(len(area), bool)
    for t in tips:
        tip_any |= t
    kept = [k for k, c in enumerate(caps) if area[c & tip_any].sum() <= cover * area[c].sum()]
    kept_tips = [t for t in tips if not any(area[t & caps[k]].sum() > 0.5 * area[t].sum() for k in kept)]
    tip_any = np.zeros(len(area), bool)
    for t in kept_tips:
        tip_any |= t
    cap_any = np.zeros(len(area), bool)
    for c in caps:
        cap_any |= c
    cent = CENT
    out = list(kept_tips)
    claimed = np.zeros(len(area), bool)  # faces of the balls already grown (cap id order)
    for k in kept:
        centre, radius, residual = CAP_SPHERES[k]
        # "residual": the ball and the band of the fit's RMS distance outside it
        scale = 1.0 + residual if factor == "residual" else factor
        inside = (np.linalg.norm(cent - centre, axis=1) <= scale * radius) & ~tip_any & (~cap_any | caps[k]) & ~claimed
        grown = connected_to(inside | (caps[k] & ~tip_any), caps[k] & ~tip_any)
        piece = largest_piece(grown & ~tip_any, area)
        if piece is not None and passes(piece, area):
            out.append(piece)
            claimed |= piece
        elif fallback:  # the ball is not a part (too wide, not compact): the cap as in cover
            piece = largest_piece(caps[k] & ~tip_any, area)
            if piece is not None and passes(piece, area):
                out.append(piece)
                claimed |= piece
    if tip_balls:  # each kept tip region adds the free faces of its own sphere's ball
        taken = claimed | tip_any
        tip_index = [k for k, t in enumerate(tips) if any(t is kt for kt in kept_tips)]
        for j, k in enumerate(tip_index):
            centre, radius, residual = TIP_SPHERES[k]
            if residual > tip_fit:  # only a tip region that is a ball (its sphere fits closely)
                continue
            t = out[j]
            if tip_shell:  # faces whose corners all lie on the sphere, as the cap finder's shape_cap
                band = min(max(2.0 * residual, 0.02), 0.1) * radius
                dist = np.abs(np.linalg.norm(VERTS[FACES] - centre, axis=2) - radius)
                inside = (dist.max(axis=1) <= band) & ~taken
            else:
                inside = (np.linalg.norm(cent - centre, axis=1) <= (1.0 + residual) * radius) & ~taken
            grown = largest_piece(connected_to(inside | t, t), area)
            if grown is not None and passes(grown, area):
                taken |= grown
                out[j] = grown
    return out


def connected_to(mask, seed):
    """Faces of mask edge-connected to a face of seed."""
    nbr = {}
    for fs in EDGES.values():
        if len(fs) == 2 and mask[fs[0]] and mask[fs[1]]:
            nbr.setdefault(fs[0], []).append(fs[1])
            nbr.setdefault(fs[1], []).append(fs[0])
    seen = seed & mask
    stack = list(np.flatnonzero(seen))
    while stack:
        u = stack.pop()
        for w in nbr.get(u, []):
            if not seen[w]:
                seen[w] = True
                stack.append(w)
    return seen


def main():
    global FACES, EDGES, VERTS, AREA, CENT, CAP_SPHERES, TIP_SPHERES
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--cover", type=float, default=0.5)
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    res = {r: {"parts": [], "bumps": [], "sub": None, "n": {}} for r in RULES}
    with tempfile.TemporaryDirectory() as tmp:
        for name in common.PAPER + ["bumpy_sphere"]:
            path = common.mesh_path(name)
            v, f = common.read_off(path)
            area, cent = common.face_areas(v, f), common.face_centroids(v, f)
            caps, tips = both(exe, path, tmp, len(f))
            FACES, VERTS, AREA = f, v, area
            CENT = common.face_centroids(v, f)
            EDGES = edge_map()
            if name == "bumpy_sphere":
                listed = os.path.join(common.ROOT, "meshes", "bumpy_sphere.bumps.txt")
                bumps = common.face_masks(common.read_face_list(listed), len(f))
            for rn, rule in RULES.items():
                regs = rule(caps, tips, area, a.cover)
                res[rn]["n"][name] = len(regs)
                res[rn].setdefault("comp", []).extend(compactness(m) for m in regs)
                if name == "bumpy_sphere":
                    res[rn]["bumps"] = [common.best_iou(b, regs, area) for b in bumps]
                    continue
                for part, P, r in labels.parts_of(name, v):
                    mask = np.linalg.norm(cent - P, axis=1) <= r
                    res[rn]["parts"].append((name, part, common.best_iou(mask, regs, area)))
        # bear against bear x4
        v, f = common.read_off(common.mesh_path("bear"))
        v4, f4 = bench_selection.split_in_four(v, f)
        fine = os.path.join(tmp, "bear4.off")
        bench_selection.write_off(fine, v4, f4)
        area4 = common.face_areas(v4, f4)
        cc, ct = both(exe, common.mesh_path("bear"), tmp, len(f))
        sph_c, tsph_c = CAP_SPHERES, TIP_SPHERES
        fc, ft = both(exe, fine, tmp, len(f4))
        sph_f, tsph_f = CAP_SPHERES, TIP_SPHERES
        area = common.face_areas(v, f)
        for rn, rule in RULES.items():
            FACES, VERTS, AREA, CAP_SPHERES, TIP_SPHERES = f, v, area, sph_c, tsph_c
            CENT = common.face_centroids(v, f)
            EDGES = edge_map()
            coarse = [np.repeat(m, 4) for m in rule(cc, ct, area, a.cover)]
            FACES, VERTS, AREA, CAP_SPHERES, TIP_SPHERES = f4, v4, area4, sph_f, tsph_f
            CENT = common.face_centroids(v4, f4)
            EDGES = edge_map()
            finer = rule(fc, ft, area4, a.cover)
            ious = [common.best_iou(m, finer, area4) for m in coarse] + [common.best_iou(m, coarse, area4) for m in finer]
            res[rn]["sub"] = min(ious) if ious else 0.0
    common.print_rule_table(res, RULES, [f"{m} {p}" for m, p, _ in res["tips"]["parts"]],
                            lambda r: " ".join(str(res[r]["n"][m]) for m in common.PAPER + ["bumpy_sphere"]))


if __name__ == "__main__":
    main()
