#!/usr/bin/python3
"""Renders an ASCII PLY written by shellcontract (regions: per-face colours; fields: per-vertex
colours) to a PNG with matplotlib (Debian package python3-matplotlib), flat-shaded by the
light direction so the shape reads. For the README pictures; not used by tests.

Usage: scripts/render_ply.py IN.ply OUT.png [--elev 20] [--azim -60] [--title TEXT]
"""
import argparse
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def read_ply(path):
    with open(path) as f:
        lines = f.read().split("\n")
    i, nv, nf, vprops, fprops, elem = 0, 0, 0, [], [], None
    while lines[i] != "end_header":
        w = lines[i].split()
        if w[:2] == ["element", "vertex"]:
            nv, elem = int(w[2]), "v"
        elif w[:2] == ["element", "face"]:
            nf, elem = int(w[2]), "f"
        elif w[0] == "property":
            (vprops if elem == "v" else fprops).append(w[-1])
        i += 1
    i += 1
    V = np.array([[float(t) for t in lines[i + k].split()] for k in range(nv)])
    F, FC = [], []
    for k in range(nf):
        t = lines[i + nv + k].split()
        n = int(t[0])
        F.append([int(v) for v in t[1:1 + n]])
        rest = t[1 + n:]
        if "red" in fprops:
            FC.append([int(rest[0]) / 255, int(rest[1]) / 255, int(rest[2]) / 255])
    if not FC and "red" in vprops:
        r = vprops.index("red")
        VC = V[:, r:r + 3] / 255
        FC = [VC[f].mean(axis=0) for f in F]
    if not FC:
        FC = [[0.7, 0.7, 0.7]] * nf
    return V[:, :3], np.array(F), np.array(FC)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ply")
    ap.add_argument("png")
    ap.add_argument("--elev", type=float, default=20)
    ap.add_argument("--azim", type=float, default=-60)
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    V, F, C = read_ply(a.ply)
    tris = V[F]
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    el, az = np.radians(a.elev), np.radians(a.azim)
    light = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    shade = 0.45 + 0.55 * np.clip(n @ light, 0, 1)
    fig = plt.figure(figsize=(6, 6), dpi=110)
    ax = fig.add_subplot(111, projection="3d")
    ax.add_collection3d(Poly3DCollection(tris, facecolors=np.clip(C * shade[:, None], 0, 1), linewidths=0))
    lo, hi = V.min(axis=0), V.max(axis=0)
    c, r = (lo + hi) / 2, (hi - lo).max() / 2
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.view_init(a.elev, a.azim)
    ax.set_axis_off()
    if a.title:
        ax.set_title(a.title)
    fig.savefig(a.png, bbox_inches="tight")
    return 0


if __name__ == "__main__":
    sys.exit(main())
