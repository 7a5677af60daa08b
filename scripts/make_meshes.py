#!/usr/bin/env python3
"""Generates the small committed test meshes in meshes/ (and meshes/bad/) deterministically.

Plain python3, no dependencies. Run from anywhere:  python3 scripts/make_meshes.py
Every output is rewritten; running it twice gives byte-identical files. Floats are written with
repr(), the shortest text that reads back to the same double (lossless).

Each good mesh is checked here before it is written (closed, edge-manifold, consistently
oriented, single fan per vertex, Euler characteristic as designed), so a generator bug fails
loudly instead of producing a bad fixture. meshes/README.md is written from the same data.
"""

import math
import os
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
OUT = os.path.join(ROOT, "meshes")
BAD = os.path.join(OUT, "bad")


# ----------------------------------------------------------------------------- small vector helpers
def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    return math.sqrt(dot(a, a))


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def normalized(a):
    return scale(a, 1.0 / norm(a))


def signed_volume(v, f):
    """Divergence theorem: V = 1/6 sum over triangles of x1 . (x2 x x3). Exact for a closed,
    outward-oriented polyhedron (up to rounding); math.fsum keeps the sum correctly rounded."""
    return math.fsum(dot(v[a], cross(v[b], v[c])) for a, b, c in triangles(f)) / 6.0


def triangles(f):
    """Fan split of polygons (only used for the volume of the quad cube)."""
    for p in f:
        for k in range(1, len(p) - 1):
            yield (p[0], p[k], p[k + 1])


# ----------------------------------------------------------------------------- topology checks
def check_closed_manifold(name, v, f, expected_chi):
    edges = {}
    for i, p in enumerate(f):
        n = len(p)
        assert len(set(p)) == n, f"{name}: face {i} repeats a vertex"
        for k in range(n):
            a, b = p[k], p[(k + 1) % n]
            edges.setdefault((min(a, b), max(a, b)), []).append(a < b)
    for e, uses in edges.items():
        assert len(uses) == 2, f"{name}: edge {e} has {len(uses)} faces"
        assert uses[0] != uses[1], f"{name}: edge {e} inconsistently oriented"
    # one fan per vertex: the link edges around each vertex form a single cycle
    link = {}
    for p in f:
        n = len(p)
        for k in range(n):
            link.setdefault(p[k], {})[p[(k + 1) % n]] = p[(k - 1) % n]
    assert len(link) == len(v), f"{name}: isolated vertices"
    for x, nxt in link.items():
        start = next(iter(nxt))
        cur, steps = nxt[start], 1
        while cur != start:
            cur, steps = nxt[cur], steps + 1
        assert steps == len(nxt), f"{name}: vertex {x} is non-manifold"
    chi = len(v) - len(edges) + len(f)
    assert chi == expected_chi, f"{name}: Euler characteristic {chi}, expected {expected_chi}"
    return chi


# ----------------------------------------------------------------------------- generators
def icosphere(levels, r):
    """Icosahedron subdivided `levels` times (each triangle into 4, midpoints projected to the
    sphere), radius r, outward counter-clockwise faces. Same construction and vertex order as
    tests/support/mesh_fixtures.hpp icosphere()."""
    t = (1.0 + math.sqrt(5.0)) / 2.0
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [normalized(p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        mid = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                m = (v[a][0] + v[b][0], v[a][1] + v[b][1], v[a][2] + v[b][2])
                v.append(normalized(m))
                mid[key] = len(v) - 1
            return mid[key]

        g = []
        for a, b, c in f:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            g += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = g
    return [scale(p, r) for p in v], f


def uv_sphere(n_lat, n_lon, r):
    """Latitude-longitude sphere: north pole, n_lat-1 rings of n_lon vertices, south pole."""
    v = [(0.0, 0.0, r)]
    for i in range(1, n_lat):
        th = math.pi * i / n_lat
        for j in range(n_lon):
            ph = 2.0 * math.pi * j / n_lon
            v.append((r * math.sin(th) * math.cos(ph), r * math.sin(th) * math.sin(ph), r * math.cos(th)))
    v.append((0.0, 0.0, -r))
    south = len(v) - 1

    def ring(i, j):  # ring i in 1..n_lat-1
        return 1 + (i - 1) * n_lon + (j % n_lon)

    f = []
    for j in range(n_lon):
        f.append((0, ring(1, j), ring(1, j + 1)))
    for i in range(1, n_lat - 1):
        for j in range(n_lon):
            a, b, c, d = ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1)
            f += [(a, b, c), (a, c, d)]
    for j in range(n_lon):
        f.append((south, ring(n_lat - 1, j + 1), ring(n_lat - 1, j)))
    return v, f


def torus(n_major, n_minor, R, r):
    """Torus around the z axis, major radius R, tube radius r; each grid quad split in two."""
    v = []
    for i in range(n_major):
        u = 2.0 * math.pi * i / n_major
        for j in range(n_minor):
            w = 2.0 * math.pi * j / n_minor
            rho = R + r * math.cos(w)
            v.append((rho * math.cos(u), rho * math.sin(u), r * math.sin(w)))

    def idx(i, j):
        return (i % n_major) * n_minor + (j % n_minor)

    f = []
    for i in range(n_major):
        for j in range(n_minor):
            a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
            f += [(a, b, c), (a, c, d)]
    return v, f


CUBE_V = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0),
          (0.0, 0.0, 1.0), (1.0, 0.0, 1.0), (1.0, 1.0, 1.0), (0.0, 1.0, 1.0)]
# Outward quads (counter-clockwise seen from outside).
CUBE_QUADS = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def cube():
    f = []
    for a, b, c, d in CUBE_QUADS:
        f += [(a, b, c), (a, c, d)]
    return list(CUBE_V), f


def octahedron():
    v = [(1.0, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, 1.0), (0.0, 0.0, -1.0)]
    f = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    return v, f


# Bumps: (unit axis, angular radius alpha in radians). Each bump is the part of a small sphere,
# centred on the axis at distance D_BUMP * R, that lies outside the base sphere of radius R;
# its radius rho follows from meeting the base sphere at angle alpha:
# rho^2 = R^2 + d^2 - 2 R d cos(alpha).
BUMPS = [((0.0, 0.0, 1.0), 0.60), (normalized((1.0, 0.0, -0.3)), 0.45), (normalized((-0.5, -0.8, -0.3)), 0.32)]
D_BUMP = 0.8


def bumpy_sphere(levels, R):
    """Icosphere of radius R whose vertices are pushed radially onto three small spheres (the
    bumps) where those stick out. Inside a bump the surface lies exactly on a sphere of radius
    rho < R, so region selection by curvature should find three spherical regions. Returns the
    mesh and, per bump, the faces whose three vertices all lie on that bump's sphere."""
    v, f = icosphere(levels, R)
    owner = [-1] * len(v)
    info = []
    for k, (axis, alpha) in enumerate(BUMPS):
        d = D_BUMP * R
        rho = math.sqrt(R * R + d * d - 2.0 * R * d * math.cos(alpha))
        info.append((axis, alpha, d, rho))
    for i, p in enumerate(v):
        u = normalized(p)
        best = R
        for k, (axis, alpha, d, rho) in enumerate(info):
            # ray origin + t u against the sphere |x - d axis| = rho (far intersection)
            uc = d * dot(u, axis)
            disc = uc * uc - d * d + rho * rho
            if disc <= 0.0:
                continue
            t = uc + math.sqrt(disc)
            if t > best * (1.0 + 1e-9):
                best, owner[i] = t, k
        v[i] = scale(u, best)
    bump_faces = [[j for j, tri in enumerate(f) if all(owner[a] == k for a in tri)] for k in range(len(BUMPS))]
    return v, f, bump_faces, info


def two_sheet(n_rings, n_theta, radius, gap):
    """Thin closed 'lens': two parallel discs of the given radius at z = +gap/2 and z = -gap/2,
    joined at a shared rim ring at z = 0. Under outside pressure the sheets meet at once."""
    v = []
    top = [[len(v)]]
    v.append((0.0, 0.0, gap / 2))
    for i in range(1, n_rings):
        rr = radius * i / n_rings
        top.append([len(v) + j for j in range(n_theta)])
        v += [(rr * math.cos(2 * math.pi * j / n_theta), rr * math.sin(2 * math.pi * j / n_theta), gap / 2) for j in range(n_theta)]
    rim = [len(v) + j for j in range(n_theta)]
    v += [(radius * math.cos(2 * math.pi * j / n_theta), radius * math.sin(2 * math.pi * j / n_theta), 0.0) for j in range(n_theta)]
    bottom = [[len(v)]]
    v.append((0.0, 0.0, -gap / 2))
    for i in range(1, n_rings):
        rr = radius * i / n_rings
        bottom.append([len(v) + j for j in range(n_theta)])
        v += [(rr * math.cos(2 * math.pi * j / n_theta), rr * math.sin(2 * math.pi * j / n_theta), -gap / 2) for j in range(n_theta)]
    top.append(rim)
    bottom.append(rim)
    f = []
    for sheet, up in ((top, True), (bottom, False)):
        c = sheet[0][0]
        for j in range(n_theta):
            a, b = sheet[1][j], sheet[1][(j + 1) % n_theta]
            f.append((c, a, b) if up else (c, b, a))
        for i in range(1, n_rings):
            for j in range(n_theta):
                a, b = sheet[i][j], sheet[i][(j + 1) % n_theta]
                c2, d2 = sheet[i + 1][j], sheet[i + 1][(j + 1) % n_theta]
                f += [(a, c2, d2), (a, d2, b)] if up else [(a, d2, c2), (a, b, d2)]
    return v, f


def grid_sheet(n):
    """Open flat square [0,1]^2 at z = 0, n x n quads split in two (has a boundary)."""
    v = [(i / n, j / n, 0.0) for j in range(n + 1) for i in range(n + 1)]
    f = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            b, c, d = a + 1, a + n + 2, a + n + 1
            f += [(a, b, c), (a, c, d)]
    return v, f


def tetra(offset, o):
    """Outward tetrahedron with corner o, vertex ids starting at offset."""
    v = [o, (o[0] + 1, o[1], o[2]), (o[0], o[1] + 1, o[2]), (o[0], o[1], o[2] + 1)]
    f = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    return v, [tuple(offset + i for i in t) for t in f]


# ----------------------------------------------------------------------------- writers
def fmt(x):
    return repr(float(x))


def off_text(v, f, comment=None):
    lines = ["OFF"]
    if comment:
        lines.append("# " + comment)
    lines.append(f"{len(v)} {len(f)} 0")
    lines += [" ".join(fmt(c) for c in p) for p in v]
    lines += [" ".join([str(len(t))] + [str(i) for i in t]) for t in f]
    return "\n".join(lines) + "\n"


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="\n") as fh:
        fh.write(text)
    size = os.path.getsize(path)
    assert size < 100_000, f"{path} is {size} bytes"


# ----------------------------------------------------------------------------- main
def main():
    rows = []  # README table rows

    def good(name, v, f, chi, genus, volume_note, comment, components=1):
        check_closed_manifold(name, v, f, chi)
        assert signed_volume(v, f) > 0.0, f"{name} is not outward oriented"
        write(os.path.join(OUT, name + ".off"), off_text(v, f, comment))
        ntri = sum(len(p) - 2 for p in f)
        rows.append((name + ".off", len(v), f"{len(f)}" + ("" if ntri == len(f) else f" ({ntri} triangles)"),
                     f"{genus} / {chi}", components, "yes", volume_note))

    R = 0.5
    for lv in (1, 2, 3):
        v, f = icosphere(lv, R)
        vol = signed_volume(v, f)
        good(f"ico{lv}", v, f, 2, 0,
             f"{vol:.15g} (computed, see below; sphere 4/3 pi r^3 = {4 / 3 * math.pi * R ** 3:.6g})",
             f"icosphere level {lv}, radius {R}, made by scripts/make_meshes.py")

    v, f = uv_sphere(12, 24, R)
    good("uv_sphere", v, f, 2, 0, f"{signed_volume(v, f):.15g} (computed)",
         "UV sphere, 12 latitude bands x 24 longitudes, radius 0.5, made by scripts/make_meshes.py")

    v, f = torus(32, 16, 0.35, 0.15)
    good("torus", v, f, 0, 1,
         f"{signed_volume(v, f):.15g} (computed; smooth torus 2 pi^2 R r^2 = {2 * math.pi ** 2 * 0.35 * 0.15 ** 2:.6g})",
         "torus R = 0.35, r = 0.15, 32 x 16 grid, made by scripts/make_meshes.py")

    v, f = cube()
    good("cube", v, f, 2, 0, "1 (exact: unit cube [0,1]^3)", "unit cube [0,1]^3, made by scripts/make_meshes.py")

    v, f = octahedron()
    good("octahedron", v, f, 2, 0, "4/3 (exact: vertices at distance 1 on the axes)",
         "regular octahedron, vertices +-1 on the axes, made by scripts/make_meshes.py")

    v, f, bump_faces, info = bumpy_sphere(3, R)
    good("bumpy_sphere", v, f, 2, 0, f"{signed_volume(v, f):.15g} (computed)",
         "icosphere level 3 (radius 0.5) with 3 spherical bumps; bump faces in bumpy_sphere.bumps.txt")
    write(os.path.join(OUT, "bumpy_sphere.bumps.txt"), "".join(" ".join(str(j) for j in b) + "\n" for b in bump_faces))
    for k, b in enumerate(bump_faces):
        assert len(b) >= 10, f"bump {k} has only {len(b)} faces"

    v, f = two_sheet(6, 32, 0.5, 0.02)
    good("two_sheet", v, f, 2, 0, f"{signed_volume(v, f):.15g} (computed; flat disc pi r^2 gap = {math.pi * 0.25 * 0.02:.6g})",
         "two discs of radius 0.5, gap 0.02, joined at the rim, made by scripts/make_meshes.py")

    # Inside-out sphere: ico2 with every face reversed; read_input_mesh flips it back (warning).
    v, f = icosphere(2, R)
    inv = [(a, c, b) for a, b, c in f]
    check_closed_manifold("inside_out_sphere", v, inv, 2)
    write(os.path.join(OUT, "inside_out_sphere.off"), off_text(v, inv, "ico2 with all faces reversed (inside-out), made by scripts/make_meshes.py"))
    rows.append(("inside_out_sphere.off", len(v), len(inv), "0 / 2", 1, "yes",
                 f"{signed_volume(v, inv):.15g} as stored (= -ico2); reoriented on reading"))

    # Quad cube: 6 quads, triangulated on reading (warning).
    check_closed_manifold("cube_quads", CUBE_V, CUBE_QUADS, 2)
    write(os.path.join(OUT, "cube_quads.off"), off_text(CUBE_V, CUBE_QUADS, "unit cube with 6 quads, made by scripts/make_meshes.py"))
    rows.append(("cube_quads.off", 8, "6 quads (12 triangles)", "0 / 2", 1, "yes", "1 (exact)"))

    # Zero-area face: the unit cube where edge (0,2) (the bottom diagonal) gets its midpoint m on
    # one side only; the sliver (2, 0, m) closes the surface and has zero area. Volume stays 1.
    v, f = cube()
    v.append((0.5, 0.5, 0.0))  # m = vertex 8, midpoint of vertices 0 and 2
    m = 8
    # bottom quad (0,3,2,1) was split into (0,3,2) and (0,2,1); split (0,2,1) at m:
    assert f[1] == (0, 2, 1)
    f[1] = (0, m, 1)
    f.append((m, 2, 1))
    f.append((0, 2, m))  # the zero-area face, index 13
    check_closed_manifold("zero_area_face", v, f, 2)
    write(os.path.join(OUT, "zero_area_face.off"), off_text(v, f, "unit cube with a zero-area sliver face (face 13), made by scripts/make_meshes.py"))
    rows.append(("zero_area_face.off", len(v), len(f), "0 / 2", 1, "yes", "1 (exact; face 13 has zero area)"))

    # ------------------------------------------------------------------ meshes/bad
    bad_rows = []

    def bad(name, text, problem):
        write(os.path.join(BAD, name), text)
        bad_rows.append((name, problem))

    v, f = grid_sheet(4)
    bad("open_sheet.off", off_text(v, f, "open 4x4 grid square, z = 0"),
        f"open boundary ({len(v)} vertices, {len(f)} faces, 16 boundary edges; chi = 1)")

    # Two tetrahedra sharing the edge (0,1): that edge has 4 faces. The second is the first
    # rotated by 180 degrees about the x axis (y -> -y, z -> -z), so its faces keep their order.
    v1, f1 = tetra(0, (0.0, 0.0, 0.0))
    v2 = [(0.0, -1.0, 0.0), (0.0, 0.0, -1.0)]
    f2 = [tuple({0: 0, 1: 1, 2: 4, 3: 5}[i] for i in t) for t in f1]
    bad("nonmanifold_edge.off", off_text(v1 + v2, f1 + f2, "two tetrahedra sharing edge (0,1)"),
        "non-manifold edge (0, 1) shared by 4 faces")

    # Two tetrahedra sharing vertex 0 only.
    v1, f1 = tetra(0, (0.0, 0.0, 0.0))
    v2 = [(-1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0)]
    f2 = [(0, 4, 5), (0, 6, 4), (0, 5, 6), (4, 6, 5)]
    bad("nonmanifold_vertex.off", off_text(v1 + v2, f1 + f2, "two tetrahedra sharing vertex 0 only"),
        "non-manifold vertex 0 (two fans)")

    cube_v, cube_f = cube()
    cube_off = off_text(cube_v, cube_f)
    lines = cube_off.splitlines()
    # header (2 lines) + 8 vertices + the first 5 faces, the 6th cut in the middle
    bad("truncated.off", "\n".join(lines[:2 + 8 + 5]) + "\n3 1 2\n", "truncated file (header announces 12 faces, the file ends inside face 5, line 16)")
    bad("garbage.off", "this is not a mesh\n\x01\x02\x03 binary junk \xff\n", "parse error (line 1, no OFF header)")
    nan_lines = list(lines)
    nan_lines[2 + 3] = "1.0 nan 0.0"  # vertex 3, line 6
    bad("nan.off", "\n".join(nan_lines) + "\n", "non-finite coordinate (vertex 3, line 6)")
    oor_lines = list(lines)
    oor_lines[2 + 8 + 4] = "3 0 8 4"  # face 4 (line 15) refers to vertex 8 of 8
    bad("index_out_of_range.off", "\n".join(oor_lines) + "\n", "vertex index out of range (face 4, line 15, vertex 8)")
    bad("empty.off", "", "empty file (0 bytes)")
    rep_lines = list(lines)
    rep_lines[2 + 8 + 7] = "3 1 1 6"  # face 7 (line 18) repeats vertex 1
    bad("repeated_vertex.off", "\n".join(rep_lines) + "\n", "degenerate face (face 7, line 18, uses vertex 1 twice)")
    dup = off_text(cube_v, cube_f + [cube_f[2]])
    bad("duplicate_face.off", dup, "duplicate face (face 12 repeats face 2)")
    bad("cube.xyz", "0 0 0\n1 0 0\n", "unknown extension (.xyz)")
    flip = list(cube_f)
    flip[5] = (flip[5][0], flip[5][2], flip[5][1])  # face 5 reversed: it agrees with no neighbour
    bad("inconsistent_orientation.off", off_text(cube_v, flip),
        "inconsistent orientation (faces 2 and 5, lines 13 and 16, both traverse edge (4, 5))")

    # ------------------------------------------------------------------ README
    ico_note = ("Icosphere (and other 'computed') volumes are the divergence-theorem sum "
                "V = 1/6 sum_f x1 . (x2 x x3) over the written triangles, evaluated with math.fsum "
                "in scripts/make_meshes.py. They are the exact volumes of the polyhedra (up to "
                "double rounding), slightly below the smooth shape's volume because the vertices lie "
                "on the sphere and the flat faces inside it.")
    out = ["# Test meshes", "",
           "Generated by `python3 scripts/make_meshes.py` (deterministic, no dependencies; do not edit by hand).",
           "All good meshes are closed, manifold, consistently outward-oriented triangle meshes unless noted;",
           "the script checks this before writing. Floats are written with Python `repr` (lossless).",
           "genus / chi: genus and Euler characteristic V - E + F (chi = 2 - 2 genus per closed component).", "",
           "| file | vertices | faces | genus / chi | components | closed | volume |",
           "|---|---|---|---|---|---|---|"]
    out += [f"| {r[0]} | {r[1]} | {r[2]} | {r[3]} | {r[4]} | {r[5]} | {r[6]} |" for r in rows]
    out += ["", ico_note, "",
            "Notes:", "",
            "- `ico1..3`: radius 0.5, same construction and vertex order as `icosphere()` in "
            "`tests/support/mesh_fixtures.hpp` (icosahedron, each level splits every triangle into 4 "
            "and projects the midpoints to the sphere). V = 10*4^l + 2, F = 20*4^l.",
            "- `bumpy_sphere`: ico3 of radius 0.5 whose vertices are pushed radially onto three small "
            "spheres where these stick out (bump k: axis a_k, small sphere centred at 0.8*0.5*a_k with "
            "radius rho_k chosen so that it meets the base sphere at angular radius alpha_k). "
            "`bumpy_sphere.bumps.txt` has one line per bump: the indices of the faces whose three "
            "vertices lie on that bump's sphere. Bumps (axis, alpha, rho):",
            ]
    for k, (axis, alpha, d, rho) in enumerate(info):
        out.append(f"  - bump {k}: axis ({axis[0]:.6g}, {axis[1]:.6g}, {axis[2]:.6g}), alpha {alpha} rad, "
                   f"rho {rho:.6g}, {len(bump_faces[k])} faces")
    out += ["- `two_sheet`: two flat discs (radius 0.5, 6 rings x 32 sectors each) at z = +-0.01 "
            "(gap 0.02 = 2% of the diameter), sharing the rim ring at z = 0: a thin closed shell that "
            "makes contact at once under pressure.",
            "- `inside_out_sphere`: ico2 with every face reversed; `read_input_mesh` flips it back with a warning.",
            "- `cube_quads`: the unit cube as 6 quads; read_input_mesh fan-triangulates them (12 triangles, warning).",
            "- `zero_area_face`: the unit cube whose bottom diagonal (0,2) has its midpoint (vertex 8) on "
            "one side only; face 13 = (0, 2, 8) is a zero-area sliver that closes the surface. "
            "read_input_mesh reports face 13 in `zero_area_faces` with a warning. The sliver lies on the "
            "diagonal, so CGAL's self-intersection test also reports pairs here (faces touching the "
            "diagonal beyond a shared vertex, and the degenerate face with itself).",
            "", "## bad/ (inputs that read_input_mesh and `shellcontract check` must refuse, exit code 2)", "",
            "| file | problem |", "|---|---|"]
    out += [f"| {n} | {p} |" for n, p in bad_rows]
    out += ["", "Line numbers count from 1 and include the header line(s).", ""]
    write(os.path.join(OUT, "README.md"), "\n".join(out))
    print(f"wrote {len(rows)} meshes and {len(bad_rows)} bad files under {OUT}")


if __name__ == "__main__":
    sys.exit(main())
