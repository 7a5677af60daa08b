#!/usr/bin/python3
"""How far each automatic region's dimple can sink before its mirror image meets the shell
(lab/regions/hand_elk.md, section 8): a candidate finder test, computed at rest.

For each region: the dimple of the default strength (sink_why.py's dimple_image: the first faces
of the dimple order whose rest cap volume reaches 0.7 of the region's, rho = 1) and its mirror
plane. Each interior vertex i at height d_i above the plane moves to its image, 2 d_i along -n
(n the plane's normal). "Room": the same move stopped where the ray from the vertex along -n
first meets a face of the rest shell other than those at the vertex and its one-ring neighbours
(Moller-Trumbore), a_i = min(2 d_i, t_i). The dimple's own faces count: a dimple that wraps round
a thin board meets its own far side (they move too, so this under-states the room there). The region's sink is then the mean over its vertices of
a_i (n . n_i) (n_i the rest vertex normal; 0 for the vertices that do not move), / the diagonal,
against the same with the whole image (a_i = 2 d_i; sink_why.py's "mirror at rest" with the crease
ring placed).

Usage: /usr/bin/python3 lab/regions/room.py [--build DIR] [--meshes bear,hand,elk,kitten,bumpy_sphere]
"""
import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
from sink_why import dimple_image, dimple_order  # noqa: E402


def first_hit(origins, direction, tri, skip):
    """Distance along `direction` from each origin to the first triangle of tri (k, 3, 3) it
    meets, inf if none; skip[j] lists the triangle indices origin j ignores."""
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    p = np.cross(direction, e2)
    det = np.einsum("kj,kj->k", e1, p)
    ok = np.abs(det) > 1e-14
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    out = np.full(len(origins), np.inf)
    for j, o in enumerate(origins):
        s = o - tri[:, 0]
        u = np.einsum("kj,kj->k", s, p) * inv
        q = np.cross(s, e1)
        v = (q @ direction) * inv
        t = np.einsum("kj,kj->k", e2, q) * inv
        hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-12)
        hit[skip[j]] = False
        if hit.any():
            out[j] = t[hit].min()
    return out


def incident_faces(faces):
    """Per vertex, the faces at it."""
    incident = [[] for _ in range(faces.max() + 1)]
    for fi, f in enumerate(faces):
        for v in f:
            incident[v].append(fi)
    return incident


def region_room(rest, faces, region, normals, diag, tri, incident):
    """The region's mean sink along the rest normals, / diag, of its whole mirror image and of the
    image stopped at the rest shell (the module's docstring): (whole, kept)."""
    order, limit, _, _ = dimple_order(rest, faces, region)
    dimple, _, interior, d, pn = dimple_image(rest, faces, region, order, limit, 0.7)
    up = d > 0
    verts, dv = interior[up], d[up]
    skip = [sorted({fi for w in faces[incident[v]].ravel() for fi in incident[w]}) for v in verts]
    t = first_hit(rest[verts], -pn, tri, skip)
    along = normals[verts] @ pn
    nreg = len(np.unique(faces[region].ravel()))
    whole = float((2 * dv * along).sum()) / nreg / diag
    kept = float((np.minimum(2 * dv, t) * along).sum()) / nreg / diag
    return whole, kept


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--meshes", default="bear,hand,elk,kitten,bumpy_sphere")
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    print("| mesh | region | whole image: sink / diag | image stopped at the shell: sink / diag | share kept |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, path, rest, faces, diag in common.each_mesh(a.meshes.split(",")):
            regions, _, _ = common.auto_regions(exe, path, tmp)
            normals = common.rest_normals(rest, faces)
            tri, incident = rest[faces], incident_faces(faces)
            for ri, region in enumerate(regions):
                whole, kept = region_room(rest, faces, region, normals, diag, tri, incident)
                print(f"| {name} | {ri} | {whole:.4f} | {kept:.4f} | {kept / whole if whole > 0 else 0:.2f} |",
                      flush=True)


if __name__ == "__main__":
    main()
