#!/usr/bin/python3
"""Would normal-cone culling (Volino and Thalmann; Tang et al.'s continuous normal cones) let the
broad phase skip the topologically near pairs on bear's default run? An upper bound on what it
could save (collision_coherence.md, section 10).

The mesh is cut once into patches of about K faces (breadth-first growth from the lowest free
face id). For each step from frame s to s + 1, a patch is "self-culled" when one axis a (the
normalized sum of its faces' normals at both ends of the step) has a . n > 0.1 |n| for the three
Bernstein control vectors of every face's normal over the step (n(t) = A (1 - t)^2 + 2 B t (1 - t)
+ C t^2, so a . n(t) > 0 on the whole step); a pair of adjacent patches (sharing a vertex) is
"union-culled" when the same holds for the two together. The boundary (contour) test that makes
the cull sound is NOT applied: every figure is an upper bound on what culling could remove.

What is left to test is then: every pair of patches whose swept, inflated boxes overlap and which
is neither union-culled (adjacent) nor self-culled (the same patch). The script prints, per step,
the culled shares, the patch pairs left, and the primitive pairs inside them ("prim pair work":
products of their vertex + face + edge counts, before any box test), to set beside the grid's
5.7-8.2 M cell pairs per step (collision_coherence.md, section 4).

Reads the frames of `shellcontract run data/meshes/bear.off -o D/out.off -q --export-dir D/fr
--export-every 1` (out_000.off .. out_200.off).

Usage: /usr/bin/python3 lab/kernels/normal_cones.py D/fr K [STEP ...]
"""
import collections
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "regions"))
import common  # noqa: E402

CONE_MARGIN = 0.1  # a . n / |n| above this for every control vector (about 84 degrees)
INFLATION = 2.5e-4  # of the diagonal: the broad phase's (delta + m) / 2 at the default delta


def patches(faces, k):
    """Face -> patch id, patches grown breadth-first to k faces from the lowest free face."""
    first = {}
    adj = [[] for _ in range(len(faces))]
    for fi, t in enumerate(faces):
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            key = (min(a, b), max(a, b))
            if key in first:
                adj[fi].append(first[key])
                adj[first[key]].append(fi)
            else:
                first[key] = fi
    patch = -np.ones(len(faces), int)
    count = 0
    for seed in range(len(faces)):
        if patch[seed] >= 0:
            continue
        queue, size = collections.deque([seed]), 1
        patch[seed] = count
        while queue and size < k:
            for g in adj[queue.popleft()]:
                if patch[g] < 0 and size < k:
                    patch[g] = count
                    size += 1
                    queue.append(g)
        count += 1
    edges = np.array(sorted(first))
    return patch, count, edges, np.array([patch[first[tuple(e)]] for e in edges])


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def main():
    frames, k = sys.argv[1], int(sys.argv[2])
    steps = [int(a) for a in sys.argv[3:]] or [0, 10, 30, 100, 190]
    x = {i: common.read_off(os.path.join(frames, f"out_{i:03d}.off"))[0] for s in steps for i in (s, s + 1)}
    f = common.read_off(os.path.join(frames, "out_000.off"))[1]
    nv = len(x[steps[0]])
    patch, n, edges, edge_patch = patches(f, k)
    vertex_patch = -np.ones(nv, int)  # a vertex's owner: its first face's patch
    for fi, t in enumerate(f):
        for v in t:
            if vertex_patch[v] < 0:
                vertex_patch[v] = patch[fi]
    prims = np.bincount(vertex_patch, minlength=n) + np.bincount(patch, minlength=n) + np.bincount(edge_patch, minlength=n)
    adjacent = set()  # patches sharing a vertex
    by_vertex = collections.defaultdict(set)
    for fi, t in enumerate(f):
        for v in t:
            by_vertex[v].add(patch[fi])
    for ps in by_vertex.values():
        ps = sorted(ps)
        adjacent.update((ps[i], ps[j]) for i in range(len(ps)) for j in range(i + 1, len(ps)))
    members = [np.where(patch == p)[0] for p in range(n)]
    sizes = np.bincount(patch)
    print(f"{n} patches of median {np.median(sizes):.0f} faces; {len(adjacent)} adjacent pairs")
    for s in steps:
        x0, x1 = x[s], x[s + 1]
        e0 = [x0[f[:, 1]] - x0[f[:, 0]], x0[f[:, 2]] - x0[f[:, 0]]]
        e1 = [x1[f[:, 1]] - x1[f[:, 0]], x1[f[:, 2]] - x1[f[:, 0]]]
        a = np.cross(*e0)
        c = np.cross(*e1)
        b = 0.5 * (np.cross(e0[0], e1[1]) + np.cross(e1[0], e0[1]))
        control = [unit(a), unit(b), unit(c)]
        axis = np.zeros((n, 3))
        np.add.at(axis, patch, a + c)

        def culled(faces, ax):
            ax = unit(ax)
            return min((v[faces] @ ax).min() for v in control) > CONE_MARGIN

        self_culled = np.array([culled(members[p], axis[p]) for p in range(n)])
        union_culled = {pq for pq in adjacent
                        if culled(np.concatenate([members[pq[0]], members[pq[1]]]), axis[pq[0]] + axis[pq[1]])}
        diag = np.linalg.norm(x0.max(0) - x0.min(0))
        vlo = np.minimum(x0, x1) - INFLATION * diag
        vhi = np.maximum(x0, x1) + INFLATION * diag
        lo = np.full((n, 3), np.inf)
        hi = np.full((n, 3), -np.inf)
        for corner in range(3):
            np.minimum.at(lo, patch, vlo[f[:, corner]])
            np.maximum.at(hi, patch, vhi[f[:, corner]])
        overlap = np.all((lo[:, None] <= hi[None]) & (lo[None] <= hi[:, None]), axis=2)
        left_adjacent = left_apart = 0
        work = sum(int(prims[p]) * (int(prims[p]) - 1) // 2 for p in range(n) if not self_culled[p])
        for p, q in zip(*np.triu_indices(n, 1)):
            if not overlap[p, q]:
                continue
            if (p, q) in adjacent:
                if (p, q) in union_culled:
                    continue
                left_adjacent += 1
            else:
                left_apart += 1
            work += int(prims[p]) * int(prims[q])
        print(f"step {s}: self-culled {self_culled.mean():.3f}, adjacent unions culled "
              f"{len(union_culled) / len(adjacent):.3f}; patch pairs left: {left_adjacent} adjacent, "
              f"{left_apart} apart; prim pair work {work / 1e6:.2f} M", flush=True)


if __name__ == "__main__":
    main()
