#!/usr/bin/python3
"""Per-region properties at rest on the five meshes (main's finder) and per-region runs at -p 0.
Columns: regions table (radius/diag, area %, compactness, residual, cap angle), sink_why.geometry
pieces (cap height/diag, mirror-at-rest sink/diag, image depth/diag, image outside), concave and
saddle vertex share (PLY curvatures, area-weighted by vertex one-ring area/3), nearest other
region (min vertex distance / diag), centre gap / (r_i + r_j), room share (room.py's first_hit
not recomputed: taken from room.log). Runs (-p 0, default frames): sink alone, sink with all,
rest alone, rest(all) - rest(all but it), rest measured outside ALL regions and their band.
Usage: props.py OUT.json"""
import json, os, subprocess, sys, tempfile
sys.path.insert(0, "/work/main/lab/regions")
import numpy as np
import common
from sink_why import region_table, geometry, rest_set, run, per_region_sink
import sink_why
sink_why.inside_strength = lambda *a, **k: float("nan")   # skip the strength scan (slow on bear)
EXE = "/work/main/build/shellcontract"

def read_ply_curv(path, nv):
    lines = open(path).read().split("\n")
    h = lines.index("end_header")
    vals = np.array([list(map(float, l.split()[3:5])) for l in lines[h + 1:h + 1 + nv]])
    return vals[:, 0], vals[:, 1]

res = {}
for name, path, rest, faces, diag in common.each_mesh(["bear", "hand", "elk", "kitten", "bumpy_sphere"]):
    with tempfile.TemporaryDirectory() as tmp:
        regions, out, ply = common.auto_regions(EXE, path, tmp)
        table = region_table(out)
        H, K = read_ply_curv(ply, len(rest))
        normals = common.rest_normals(rest, faces)
        areas = common.face_areas(rest, faces)
        va = np.zeros(len(rest)); 
        for k in range(3): np.add.at(va, faces[:, k], areas / 3)
        out_mask = rest_set(faces, regions, len(rest))
        def measure(sub):
            fl = os.path.join(tmp, "sub.txt")
            open(fl, "w").write("".join(" ".join(map(str, regions[i])) + "\n" for i in sub))
            s, end = run(EXE, path, tmp, ["--regions", fl, "-p", "0"])
            d = np.linalg.norm(end - rest, axis=1)
            return per_region_sink(rest, faces, end, regions), float(d[out_mask].mean()) / diag
        n = len(regions)
        s_all, r_all = measure(range(n))
        rows = []
        vsets = [np.unique(faces[r].ravel()) for r in regions]
        for i, reg in enumerate(regions):
            g = geometry(rest, faces, reg, normals, diag, 0.7)
            t = table.get(i)
            vs = vsets[i]
            w = va[vs]
            near = min([float(np.min(np.linalg.norm(rest[vs][:, None] - rest[vsets[j]][None], axis=2)))
                        for j in range(n) if j != i], default=np.inf) / diag
            sa, ra = measure([i])
            sb, rb = measure([j for j in range(n) if j != i])
            rows.append(dict(id=i, faces=len(reg), area=float(areas[reg].sum() / areas.sum() * 100),
                             radius=t[0] / diag, compact=t[3], residual=t[4], angle=t[5] if len(t) > 5 else None,
                             height=g["height"], mirror=g["mirror"], depth=g["depth"], image_out=g["image_out"],
                             concave=float(w[H[vs] < 0].sum() / w.sum()), saddle=float(w[K[vs] < 0].sum() / w.sum()),
                             near=near, sink_alone=sa[i] / diag, sink_all=s_all[i] / diag, rest_alone=ra,
                             rest_contrib=r_all - rb,
                             but_ratio=rb / (min(x for j, x in enumerate(sb) if j != i) / diag) if n > 1 else None))
            print(name, rows[-1], flush=True)
        res[name] = dict(diag=diag, rest_all=r_all, min_sink_all=min(s_all) / diag, rows=rows)
json.dump(res, open(sys.argv[1], "w"), indent=1)
