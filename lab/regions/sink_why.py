#!/usr/bin/python3
"""Which of the finder's regions limit issue 55 point 2, and why (lab/regions/sink_why.md).

For each mesh: the regions `shellcontract regions MESH` finds, then `run MESH -p 0` (sink.py's
run: 200 frames, --validate end) with all of them, with each ALONE and with all BUT each one.
Every run is measured on the same vertex sets as sink.py: a region's sink is the mean inward
displacement of its vertices along the rest normal; the rest is the mean displacement of the
vertices outside ALL the regions and their one-ring band (so the runs with fewer regions are
measured on the same rest vertices); both / the bounding-box diagonal.

Per region it prints:
  - the finder's table row (radius, area share, compactness, fit residual);
  - its geometry at rest: cap height (largest height of a region vertex above its rim's
    best-fit plane), the rim's planarity (rms and largest distance of the rim vertices from
    that plane, in mean edge lengths of the region), whether make_region_dimple cuts it
    (a Python copy of region_dimple.cpp's cut: CUT_TOLERANCE 3 edges, tilts 0-60 degrees),
    whether its mirror falls back to the volume projection (no interior vertex), and the
    sink its dimple's mirror image at rest gives (the dimple: the first faces of the dimple
    order whose rest cap volume reaches --region-shrink times the region's, rho = 1; in
    brackets with the crease ring left where it is); that image's depth, how many of its
    vertices (of those more than an edge deep) lie outside the rest shell (winding number
    < 0.25), and the largest strength (1, 0.9, ..., 0.1 of --region-shrink) whose image stays
    inside (inside_strength);
  - its sink alone, with all, and with all but it; the rest alone, and the rest with all minus
    the rest with all but it (its marginal share); alone with --collisions off, the rest and
    the new self-intersections (what the contacts do).
Then the map of the rest with all regions: by distance to the nearest region vertex, and per
nearest region, near (< 0.1 diag) and far; the rest with the best rigid motion of the rest
vertices removed (Kabsch), and that rigid motion's size.

Usage: /usr/bin/python3 lab/regions/sink_why.py [--build DIR] [--meshes bear,hand,elk]
       [--shrink 0.7] [--run-args "..."] [--out FILE]   (prints markdown; --out also writes it)
"""
import argparse
import os
import sys
import tempfile

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from rest_motion import kabsch  # noqa: E402
from sink import per_region_sink, run  # noqa: E402

CUT_TOLERANCE = 3.0  # src/sim/region_dimple.hpp


def region_table(stdout):
    """The finder's printed table: id -> (radius, area %, faces, compactness, residual, angle)."""
    rows, on = {}, False
    for line in stdout.splitlines():
        if line.strip().startswith("id "):
            on = True
            continue
        t = line.split()
        if on and len(t) >= 10 and t[0].isdigit():
            rows[int(t[0])] = tuple(float(x) for x in t[-6:])
    return rows


def rim_edges(faces, region):
    directed = {}
    for f in region:
        a, b, c = faces[f]
        for i, j in ((a, b), (b, c), (c, a)):
            directed[(i, j)] = True
    return [(i, j) for (i, j) in directed if (j, i) not in directed]


def cap_volume(x, faces, region):
    """region_volume.cpp's cap_volume: the region closed by the fan from its rim's centroid."""
    if not region:
        return 0.0
    rim = rim_edges(faces, region)
    f = faces[region]
    det = np.einsum("ij,ij->i", x[f[:, 0]], np.cross(x[f[:, 1]], x[f[:, 2]])).sum()
    if not rim:
        return det / 6.0
    e = np.array(rim)
    c = x[np.unique(e.ravel())].mean(0)
    return (det - c @ np.cross(x[e[:, 0]], x[e[:, 1]]).sum(0)) / 6.0


def plane_fit(p):
    c = p.mean(0)
    _, s, vt = np.linalg.svd(p - c)
    return c, vt[2]


def dimple_order(rest, faces, region):
    """region_dimple.cpp's make_region_dimple: (order, limit, cut?, axis) at rest."""
    region = sorted(set(region))
    f = faces[region]
    a, b, c = rest[f[:, 0]], rest[f[:, 1]], rest[f[:, 2]]
    normal = np.cross(b - a, c - a).sum(0)
    edge = (np.linalg.norm(b - a, axis=1) + np.linalg.norm(c - b, axis=1) + np.linalg.norm(a - c, axis=1)).mean() / 3
    rim_v = np.unique(np.array(rim_edges(faces, region)).ravel())
    rc = rest[rim_v].mean(0)
    verts = np.unique(f.ravel())
    apex = verts[np.argmax((rest[verts] - rc) @ normal)]
    cent = (a + b + c) / 3
    order = [region[i] for i in np.argsort(((cent - rest[apex]) ** 2).sum(1), kind="stable")]
    n0 = normal / np.linalg.norm(normal)
    q = rest[rim_v] - rc
    rise = ((q @ n0)[:, None] * (q - np.outer(q @ n0, n0))).sum(0)
    u = rise / np.linalg.norm(rise) if np.linalg.norm(rise) > 1e-9 * edge * edge * len(rim_v) else None
    if u is None:
        ax = int(np.argmin(np.abs(n0)))
        u = np.cross(n0, np.eye(3)[ax])
        u /= np.linalg.norm(u)
    w = np.cross(n0, u)
    lows = lambda axis: np.minimum(np.minimum(rest[faces[order, 0]] @ axis, rest[faces[order, 1]] @ axis),  # noqa
                                   rest[faces[order, 2]] @ axis)
    best, best_axis, best_h = -np.inf, n0, 0.0
    for tilt in range(7):
        for az in range(1 if tilt == 0 else 12):
            t, ang = np.radians(10 * tilt), 2 * np.pi * az / 12
            axis = np.cos(t) * n0 + np.sin(t) * (np.cos(ang) * u + np.sin(ang) * w)
            axis /= np.linalg.norm(axis)
            h = (rest[rim_v] @ axis).max() - CUT_TOLERANCE * edge
            kept = [order[i] for i in np.flatnonzero(lows(axis) >= h)]
            vol = cap_volume(rest, faces, kept)
            if vol > best:
                best, best_axis, best_h = vol, axis, h
    low = lows(best_axis)
    kept = int((low >= best_h).sum())
    if kept < len(order):
        order = [order[i] for i in np.argsort(-low, kind="stable")]
        return order, kept, True, edge
    return order, len(order), False, edge


def winding(p, v, f):
    """Generalized winding number of points p about the closed mesh (v, f): 1 inside, 0 outside."""
    a, b, c = (v[f[:, k]][None] - p[:, None] for k in range(3))
    la, lb, lc = (np.linalg.norm(x, axis=2) for x in (a, b, c))
    det = np.einsum("pfi,pfi->pf", a, np.cross(b, c))
    den = (la * lb * lc + np.einsum("pfi,pfi->pf", a, b) * lc + np.einsum("pfi,pfi->pf", b, c) * la
           + np.einsum("pfi,pfi->pf", c, a) * lb)
    return (2 * np.arctan2(det, den)).sum(1) / (4 * np.pi)


def dimple_image(rest, faces, region, order, limit, shrink):
    """The dimple of strength `shrink` at rho = 1 (the first faces of the dimple order whose rest
    cap volume reaches shrink times the region's) and its mirror plane (region_mirror.cpp: through
    its rim's centroid, normal to its area vector). Returns (dimple faces, rim vertices, interior
    vertices, their signed heights above the plane, the plane's normal)."""
    whole = cap_volume(rest, faces, region)
    k = next((i for i in range(1, limit + 1) if cap_volume(rest, faces, order[:i]) >= shrink * whole), limit)
    dimple = order[:k]
    drim = np.unique(np.array(rim_edges(faces, dimple)).ravel())
    interior = np.setdiff1d(np.unique(faces[dimple].ravel()), drim)
    f = faces[dimple]
    area = np.cross(rest[f[:, 1]] - rest[f[:, 0]], rest[f[:, 2]] - rest[f[:, 0]]).sum(0)
    pn = area / np.linalg.norm(area)
    return dimple, drim, interior, (rest[interior] - rest[drim].mean(0)) @ pn, pn


def image_outside(rest, faces, interior, d, pn, edge):
    """How many of the dimple's interior vertices more than an edge above the plane have their
    mirror image outside the rest shell (winding < 0.25), and how many such vertices there are.
    Nearer the plane (a ragged rim) the image lies within an edge of the surface: not counted."""
    deep = d > edge
    if not deep.any():
        return 0, 0
    img = rest[interior][deep] - 2 * d[deep][:, None] * pn
    w = np.concatenate([winding(img[s:s + 200], rest, faces) for s in range(0, len(img), 200)])
    return int((w < 0.25).sum()), int(deep.sum())


def inside_strength(rest, faces, region, shrink=0.7):
    """The largest strength t in 1, 0.9, ..., 0.1 (of `shrink`) whose dimple's mirror image stays
    inside the rest shell (image_outside 0); 0 when none does."""
    order, limit, _, edge = dimple_order(rest, faces, region)
    for t in [1.0, .9, .8, .7, .6, .5, .4, .3, .2, .1]:
        _, _, interior, d, pn = dimple_image(rest, faces, region, order, limit, shrink * t)
        if len(interior) and image_outside(rest, faces, interior, d, pn, edge)[0] == 0:
            return t
    return 0.0


def geometry(rest, faces, region, normals, diag, shrink):
    verts = np.unique(faces[region].ravel())
    rim_v = np.unique(np.array(rim_edges(faces, region)).ravel())
    order, limit, cut, edge = dimple_order(rest, faces, region)
    c, n = plane_fit(rest[rim_v])
    if ((rest[verts] - c) @ n).sum() < 0:
        n = -n
    height = float(((rest[verts] - c) @ n).max())
    off = np.abs((rest[rim_v] - c) @ n)
    dimple, drim, interior, d, pn = dimple_image(rest, faces, region, order, limit, shrink)
    move = np.zeros(len(rest))
    move[interior] = np.einsum("ij,ij->i", 2 * d[:, None] * pn[None, :], normals[interior])
    # The crease ring (interior vertices sharing a face with the dimple's rim) is left to the
    # solver in the product: without it, the placed vertices' share of the sink.
    onrim = np.zeros(len(rest), bool)
    onrim[drim] = True
    ring = np.zeros(len(rest), bool)
    ring[faces[dimple][onrim[faces[dimple]].any(1)].ravel()] = True
    placed = move * ~(ring | onrim)
    out, deep = image_outside(rest, faces, interior, d, pn, edge)
    return dict(mirror_placed=float(placed[verts].mean()) / diag, height=height / diag,
                rim_rms=float(np.sqrt((off ** 2).mean())) / edge, rim_max=float(off.max()) / edge,
                cut=cut, kept=f"{limit}/{len(order)}", fallback=len(interior) == 0,
                mirror=float(move[verts].mean()) / diag, dimple_faces=len(dimple),
                image_out=f"{out}/{deep}", depth=float(2 * d.max()) / diag if len(d) else 0.0,
                inside=inside_strength(rest, faces, region, shrink))


def rest_set(faces, regions, nv):
    inr = np.zeros(nv, bool)
    for r in regions:
        inr[faces[r].ravel()] = True
    band = inr.copy()
    band[faces[inr[faces].any(1)].ravel()] = True
    return ~band


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--meshes", default="bear,hand,elk")
    ap.add_argument("--shrink", type=float, default=0.7, help="the run's --region-shrink (the default)")
    ap.add_argument("--run-args", default="")
    ap.add_argument("--out", default="")
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    extra = a.run_args.split() + (["--region-shrink", str(a.shrink)] if a.shrink != 0.7 else [])
    md = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, path, rest, faces, diag in common.each_mesh(a.meshes.split(",")):
            normals = common.rest_normals(rest, faces)
            regions, out, _ = common.auto_regions(exe, path, tmp)
            table = region_table(out)
            out_mask = rest_set(faces, regions, len(rest))
            areas = common.face_areas(rest, faces)

            def measure(sub, more=()):
                fl = os.path.join(tmp, "sub.txt")
                with open(fl, "w") as fo:
                    fo.write("".join(" ".join(map(str, regions[i])) + "\n" for i in sub))
                s, end = run(exe, path, tmp, ["--regions", fl, "-p", "0"] + extra + list(more))
                d = np.linalg.norm(end - rest, axis=1)
                sinks = per_region_sink(rest, faces, end, regions)
                return dict(end=end, sinks=sinks, rest=float(d[out_mask].mean()) / diag,
                            vr=s.get("final_volume_ratio"), new=s.get("new_intersections"))

            n = len(regions)
            every = measure(range(n))
            alone = [measure([i]) for i in range(n)]
            but = [measure([j for j in range(n) if j != i]) for i in range(n)]
            free = [measure([i], ["--collisions", "off"]) for i in range(n)]
            first = len(md)
            md.append(f"### {name}: {n} regions, all together: rest {every['rest']:.5f}, smallest sink "
                      f"{min(every['sinks']) / diag:.4f}, rest / smallest sink "
                      f"{every['rest'] / (min(every['sinks']) / diag):.3f}, V/V0 {every['vr']:.3f}, "
                      f"new intersections {every['new']}\n")
            geo = [geometry(rest, faces, r, normals, diag, a.shrink) for r in regions]
            md.append("Geometry at rest (radius from the finder's table; cap height, image depth: / diag; rim off "
                      "its plane: rms, largest, in mean edges; image outside: vertices deeper than an edge whose "
                      "mirror image lies outside the shell, of those):\n")
            md.append("| id | faces | area % | radius | compact. | residual | cap height | rim off plane | cut "
                      "| mirror at rest: sink (crease ring left) | image depth | image outside "
                      "| largest strength inside |")
            md.append("|" + "---|" * 13)
            for i, g in enumerate(geo):
                t = table.get(i, (np.nan,) * 6)
                md.append(f"| {i} | {len(regions[i])} | {areas[regions[i]].sum() / areas.sum() * 100:.2f} | "
                          f"{t[0] / diag:.3f} | {t[3]:.2f} | {t[4]:.3f} | {g['height']:.4f} | "
                          f"{g['rim_rms']:.1f}, {g['rim_max']:.1f} | "
                          f"{'yes, ' + g['kept'] + ' faces above' if g['cut'] else 'no'}"
                          f"{' (volume fallback)' if g['fallback'] else ''} | "
                          f"{g['mirror']:.4f} ({g['mirror_placed']:.4f}) | {g['depth']:.4f} | {g['image_out']} | "
                          f"{g['inside']:.1f} |")
            md.append("\nRuns at -p 0 (sinks and rests / diag; \"rest all - all but it\": the rest with every region "
                      "minus the rest without this one):\n")
            md.append("| id | sink alone | sink with all | sink all but it | rest alone | rest alone / sink alone "
                      "| rest all - all but it | V/V0 alone | alone, collisions off: rest, new intersections |")
            md.append("|" + "---|" * 9)
            for i in range(n):
                sa = alone[i]["sinks"][i] / diag
                md.append(f"| {i} | {sa:.4f} | {every['sinks'][i] / diag:.4f} | {but[i]['sinks'][i] / diag:.4f} | "
                          f"{alone[i]['rest']:.5f} | {alone[i]['rest'] / sa if sa > 0 else np.inf:.3f} | "
                          f"{every['rest'] - but[i]['rest']:+.5f} | {alone[i]['vr']:.3f} | "
                          f"{free[i]['rest']:.5f}, {free[i]['new']} |")
            md.append("")

            def ratio_without(i):
                return but[i]["rest"] / (min(x for j, x in enumerate(but[i]["sinks"]) if j != i) / diag)
            md.append(f"Sum of the rests alone: {sum(x['rest'] for x in alone):.5f} (all together "
                      f"{every['rest']:.5f}). All but one, rest / smallest sink: " +
                      ", ".join(f"without {i}: {ratio_without(i):.3f}" for i in range(n)) + ".\n")
            # The map of the rest with every region.
            end = every["end"]
            rv = np.zeros(len(rest), int) - 1
            for i, r in enumerate(regions):
                rv[np.unique(faces[r].ravel())] = i
            tree = cKDTree(rest[rv >= 0])
            dist, idx = tree.query(rest[out_mask])
            nearest = rv[rv >= 0][idx]
            d = np.linalg.norm(end - rest, axis=1)[out_mask] / diag
            rot, cp, cq = kabsch(rest[out_mask], end[out_mask])
            aligned = (rest - cp) @ rot.T + cq
            drig = np.linalg.norm(end - aligned, axis=1)[out_mask] / diag
            angle = np.degrees(np.arccos(np.clip((np.trace(rot) - 1) / 2, -1, 1)))
            md.append(f"Rigid part of the rest's motion: translation {np.linalg.norm(cq - cp) / diag:.5f} diag, "
                      f"turn {angle:.3f} degrees; rest with it removed {drig.mean():.5f} (raw {d.mean():.5f}); "
                      f"95 % {np.percentile(d, 95):.5f}.\n")
            cells = []
            for lo, hi in [(0, .02), (.02, .05), (.05, .1), (.1, .2), (.2, None)]:
                m = (dist >= lo * diag) & ((dist < hi * diag) if hi else True)
                cells.append(f"{lo}-{hi if hi else 'max'}: {m.sum()} vertices, mean "
                             f"{d[m].mean() if m.any() else 0:.5f}, {d[m].sum() / d.sum() * 100:.0f} %")
            md.append("By distance to the nearest region vertex (diag; vertices, their mean motion, their share of "
                      "the summed rest motion): " + "; ".join(cells) + ".\n")
            md.append("| nearest region | rest vertices near (< 0.1 diag), far | mean motion near | far | "
                      "share of the summed rest motion |")
            md.append("|---|---|---|---|---|")
            near = dist < 0.1 * diag
            for i in range(n):
                m = nearest == i
                mn, mf = m & near, m & ~near
                md.append(f"| {i} | {mn.sum()}, {mf.sum()} | {d[mn].mean() if mn.any() else 0:.5f} | "
                          f"{d[mf].mean() if mf.any() else 0:.5f} | {d[m].sum() / d.sum() * 100:.0f} % |")
            md.append("")
            print("\n".join(md[first:]), flush=True)
    text = "\n".join(md) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
