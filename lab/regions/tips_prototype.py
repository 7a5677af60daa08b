#!/usr/bin/python3
"""A prototype of tip-centred regions (issue 55 point 1), measured against the labelled set.

Not the product's finder: a study of whether "the end of a protrusion, as a geodesic disc around
its tip" can match the parts of labels.py, and which rule could pick each disc's radius.

1. Protrusion p(v): the average geodesic (edge-graph Dijkstra) distance from v to K = 24 sources
   placed by farthest-point sampling, the first being the vertex farthest from the area centroid
   (so the sources do not depend on the vertex order).
2. Tips: one-ring maxima of p that stay maxima within a geodesic radius of 0.06 * size
   (size = sqrt(total area)).
3. Per labelled part: the tip nearest its point P, and the geodesic disc radius rho (0.02 to 0.44
   size, in steps of 0.01) whose faces (mean corner distance <= rho) give the best IoU with the
   part: an upper bound of any radius rule on these tips. Then three candidate rules for rho:
   - fit: the largest disc whose area-weighted Kasa sphere fit has residual <= 0.12 and lies
     within a hemisphere about the axis from its centre to the tip (grown in steps of 0.01 size);
   - neck: the geodesic distance from the tip to the nearest concave vertex (mean curvature
     smoothed by one implicit heat step at 0.01 size, as the finder's first scale);
   - persistence: the tip's 0-dimensional persistence of p (p at the tip minus p where its
     superlevel component merges with a higher one).

Usage: /usr/bin/python3 lab/regions/tips_prototype.py   (prints a markdown table)
"""
import os
import sys

import numpy as np
from scipy.sparse import coo_matrix, diags
from scipy.sparse.csgraph import dijkstra
from scipy.sparse.linalg import spsolve

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import labels  # noqa: E402


def edge_graph(v, f):
    e = np.unique(np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1), axis=0)
    w = np.linalg.norm(v[e[:, 0]] - v[e[:, 1]], axis=1)
    n = len(v)
    return coo_matrix((np.r_[w, w], (np.r_[e[:, 0], e[:, 1]], np.r_[e[:, 1], e[:, 0]])), shape=(n, n)).tocsr()


def vertex_areas(v, f, fa):
    va = np.zeros(len(v))
    np.add.at(va, f.ravel(), np.repeat(fa / 3, 3))
    return va


def protrusion(G, v, va, K=24):
    c = (v * va[:, None]).sum(0) / va.sum()
    src = int(np.argmax(np.linalg.norm(v - c, axis=1)))
    dmin = dijkstra(G, indices=src)
    acc = dmin.copy()
    for _ in range(K - 1):
        d = dijkstra(G, indices=int(np.argmax(dmin)))
        acc += d
        dmin = np.minimum(dmin, d)
    return acc / K


def tips_of(G, p, radius):
    cand = [i for i in range(len(p)) if all(p[i] > p[j] for j in G.indices[G.indptr[i]:G.indptr[i + 1]])]
    out = []
    for i in cand:
        d = dijkstra(G, indices=i, limit=radius)
        if np.all(p[np.isfinite(d)] <= p[i]):
            out.append(i)
    return out


def kasa(p, w):
    A = np.c_[2 * p, np.ones(len(p))]
    W = w / w.sum()
    M = A.T @ (A * W[:, None])
    try:
        sol = np.linalg.solve(M, A.T @ ((p * p).sum(1) * W))
    except np.linalg.LinAlgError:
        return None
    c = sol[:3]
    r2 = sol[3] + c @ c
    if not r2 > 0:
        return None
    r = np.sqrt(r2)
    return c, r, np.sqrt((W * (np.linalg.norm(p - c, axis=1) - r) ** 2).sum()) / r


def fit_rule(v, va, d, tip, size, tol=0.12):
    best = None
    for k in range(1, 50):
        rho = 0.01 * k * size
        inside = np.isfinite(d) & (d <= rho)
        if inside.sum() < 10:
            continue
        fit = kasa(v[inside], va[inside])
        if fit is None or fit[2] > tol:
            break
        a = v[tip] - fit[0]
        a /= np.linalg.norm(a)
        u = v[inside] - fit[0]
        if ((u @ a) / np.linalg.norm(u, axis=1)).min() < 0.0:
            break
        best = rho
    return best


def smoothed_mean_curvature(v, f, fa, va, scale):
    n = len(v)
    rows, cols, vals = [], [], []
    for k in range(3):
        i, j, o = f[:, k], f[:, (k + 1) % 3], f[:, (k + 2) % 3]
        a, b = v[i] - v[o], v[j] - v[o]
        w = 0.5 * (a * b).sum(1) / np.maximum(np.linalg.norm(np.cross(a, b), axis=1), 1e-300)
        rows += [i, j, i, j]
        cols += [j, i, i, j]
        vals += [-w, -w, w, w]
    L = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)).tocsr()
    fn = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    vn = np.zeros((n, 3))
    for k in range(3):
        np.add.at(vn, f[:, k], fn)
    vn /= np.linalg.norm(vn, axis=1)[:, None]
    H = ((L @ v) * vn).sum(1) / (2 * va)
    t = (scale * np.sqrt(fa.sum())) ** 2
    return spsolve((diags(va) + t * L).tocsc(), va * H)


def persistence(G, p):
    parent = -np.ones(len(p), int)
    out = {}

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a
    for x in np.argsort(-p, kind="stable"):
        parent[x] = x
        roots = sorted({find(w) for w in G.indices[G.indptr[x]:G.indptr[x + 1]] if parent[w] >= 0}, key=lambda r: -p[r])
        if roots:
            parent[x] = roots[0]
            for r in roots[1:]:
                out[r] = p[r] - p[x]
                parent[r] = roots[0]
    return out


def main():
    print("| mesh | part | tip to P / size | ideal rho / size | IoU at ideal | fit rule rho | IoU | neck rho | IoU | persistence / size |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    totals = {"ideal": [], "fit": [], "neck": []}
    for name in common.PAPER:
        path = common.mesh_path(name)
        if not os.path.exists(path):
            print(f"| {name} | (mesh absent) |||||||||")
            continue
        v, f = common.read_off(path)
        fa = common.face_areas(v, f)
        va = vertex_areas(v, f, fa)
        size = np.sqrt(fa.sum())
        G = edge_graph(v, f)
        p = protrusion(G, v, va)
        tips = tips_of(G, p, 0.06 * size)
        u = smoothed_mean_curvature(v, f, fa, va, 0.01)
        pers = persistence(G, p)
        cent = common.face_centroids(v, f)
        for part, P, r in labels.parts_of(name, v):
            mask = np.linalg.norm(cent - P, axis=1) <= r
            t = min(tips, key=lambda t: np.linalg.norm(v[t] - P))
            d = dijkstra(G, indices=t)
            fd = d[f].mean(1)

            def iou(rho):
                if rho is None or not np.isfinite(rho):
                    return 0.0
                m = fd <= rho
                return fa[m & mask].sum() / fa[m | mask].sum()
            ideal = max((iou(q * size), q) for q in np.arange(0.02, 0.45, 0.01))
            fit = fit_rule(v, va, d, t, size)
            neck = d[u < 0].min() if (u < 0).any() else np.inf
            ri = [ideal[0], iou(fit), iou(neck)]
            for k, x in zip(("ideal", "fit", "neck"), ri):
                totals[k].append(x)
            fmt = lambda x: "-" if x is None or not np.isfinite(x) else f"{x / size:.2f}"
            print(f"| {name} | {part} | {np.linalg.norm(v[t] - P) / size:.3f} | {ideal[1]:.2f} | {ri[0]:.2f} | {fmt(fit)} | "
                  f"{ri[1]:.2f} | {fmt(neck)} | {ri[2]:.2f} | {fmt(pers.get(t, np.inf))} |")
    print()
    for k, x in totals.items():
        print(f"- {k}: mean IoU {np.mean(x):.2f}, parts with IoU >= 0.5: {sum(i >= 0.5 for i in x)} of {len(x)}")


if __name__ == "__main__":
    main()
