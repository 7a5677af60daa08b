#!/usr/bin/python3
"""Checks of the neck prototype's geometry (necks_geo.py, necks.py) on surfaces whose answer is
known, so that a table of necks.md is not the only evidence that the code does what it says:

1. A unit sphere: the heat distance from a vertex against the arc length (mean error under half
   an edge), and L(r) of the exact distance against 2 pi sin r: within 1 % on 12000 points and
   falling at least 2.5 times from 3000 points (edge h) to 12000 (h / 2), as an error of order h^2
   (the level curves lie on the inscribed mesh) does.
2. A ball on a neck: a surface of revolution, ball A (radius 1) on a cylinder of radius 0.4
   joined to a body (a ball of radius 2.5). From A's pole the rule must cut at a neck (not where
   L stops growing) and the region must hold A (every face with z < 1.8) and nothing of the body
   (no face with z > 3.0; the body's radius passes the cylinder's 0.4 at z = 3.03).
3. A capsule (a cylinder with round ends, no neck): the cut is where L stops growing, so the
   region is A's round end: no face beyond 1.5 radii from the pole along the axis.

Each check prints PASS or FAIL; the exit status is the number of failures.
Usage: /usr/bin/python3 lab/regions/necks_check.py
"""
import os
import sys

import numpy as np
import scipy.spatial

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import necks  # noqa: E402
import necks_geo as G  # noqa: E402


def sphere(n=3000, seed=0):
    p = np.random.default_rng(seed).normal(size=(n, 3))
    p /= np.linalg.norm(p, axis=1)[:, None]
    f = scipy.spatial.ConvexHull(p).simplices
    n_ = np.cross(p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]])
    flip = (n_ * p[f].mean(axis=1)).sum(1) < 0
    f[flip] = f[flip][:, [0, 2, 1]]
    return p, f


def revolution(rho, z0, z1, nz=160, nt=48):
    """A closed surface of revolution about z with radius rho(z) on [z0, z1], poles at both ends."""
    zs = np.linspace(z0, z1, nz)[1:-1]
    t = np.linspace(0, 2 * np.pi, nt, endpoint=False)
    ring = np.array([[rho(z) * np.cos(a), rho(z) * np.sin(a), z] for z in zs for a in t])
    v = np.vstack([[0, 0, z0], ring, [0, 0, z1]])
    f = []
    for i in range(nt):
        j = (i + 1) % nt
        f.append([0, 1 + j, 1 + i])
        for k in range(len(zs) - 1):
            a, b = 1 + k * nt, 1 + (k + 1) * nt
            f += [[a + i, a + j, b + i], [a + j, b + j, b + i]]
        last = 1 + (len(zs) - 1) * nt
        f.append([len(v) - 1, last + i, last + j])
    return v, np.array(f)


def normalised(v, f):
    return G.Mesh((v - v.min(0)) / np.linalg.norm(v.max(0) - v.min(0)), f)


def cut_from_pole(rho):
    """The surface of revolution of radius rho(z), z in [0, 8], cut from its pole at z = 0 as
    necks.py cuts a part: (cut, r_stop, neck, the region's face mask, the faces' mean z)."""
    v, f = revolution(rho, 0.0, 8.0)
    m = normalised(v, f)
    d = m.distance(0)
    cut, stop, neck = necks.cut_radius(m, d, m.area.sum())
    region = m.largest_piece(d[m.f].mean(axis=1) < cut)
    return cut, stop, neck, region, v[f].mean(axis=1)[:, 2]


def report(name, ok, detail):
    print(f"{'PASS' if ok else 'FAIL'} {name}: {detail}")
    return 0 if ok else 1


def main():
    bad = 0
    v, f = sphere()
    m = G.Mesh(v, f)
    s = int(np.argmax(v[:, 2]))
    d = m.distance(s)
    true = np.arccos(np.clip(v @ v[s], -1, 1))
    err = np.abs(d - true).mean()
    bad += report("sphere heat distance", err < 0.5 * m.h, f"mean error {err:.4f}, edge {m.h:.4f}")
    r = np.linspace(0.2, np.pi - 0.2, 12)
    rel = []
    for n in (3000, 12000):  # the level curves lie on the inscribed mesh: an error of order h^2
        v, f = sphere(n)
        m = G.Mesh(v, f)
        true = np.arccos(np.clip(v @ v[int(np.argmax(v[:, 2]))], -1, 1))
        rel.append(np.abs(m.level_length(true, r) / (2 * np.pi * np.sin(r)) - 1).max())
    bad += report("sphere level length", rel[1] < 0.01 and rel[1] < rel[0] / 2.5,
                  f"largest relative error {rel[0]:.4f} (3000 points), {rel[1]:.4f} (12000): second order")

    def ball_on_neck(z):
        a = np.sqrt(max(0.0, 1 - (z - 1) ** 2))
        body = np.sqrt(max(0.0, 2.5 ** 2 - (z - 5.5) ** 2))
        neck = 0.4 if 1.5 <= z <= 4.0 else 0.0
        return max(a, body, neck, 1e-3)
    cut, stop, neck, region, z = cut_from_pole(ball_on_neck)
    ok = neck is not None and region[z < 1.8].all() and not region[z > 3.0].any()
    bad += report("ball on a neck", ok, f"neck {neck}, r_stop {stop:.3f}, region z in "
                  f"[{z[region].min():.2f}, {z[region].max():.2f}] (A ends at 1.92, the body starts at 3.03)")

    def capsule(z):
        return max(np.sqrt(max(0.0, 1 - (z - 1) ** 2)) if z < 1 else
                   (1.0 if z <= 7 else np.sqrt(max(0.0, 1 - (z - 7) ** 2))), 1e-3)
    cut, stop, neck, region, z = cut_from_pole(capsule)
    ok = neck is None and region[z < 0.5].all() and z[region].max() < 1.5
    bad += report("capsule end", ok, f"neck {neck}, cut {cut:.3f}, region z up to {z[region].max():.2f}")
    return bad


if __name__ == "__main__":
    sys.exit(main())
