#!/usr/bin/python3
"""How the rest moves over a long run with the automatic regions (lab/regions/rest_over_time.md).

Reads the frames of `run MESH --regions auto -p 0 -n N --export-every K --export-dir D` and, for
each frame, prints the mean displacement from the input of the vertices outside the regions and
their one-ring band ("the rest", as sink.py takes it) over the bounding-box diagonal; the same
after the best similarity (Umeyama) and after the best affine map of the rest, fitted by least
squares (does a global motion explain it?); and the rest's mean motion since the previous frame.
With --by-distance it also splits the last frame's rest (or that of --frame NNNN) by Euclidean
distance to the nearest region vertex at rest; --sinks adds each frame's smallest region sink
(sink.py's measure) and rest / smallest sink.

Usage: /usr/bin/python3 lab/regions/rest_over_time.py BUILD_DIR/shellcontract MESH D [--sinks]
       [--by-distance [--frame NNNN]]
"""
import glob
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import sink  # noqa: E402


def similarity_fit(P, Q):
    cp, cq = P.mean(0), Q.mean(0)
    u, s, vt = np.linalg.svd((P - cp).T @ (Q - cq))
    v = vt.T
    d = np.diag([1.0, 1.0, np.sign(np.linalg.det(v @ u.T))])
    r = v @ d @ u.T
    scale = np.trace(np.diag(s) @ d) / ((P - cp) ** 2).sum()
    return scale * (P - cp) @ r.T + cq, scale


def affine_fit(P, Q):
    X = np.hstack([P, np.ones((len(P), 1))])
    a, *_ = np.linalg.lstsq(X, Q, rcond=None)
    return X @ a


def main():
    exe, name, frames = sys.argv[1], sys.argv[2], sys.argv[3]
    path = common.mesh_path(name)
    rest, faces = common.read_off(path)
    with tempfile.TemporaryDirectory() as tmp:
        regions, _, _ = common.auto_regions(exe, path, tmp)
    in_region = np.zeros(len(rest), bool)
    for r in regions:
        in_region[faces[r].ravel()] = True
    band = in_region.copy()
    band[faces[in_region[faces].any(axis=1)].ravel()] = True
    keep = ~band
    diag = np.linalg.norm(rest.max(0) - rest.min(0))
    mean = lambda d: float(np.linalg.norm(d, axis=1).mean() / diag)  # noqa: E731
    print(f"{name}: {len(regions)} regions, {keep.sum()} rest vertices")
    sinks = "--sinks" in sys.argv
    pick = sys.argv[sys.argv.index("--frame") + 1] if "--frame" in sys.argv else None
    extra = " smallest sink / diag | rest / smallest sink |" if sinks else ""
    print("| frame | rest / diag | after similarity (scale) | after affine | since previous frame |" + extra)
    print("|---|---|---|---|---|" + ("---|---|" if sinks else ""))
    prev, last = None, None
    # Only the exported frames (NAME_NNNN.off), not an output that may share the folder.
    for fn in sorted(f for f in glob.glob(os.path.join(frames, "*_*.off"))
                     if os.path.splitext(f)[0].rsplit("_", 1)[-1].isdigit()):
        x = common.read_off(fn)[0]
        P, Q = rest[keep], x[keep]
        qs, s = similarity_fit(P, Q)
        step = "" if prev is None else f"{mean(Q - prev):.5f}"
        frame = os.path.splitext(os.path.basename(fn))[0].rsplit("_", 1)[-1]
        row = f"| {frame} | {mean(Q - P):.5f} | {mean(Q - qs):.5f} ({s:.5f}) | {mean(Q - affine_fit(P, Q)):.5f} | {step} |"
        if sinks:
            smallest = min(sink.per_region_sink(rest, faces, x, regions)) / diag
            row += f" {smallest:.4f} | {mean(Q - P) / smallest:.3f} |" if smallest > 0 else f" {smallest:.4f} | - |"
        print(row)
        prev = Q
        if pick is None or frame == pick:
            last = x
    if "--by-distance" in sys.argv and last is not None:
        from scipy.spatial import cKDTree
        dist = cKDTree(rest[in_region]).query(rest)[0] / diag
        d = np.linalg.norm(last - rest, axis=1) / diag
        total = d[keep].sum()
        print("\n| distance to the nearest region vertex / diag | rest vertices | mean displacement / diag | share of the rest's sum |")
        print("|---|---|---|---|")
        edges = [0, 0.02, 0.05, 0.1, 0.2, 0.4, np.inf]
        for a, b in zip(edges[:-1], edges[1:]):
            m = keep & (dist >= a) & (dist < b)
            if m.any():
                print(f"| [{a}, {b}) | {m.sum()} | {d[m].mean():.5f} | {d[m].sum() / total:.2f} |")


if __name__ == "__main__":
    main()
