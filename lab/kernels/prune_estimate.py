#!/usr/bin/python3
"""How many of the AVX2 cell loop's 8-lane blocks a row could skip if each cell listed its faces
and edges sorted along one axis (collision_coherence.md, section 11): an estimate from bear's
default run, before building it.

Emulates the grid of grid_pairs on the swept boxes of a step (cells of 3 x the median largest
side of the face and edge boxes, boxes inflated by 2.5e-4 of the diagonal, the default), the
cell lists' runs (vertices, faces, edges) and the rows (every vertex against the cell's faces,
every edge against the edges after it), and counts the blocks of 8 the rows test:
- in the input's id order (what the product does);
- with faces and edges ranked by their box's lower bound on AXIS at frame 0, each row ending
  at the first block from which every later item starts above the row's box on AXIS, and (vertex
  rows) skipping blocks whose items all end below it.

Reads the frames of `shellcontract run data/meshes/bear.off -o D/out.off -q --export-dir D/fr
--export-every 1`. Slow (pure Python, a few minutes per step).

Usage: /usr/bin/python3 lab/kernels/prune_estimate.py D/fr AXIS [STEP ...]
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "regions"))
import common  # noqa: E402


def blocks(n):
    return (n + 7) // 8


def main():
    frames, axis = sys.argv[1], int(sys.argv[2])
    steps = [int(a) for a in sys.argv[3:]] or [5, 40, 100, 190]
    x_rest, f = common.read_off(os.path.join(frames, "out_000.off"))
    nv, nf = len(x_rest), len(f)
    e = np.unique(np.sort(np.vstack([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), 1), axis=0)
    diag = np.linalg.norm(x_rest.max(0) - x_rest.min(0))

    def boxes(x0, x1):
        vlo = np.minimum(x0, x1) - 2.5e-4 * diag
        vhi = np.maximum(x0, x1) + 2.5e-4 * diag
        lo = np.vstack([vlo, vlo[f].min(1), vlo[e].min(1)])
        hi = np.vstack([vhi, vhi[f].max(1), vhi[e].max(1)])
        return lo, hi

    kind = np.concatenate([np.zeros(nv, int), np.ones(nf, int), np.full(len(e), 2)])
    lo0, _ = boxes(x_rest, x_rest)
    rank = np.empty(len(kind), int)
    for k in range(3):
        ids = np.where(kind == k)[0]
        rank[ids[np.argsort(lo0[ids, axis], kind="stable")]] = np.arange(len(ids))
    for s in steps:
        x0 = common.read_off(os.path.join(frames, f"out_{s:03d}.off"))[0]
        x1 = common.read_off(os.path.join(frames, f"out_{s + 1:03d}.off"))[0]
        lo, hi = boxes(x0, x1)
        h = 3 * np.median(np.max(hi[nv:] - lo[nv:], axis=1))
        origin = lo.min(0) - 0.5 * h
        first = np.floor((lo - origin) / h).astype(int)
        last = np.floor((hi - origin) / h).astype(int)
        cells = {}
        for p in range(len(kind)):
            for cx in range(first[p, 0], last[p, 0] + 1):
                for cy in range(first[p, 1], last[p, 1] + 1):
                    for cz in range(first[p, 2], last[p, 2] + 1):
                        cells.setdefault((cx, cy, cz), []).append(p)
        plain = pruned = 0
        for items in cells.values():
            items = np.array(items)
            vs, fs, es = (items[kind[items] == k] for k in range(3))
            plain += len(vs) * blocks(len(fs)) + sum(blocks(len(es) - i - 1) for i in range(len(es)))
            fs, es = fs[np.argsort(rank[fs])], es[np.argsort(rank[es])]
            if len(fs):
                tail = np.minimum.accumulate(lo[fs, axis][::-1])[::-1]
                lead = np.maximum.accumulate(hi[fs, axis])
                for v in vs:
                    for j in range(0, len(fs), 8):
                        if tail[j] > hi[v, axis]:
                            break
                        if lead[min(j + 7, len(fs) - 1)] >= lo[v, axis]:
                            pruned += 1
            if len(es) > 1:
                tail = np.minimum.accumulate(lo[es, axis][::-1])[::-1]
                for i in range(len(es) - 1):
                    for j in range(i + 1, len(es), 8):
                        if tail[j] > hi[es[i], axis]:
                            break
                        pruned += 1
        print(f"step {s}: axis {axis}, {len(cells)} cells; blocks in id order {plain}, "
              f"sorted and pruned {pruned} ({pruned / plain:.2f})", flush=True)


if __name__ == "__main__":
    main()
