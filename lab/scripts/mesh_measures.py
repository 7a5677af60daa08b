"""Numbers measured on meshes and run logs for lab/scripts/paper_figures.py (numpy only).

Each measure is defined in its docstring so that the figures' README can quote it.
"""
import csv

import numpy as np


def face_normals(V, F):
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    area = np.linalg.norm(n, axis=1) / 2
    return n / np.maximum(2 * area, 1e-300)[:, None], area


def edge_faces(F):
    """(e×2 face ids) of the edges shared by exactly two faces."""
    half = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    face = np.tile(np.arange(len(F)), 3)
    key = np.sort(half, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, face = key[order], face[order]
    same = (key[1:] == key[:-1]).all(axis=1)
    return np.column_stack([face[:-1][same], face[1:][same]])


def roughness_deg(V, F):
    """Mean angle in degrees between the normals of the two faces of each edge: 0 on a plane,
    small on a smooth, finely meshed surface, larger where the surface creases or wrinkles. It
    depends on the mesh resolution, so compare it only between runs of one mesh."""
    n, _ = face_normals(V, F)
    ef = edge_faces(F)
    cos = np.clip((n[ef[:, 0]] * n[ef[:, 1]]).sum(axis=1), -1, 1)
    return float(np.degrees(np.arccos(cos)).mean())


def volume(V, F):
    return float(np.einsum("ij,ij->i", V[F[:, 0]], np.cross(V[F[:, 1]], V[F[:, 2]])).sum() / 6)


def read_log(path):
    """Columns of a `shellcontract run --log` CSV as float arrays, by header name."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]} if rows else {}


# V/V0 changes smaller than this are not counted as going up or down: a shell at rest still
# moves V/V0 by ~1e-9 per frame (rounding, contact pushes), which is no jitter one could see.
JITTER_TOLERANCE = 1e-5


def _steps(volume_ratio, tol):
    d = np.diff(np.asarray(volume_ratio, float))
    return np.where(np.abs(d) > tol, np.sign(d), 0)


def jitter_frames(volume_ratio, tol=JITTER_TOLERANCE):
    """Frames where V/V0 increases by more than `tol` over the frame before (the paper's
    'jitter' of Fig. 18 is the volume curve going up and down while the shell contracts)."""
    return int((_steps(volume_ratio, tol) > 0).sum())


def reversals(volume_ratio, tol=JITTER_TOLERANCE):
    """How often the V/V0 curve turns (from going down to going up or back), ignoring steps of
    at most `tol`: a slow oscillation counts each of its turns, a frame-to-frame wobble every
    frame."""
    step = _steps(volume_ratio, tol)
    step = step[step != 0]
    return int((step[1:] != step[:-1]).sum())


def read_face_list(path):
    """Regions of `shellcontract regions --face-list`: one line per region of 0-based face ids."""
    with open(path) as f:
        return [[int(w) for w in line.split()] for line in f if line.strip()]


def fibre_strains(V0, V1, F, region):
    """Mean engineering strains of a region's faces along its fibre and across it, from the
    input (V0) and output (V1) positions of one run (same vertex order).

    The fibre of a face is the one `shellcontract run --fiber centre` uses: the direction from
    the face's centroid toward the area-weighted rest centroid of its region, projected on the
    face's plane (src/sim/anisotropy.cpp). 'Across' is the tangent direction perpendicular to
    it. A direction d on a rest face with edge matrix E0 = [b-a, c-a] has the coordinates
    alpha = E0^+ d, and after the run its length is |E1 alpha|; strain = length - 1 for unit d.
    Returns (along, across) area-weighted over the region's faces."""
    region = np.asarray(region)
    Fr = F[region]
    n0, area = face_normals(V0, Fr)
    centroid = V0[Fr].mean(axis=1)
    centre = (area[:, None] * centroid).sum(axis=0) / area.sum()
    d = centre - centroid
    d -= (d * n0).sum(axis=1, keepdims=True) * n0
    d /= np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-300)
    across = np.cross(n0, d)
    E0 = np.stack([V0[Fr[:, 1]] - V0[Fr[:, 0]], V0[Fr[:, 2]] - V0[Fr[:, 0]]], axis=2)  # k×3×2
    E1 = np.stack([V1[Fr[:, 1]] - V1[Fr[:, 0]], V1[Fr[:, 2]] - V1[Fr[:, 0]]], axis=2)
    pinv = np.linalg.pinv(E0)  # k×2×3

    def strain(u):
        alpha = np.einsum("kij,kj->ki", pinv, u)
        return np.linalg.norm(np.einsum("kij,kj->ki", E1, alpha), axis=1) - 1

    w = area / area.sum()
    return float(w @ strain(d)), float(w @ strain(across))


def region_sink(V0, V1, F, regions):
    """Mean inward displacement of the regions' vertices along their rest normals, as a fraction
    of the input's bounding-box diagonal: the summary's `region_inward_displacement`
    (src/sim/simulator.cpp: area-weighted vertex normals of the rest mesh), computed from the
    input and output meshes, so that a run made without any region option can be measured too."""
    n = np.cross(V0[F[:, 0]] - V0[F[:, 2]], V0[F[:, 1]] - V0[F[:, 2]])
    vn = np.zeros_like(V0)
    for k in range(3):
        np.add.at(vn, F[:, k], n)
    verts = np.unique(np.concatenate([F[np.asarray(r)].ravel() for r in regions]))
    normal = vn[verts] / np.maximum(np.linalg.norm(vn[verts], axis=1, keepdims=True), 1e-300)
    diag = np.linalg.norm(V0.max(axis=0) - V0.min(axis=0))
    return float(-((V1[verts] - V0[verts]) * normal).sum(axis=1).mean() / diag)
