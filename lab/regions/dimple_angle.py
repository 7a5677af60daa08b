#!/usr/bin/python3
"""Issue 55 point 2 (lab/regions/dimple_angle.md): the automatic regions' dimples limited to
THETA degrees from each region's axis, emulated with per-region strengths in a face list
('S: ids', S the share of --region-shrink 0.7): S = min(1, F / 0.7), F the cap-volume share of
the dimple order's prefix (sink_why.dimple_order, the order region_dimple.cpp uses) whose faces
lie within THETA of the axis (the fitted sphere's centre, from the regions table, to the first
face of the order). Writes OUTDIR/MESH.txt for bear, hand, elk, kitten, bumpy_sphere, then:
  lab/regions/sink.py --face-list bear=OUTDIR/bear.txt ... (all five)

Usage: /usr/bin/python3 lab/regions/dimple_angle.py THETA OUTDIR
"""
import sys, os, subprocess, numpy as np
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from sink_why import dimple_order, cap_volume  # noqa: E402
exe = os.path.join(common.ROOT, "build", "shellcontract")
theta_d = float(sys.argv[1]); shrink = 0.7; outdir = sys.argv[2]
os.makedirs(outdir, exist_ok=True)
for name in ["bear", "hand", "elk", "kitten", "bumpy_sphere"]:
    mesh = common.mesh_path(name)
    rest, faces = common.read_off(mesh)
    regs, table, _ = common.auto_regions(exe, mesh, outdir)
    centres = {}
    on = False
    for line in table.splitlines():
        t = line.split()
        if line.strip().startswith("id "): on = True; continue
        if on and len(t) >= 10 and t[0].isdigit():
            centres[int(t[0])] = np.array([float(x.strip(",")) for x in t[1:4]])
    lines = []
    for k, reg in enumerate(regs):
        order = dimple_order(rest, faces, reg)[0]
        cent = rest[faces[order]].mean(1)
        c = centres[k]
        axis = cent[0] - c; axis /= np.linalg.norm(axis)
        v = cent - c; ang = np.degrees(np.arccos(np.clip((v @ axis) / np.linalg.norm(v, axis=1), -1, 1)))
        # prefix of the order within theta_d (first face beyond ends it)
        beyond = np.flatnonzero(ang > theta_d)
        kk = int(beyond[0]) if len(beyond) else len(order)
        whole = cap_volume(rest, faces, list(reg))
        F = cap_volume(rest, faces, order[:kk]) / whole if kk > 0 else 0.0
        s = min(1.0, max(F / shrink, 0.0))
        lines.append(f"{s:.4f}: " + " ".join(map(str, reg)))
        print(f"{name} region {k}: widest {ang.max():.0f} deg, prefix {kk}/{len(order)} faces, F {F:.3f}, strength {s:.3f}")
    open(os.path.join(outdir, name + ".txt"), "w").write("\n".join(lines) + "\n")
