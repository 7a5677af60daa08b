"""Geometry of the neck prototype (lab/regions/necks.py, its rule and tables in necks.md): the
heat-method geodesic distance, the length of a distance's level sets, persistent maxima, face
sets' perimeters. Lab code, not product; checked by necks_check.py.

Every length is in units of the mesh's bounding-box diagonal (the caller scales the vertices), so
that each threshold of necks.py is scale-free.
"""
import numpy as np
import scipy.sparse as sp
import scipy.sparse.csgraph  # noqa: F401 (sp.csgraph)
import scipy.sparse.linalg as spla


class Mesh:
    """A triangle mesh with the operators of the heat method (Crane, Weischedel, Wardetzky 2013:
    "Geodesics in Heat"): cotan Laplacian, lumped mass, face gradients; the two matrices are
    factorised once (on the first distance) so that each source costs two pairs of triangular
    solves."""

    def __init__(self, v, f):
        self.v, self.f = v, f
        nv = len(v)
        p0, p1, p2 = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
        cr = np.cross(p1 - p0, p2 - p0)
        dbl = np.linalg.norm(cr, axis=1)
        self.area = 0.5 * dbl
        self.normal = cr / np.maximum(dbl, 1e-300)[:, None]
        self.centroid = (p0 + p1 + p2) / 3.0
        # cotangent of the angle at corner k, opposite the edge (k+1, k+2)
        rows, cols, vals = [], [], []
        self.e = []  # e[k]: the edge vector opposite corner k
        for k in range(3):
            a, b, c = f[:, k], f[:, (k + 1) % 3], f[:, (k + 2) % 3]
            u, w = v[b] - v[a], v[c] - v[a]
            cot = (u * w).sum(1) / np.maximum(dbl, 1e-300)
            self.e.append(v[c] - v[b])
            rows += [b, c, b, c]
            cols += [c, b, b, c]
            vals += [0.5 * cot, 0.5 * cot, -0.5 * cot, -0.5 * cot]
        self.L = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                               shape=(nv, nv))  # negative semi-definite
        mass = np.zeros(nv)
        for k in range(3):
            np.add.at(mass, f[:, k], self.area / 3.0)
        self.mass = mass
        M = sp.diags(mass)
        edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
        self.h = float(np.linalg.norm(v[edges[:, 0]] - v[edges[:, 1]], axis=1).mean())
        t = self.h ** 2
        self.heat_matrix = (M - t * self.L).tocsc()  # factorised on first use (not for Dijkstra)
        # The Poisson matrix is singular (constants); a shift of 1e-8 of its own diagonal scale
        # (relative, so that it does not vanish on a fine mesh) fixes the constant and changes
        # the distances by far less than the heat method's own error.
        shift = 1e-8 * float(-self.L.diagonal().mean()) / float(mass.mean())
        self.poisson_matrix = (-self.L + shift * M).tocsc()
        # vertex adjacency (for persistence, pieces)
        self.adj = sp.csr_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(nv, nv))
        self.adj = ((self.adj + self.adj.T) > 0).tocsr()
        # face edges: key per undirected edge, its faces
        key = np.sort(edges, axis=1)
        uniq, inv, cnt = np.unique(key, axis=0, return_inverse=True, return_counts=True)
        self.edge_vertices, self.face_edge, self.edge_faces_count = uniq, inv.reshape(3, -1).T, cnt
        self.edge_len = np.linalg.norm(v[uniq[:, 0]] - v[uniq[:, 1]], axis=1)
        nf = len(f)
        fe = np.concatenate([np.arange(nf)] * 3)
        self.edge_face = sp.csr_matrix((np.ones(3 * nf), (inv.ravel(), fe)), shape=(len(uniq), nf))
        ff = (self.edge_face.T @ self.edge_face).tocsr()
        ff.setdiag(0)
        ff.eliminate_zeros()
        self.face_adj = ff

    # necks.py --distance dijkstra: edge-graph distances instead (what a port could take from
    # src/geometry/edge_dijkstra.cpp)
    dijkstra = False

    def distance(self, sources):
        """Geodesic distance to the vertex set `sources` (heat method, t = h^2)."""
        if Mesh.dijkstra:
            if not hasattr(self, "graph"):
                ev = self.edge_vertices
                self.graph = sp.csr_matrix((self.edge_len, (ev[:, 0], ev[:, 1])), shape=(len(self.v),) * 2)
            d = sp.csgraph.dijkstra(self.graph, directed=False, indices=np.atleast_1d(sources), min_only=True)
            return d
        if not hasattr(self, "heat"):
            self.heat, self.poisson = spla.splu(self.heat_matrix), spla.splu(self.poisson_matrix)
        delta = np.zeros(len(self.v))
        delta[np.atleast_1d(sources)] = 1.0
        u = self.heat.solve(delta)
        f, v = self.f, self.v
        grad = np.zeros((len(f), 3))
        for k in range(3):  # grad u = sum_k u_k (N x e_k) / (2A)
            grad += u[f[:, k]][:, None] * np.cross(self.normal, self.e[k])
        # u spans hundreds of decades on a fine mesh: scale each face's gradient by its largest
        # component before normalising, or its norm underflows and X blows up; a face where u
        # underflowed to 0 carries no direction (X = 0).
        big = np.abs(grad).max(axis=1)
        grad = grad / np.where(big > 0, big, 1.0)[:, None]
        X = -grad / np.maximum(np.linalg.norm(grad, axis=1), 1e-300)[:, None]
        div = np.zeros(len(v))
        for k in range(3):  # integrated divergence at corner k: 1/2 sum cot-weighted terms
            a, b, c = f[:, k], f[:, (k + 1) % 3], f[:, (k + 2) % 3]
            e1, e2 = v[b] - v[a], v[c] - v[a]
            cr = np.linalg.norm(np.cross(e1, e2), axis=1)
            cot_c = ((v[a] - v[c]) * (v[b] - v[c])).sum(1) / np.maximum(cr, 1e-300)  # angle at c, opp. e1
            cot_b = ((v[a] - v[b]) * (v[c] - v[b])).sum(1) / np.maximum(cr, 1e-300)  # angle at b, opp. e2
            np.add.at(div, a, 0.5 * (cot_c * (e1 * X).sum(1) + cot_b * (e2 * X).sum(1)))
        phi = self.poisson.solve(-div)
        d = phi - phi[np.atleast_1d(sources)].mean()
        return np.maximum(d, 0.0)

    def level_length(self, d, levels):
        """Total length of the level sets {d = r} for each r of `levels` (d linear on each face):
        each face adds a tent in r, 0 at its smallest and largest corner value and the length of
        its middle corner's cross-section there; tents are summed as ramps (exact)."""
        f, v = self.f, self.v
        order = np.argsort(d[f], axis=1)
        fi = np.take_along_axis(f, order, axis=1)
        a, b, c = d[fi[:, 0]], d[fi[:, 1]], d[fi[:, 2]]
        span = c - a
        ok = span > 1e-12
        s = np.where(ok, (b - a) / np.where(ok, span, 1.0), 0.0)
        q = v[fi[:, 0]] + s[:, None] * (v[fi[:, 2]] - v[fi[:, 0]])
        ell = np.where(ok, np.linalg.norm(v[fi[:, 1]] - q, axis=1), 0.0)
        up, down = b - a, c - b
        eps = 1e-9 * max(span.max(), 1e-300)
        s1 = ell / np.maximum(up, eps)
        s2 = ell / np.maximum(down, eps)
        # rising ramp on [a, b] (slope s1) then falling on [b, c] (slope -s2), as four ramps
        knots = np.concatenate([a, np.maximum(b, a + eps), b, np.maximum(c, b + eps)])
        slopes = np.concatenate([s1, -s1, -s2, s2])
        srt = np.argsort(knots)
        knots, slopes = knots[srt], slopes[srt]
        cw, cwk = np.cumsum(slopes), np.cumsum(slopes * knots)
        idx = np.searchsorted(knots, levels, side="right") - 1
        out = np.where(idx >= 0, levels * cw[np.maximum(idx, 0)] - cwk[np.maximum(idx, 0)], 0.0)
        return np.maximum(out, 0.0)

    def perimeter(self, mask):
        """Length of the edges with exactly one face in `mask`."""
        inside = self.edge_face @ mask.astype(float)
        return float(self.edge_len[inside == 1].sum())

    def compactness(self, mask):
        a = self.area[mask].sum()
        return self.perimeter(mask) ** 2 / (4 * np.pi * max(a, 1e-300))

    def largest_piece(self, mask):
        """The largest edge-connected piece of a face set, by area."""
        if not mask.any():
            return mask
        idx = np.flatnonzero(mask)
        sub = self.face_adj[idx][:, idx]
        n, lab = sp.csgraph.connected_components(sub, directed=False)
        areas = np.bincount(lab, weights=self.area[idx], minlength=n)
        out = np.zeros_like(mask)
        out[idx[lab == int(np.argmax(areas))]] = True
        return out


def persistent_maxima(adj, g, tau):
    """Vertices that are maxima of g with persistence at least tau (0-dimensional persistence of
    the superlevel sets on the edge graph): sweeping g downwards, a component is born at its
    peak and dies when it merges with a component whose peak is higher; the global maximum
    never dies. Returns (vertex, persistence) pairs, highest g first."""
    order = np.argsort(-g, kind="stable")
    parent = -np.ones(len(g), int)
    peak = np.zeros(len(g), int)
    pers = {}

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    indptr, indices = adj.indptr, adj.indices
    for vtx in order:
        parent[vtx] = vtx
        peak[vtx] = vtx
        for w in indices[indptr[vtx]:indptr[vtx + 1]]:
            if parent[w] < 0:
                continue
            ra, rb = find(vtx), find(w)
            if ra == rb:
                continue
            # the root with the lower peak dies here
            if g[peak[ra]] < g[peak[rb]] or (g[peak[ra]] == g[peak[rb]] and peak[ra] > peak[rb]):
                ra, rb = rb, ra
            lo = peak[rb]
            if lo != vtx:
                pers[lo] = g[lo] - g[vtx]
            parent[rb] = ra
    top = order[0]
    pers[top] = np.inf
    out = [(p, s) for p, s in pers.items() if s >= tau]
    return sorted(out, key=lambda t: -g[t[0]])
