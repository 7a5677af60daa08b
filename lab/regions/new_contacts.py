#!/usr/bin/python3
"""Where a run's new near-contacts are (lab/regions/dimple_angle.md): vertex pairs of the end
state closer than half the mean rest edge that were farther apart at rest and are not within
two rings of each other, counted by the regions (face list) their vertices belong to (-1: the
rest of the shell). scipy's cKDTree.

Usage: /usr/bin/python3 lab/regions/new_contacts.py MESH END.off FACE_LIST
"""
import os
import sys

import numpy as np
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from scipy.spatial import cKDTree  # noqa: E402
name, endp, flist = sys.argv[1], sys.argv[2], sys.argv[3]
r, f = common.read_off(common.mesh_path(name)); e = common.read_off(endp)[0]
regs = common.read_face_list(flist)
lab = -np.ones(len(r), int)
for k, reg in enumerate(regs): lab[f[reg].ravel()] = k
nb = [set() for _ in r]
for t in f:
    for a in t:
        nb[a].update(t)
ring2 = [set().union(*[nb[b] for b in nb[a]]) for a in range(len(r))]
el = np.linalg.norm(r[f[:, 0]] - r[f[:, 1]], axis=1).mean()
tree = cKDTree(e)
pairs = tree.query_pairs(0.5 * el)
rt = cKDTree(r)
out = {}
for a, b in pairs:
    if b in ring2[a]: continue
    if np.linalg.norm(r[a] - r[b]) < 0.5 * el: continue  # already close at rest
    key = tuple(sorted((int(lab[a]), int(lab[b]))))
    out[key] = out.get(key, 0) + 1
print("mean edge", el, "new close pairs by (region, region) (-1 = rest):", out)
