"""Shared helpers of the lab/regions scripts: reading meshes and face lists, running the tool.

Every script here runs the built tool (build/shellcontract by default) on the paper's meshes in
data/meshes (scripts/fetch_paper_meshes.sh; the kitten: scripts/make_kitten.sh) and on
meshes/bumpy_sphere.off; a mesh that is absent is skipped and said so.
"""
import os
import subprocess

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PAPER = ["eight", "hand", "elk", "bear", "kitten"]


def mesh_path(name):
    if name == "bumpy_sphere":
        return os.path.join(ROOT, "meshes", "bumpy_sphere.off")
    return os.path.join(ROOT, "data", "meshes", name + ".off")


def read_off(path):
    tokens = " ".join(line.split("#")[0] for line in open(path)).split()
    i = 1 if tokens[0] == "OFF" else 0
    nv, nf = int(tokens[i]), int(tokens[i + 1])
    i += 3
    v = np.array(tokens[i:i + 3 * nv], float).reshape(nv, 3)
    i += 3 * nv
    faces = []
    for _ in range(nf):
        n = int(tokens[i])
        faces.append([int(x) for x in tokens[i + 1:i + 1 + n]])
        i += 1 + n
    return v, np.array(faces)


def each_mesh(names):
    """(name, path, rest vertices, faces, bounding-box diagonal) of each named mesh that exists;
    an absent one is said on stderr and skipped (the kitten is made by scripts/make_kitten.sh)."""
    import sys
    for name in names:
        path = mesh_path(name)
        if not os.path.exists(path):
            print(f"{name}: absent, skipped", file=sys.stderr)
            continue
        rest, faces = read_off(path)
        yield name, path, rest, faces, float(np.linalg.norm(rest.max(0) - rest.min(0)))


def read_face_list(path):
    """Regions of a face-list file: one list of face ids per non-comment line (a leading strength
    token "S:", as the tool reads it, is skipped)."""
    out = []
    for line in open(path):
        line = line.split("#")[0].split()
        if line and line[0].endswith(":"):
            line = line[1:]
        if line:
            out.append([int(t) for t in line])
    return out


def auto_regions(exe, mesh, tmp, extra=()):
    """The regions `shellcontract regions MESH` finds (its face list) and its printed table."""
    listed = os.path.join(tmp, "regions.txt")
    ply = os.path.join(tmp, "regions.ply")
    if os.path.exists(listed):
        os.remove(listed)
    out = subprocess.run([exe, "regions", mesh, "-o", ply, "--face-list", listed] + list(extra),
                         check=True, capture_output=True, text=True).stdout
    return (read_face_list(listed) if os.path.exists(listed) else []), out, ply


def face_masks(regions, nf):
    """One boolean mask over the nf faces per region (a list of face indices)."""
    out = []
    for reg in regions:
        m = np.zeros(nf, bool)
        m[reg] = True
        out.append(m)
    return out


def best_iou(mask, regs, area):
    """The largest IoU by area of a face mask with any of the masks regs (0 if none)."""
    return max([area[mask & r].sum() / max(area[mask | r].sum(), 1e-300) for r in regs], default=0.0)


def face_centroids(v, f):
    return v[f].mean(axis=1)


def face_areas(v, f):
    return 0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1)


def rest_normals(v, f):
    n = np.zeros_like(v)
    cr = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    for k in range(3):
        np.add.at(n, f[:, k], cr)
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]


def print_rule_table(res, cols, names, counts):
    """The prototypes' comparison table (heads_prototype.py, necks.py): a row per labelled part
    (names, in res[c]["parts"] order: (mesh, part, IoU)) and the summary rows, a column per rule
    in cols; counts(c) is the last row's cell (the regions per mesh)."""
    print("| part | " + " | ".join(cols) + " |")
    print("|---|" + "---:|" * len(cols))
    for k, name in enumerate(names):
        print(f"| {name} | " + " | ".join(f"{res[c]['parts'][k][2]:.2f}" for c in cols) + " |")
    for label, fn in [("mean IoU", lambda c: f"{np.mean([p[2] for p in res[c]['parts']]):.3f}"),
                      ("parts >= 0.5", lambda c: str(sum(p[2] >= 0.5 for p in res[c]['parts']))),
                      ("bumpy_sphere bumps", lambda c: "/".join(f"{b:.2f}" for b in res[c]["bumps"])),
                      ("bear vs bear x4 (min)", lambda c: f"{res[c]['sub']:.2f}"),
                      ("largest compactness", lambda c: f"{max(res[c]['comp']):.2f}"),
                      ("regions (eight hand elk bear kitten bumpy)", counts)]:
        print(f"| **{label}** | " + " | ".join(fn(c) for c in cols) + " |")
