#!/usr/bin/python3
"""How far bear's vertices move per step on the default run, and how much of it a global affine
motion explains (collision_coherence.md, section 9): the question behind a Verlet list of the
broad phase, whose margin must cover k steps of motion.

Reads the frames of `shellcontract run data/meshes/bear.off -o D/out.off -q --export-dir D/fr
--export-every 1` (out_000.off .. out_200.off) and prints, for windows of k = 1, 2, 5, 10, 20
steps starting at several frames, the vertices' displacement (median, max) and what is left of
it after the least-squares affine map of the whole mesh over the window (median, 99th
percentile, max), in units of the rest's mean edge length, with the affine map's smallest
singular value.

Usage: /usr/bin/python3 lab/kernels/motion_per_step.py D/fr
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "regions"))
import common  # noqa: E402


def affine_residual(p, q):
    """The least-squares affine map p -> q: (residual per vertex, its linear part)."""
    ph = np.hstack([p, np.ones((len(p), 1))])
    m, *_ = np.linalg.lstsq(ph, q, rcond=None)
    return np.linalg.norm(q - ph @ m, axis=1), m[:3].T


def read_frames(frames):
    """The 201 frames out_000.off .. out_200.off (positions, steps x vertices x 3) and the mean
    length of the first frame's edges."""
    x = np.array([common.read_off(os.path.join(frames, f"out_{i:03d}.off"))[0] for i in range(201)])
    f = common.read_off(os.path.join(frames, "out_000.off"))[1]
    e = np.unique(np.sort(np.vstack([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), 1), axis=0)
    return x, np.linalg.norm(x[0][e[:, 0]] - x[0][e[:, 1]], axis=1).mean()


def main():
    frames = sys.argv[1]
    x, edge = read_frames(frames)
    print(f"mean edge {edge:.6g} (input units); every figure below is in mean edges")
    for k in (1, 2, 5, 10, 20):
        print(f"k = {k}")
        for s in (1, 5, 10, 20, 40, 60, 100, 150, 200 - k):
            raw = np.linalg.norm(x[s + k] - x[s], axis=1)
            res, a = affine_residual(x[s], x[s + k])
            print(f"  from frame {s}: moved median {np.median(raw) / edge:.2f} max {raw.max() / edge:.2f}; "
                  f"after the affine fit median {np.median(res) / edge:.2f} p99 {np.percentile(res, 99) / edge:.2f} "
                  f"max {res.max() / edge:.2f}; smallest singular value {np.linalg.svd(a, compute_uv=False).min():.4f}")


if __name__ == "__main__":
    main()
