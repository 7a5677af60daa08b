#!/usr/bin/python3
"""A small z-buffer rasterizer for triangle meshes (numpy only; PNG via matplotlib's imsave).

Why not matplotlib's 3D axes: Poly3DCollection sorts whole polygons by their mean depth and paints
them back to front, so on thin parts (fingers, legs, antlers) far faces are painted over near ones.
Here every pixel keeps the nearest surface (a per-pixel depth test), so there is no such artefact.

The camera is orthographic and turns about the mesh's up axis, so a model that stands on y (the
paper's CGAL meshes) is drawn standing, not lying on its back. The up axis comes from --up or from
detect_up() (the rule is in its docstring).

Importable: read_mesh(), detect_up(), render() (returns an RGB float image), save_png().
Command line: lab/scripts/render_mesh.py IN.(off|ply|obj) OUT.png [--up auto|x|y|z|-x|-y|-z]
              [--azim 30] [--elev 15] [--size 800x600] [--title TEXT]
"""
import argparse
import sys

import numpy as np

# ----------------------------------------------------------------------------- reading

def _read_off(path):
    # Comments (#) may follow the header line, as in meshes/bumpy_sphere.off.
    words = []
    with open(path) as f:
        for line in f:
            words.extend(line.split("#", 1)[0].split())
    if words[0] != "OFF":
        raise ValueError(f"{path}: not an OFF file")
    nv, nf = int(words[1]), int(words[2])
    V = np.array(words[4:4 + 3 * nv], float).reshape(nv, 3)
    F, k = [], 4 + 3 * nv
    for _ in range(nf):
        n = int(words[k])
        F.append([int(w) for w in words[k + 1:k + 1 + n]])
        k += 1 + n
    return V, _triangulate(F), None


def _read_obj(path):
    V, F = [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                V.append([float(t) for t in w[1:4]])
            elif w[0] == "f":
                F.append([int(t.split("/")[0]) - 1 for t in w[1:]])
    return np.array(V), _triangulate(F), None


def _read_ply(path):
    """ASCII PLY as shellcontract writes it: per-face colours (regions) or per-vertex colours
    (fields) become one colour per triangle."""
    with open(path) as f:
        lines = f.read().split("\n")
    i, nv, nf, vprops, fprops, elem = 0, 0, 0, [], [], None
    if "format ascii" not in lines[1]:
        raise ValueError(f"{path}: only ASCII PLY is read")
    while lines[i] != "end_header":
        w = lines[i].split()
        if w[:2] == ["element", "vertex"]:
            nv, elem = int(w[2]), "v"
        elif w[:2] == ["element", "face"]:
            nf, elem = int(w[2]), "f"
        elif w and w[0] == "property":
            (vprops if elem == "v" else fprops).append(w[-1])
        i += 1
    i += 1
    VA = np.array([[float(t) for t in lines[i + k].split()] for k in range(nv)])
    F, FC = [], []
    for k in range(nf):
        t = lines[i + nv + k].split()
        n = int(t[0])
        F.append([int(v) for v in t[1:1 + n]])
        rest = t[1 + n:]
        if "red" in fprops:
            # The list property comes first in shellcontract's PLY, so fprops[1:] index `rest`.
            r = fprops.index("red") - 1
            FC.append([int(rest[r + c]) / 255 for c in range(3)])
    F = np.array(F)
    if FC:
        C = np.array(FC)
    elif "red" in vprops:
        r = vprops.index("red")
        C = (VA[:, r:r + 3] / 255)[F].mean(axis=1)
    else:
        C = None
    return VA[:, :3], F, C


def _triangulate(F):
    tris = []
    for f in F:
        for k in range(1, len(f) - 1):  # fan: the project's meshes are convex polygons at most
            tris.append([f[0], f[k], f[k + 1]])
    return np.array(tris, dtype=int)


def read_mesh(path):
    """(V n×3, F m×3 triangles, per-triangle colours m×3 in [0,1] or None)."""
    ext = path.rsplit(".", 1)[-1].lower()
    return {"off": _read_off, "obj": _read_obj, "ply": _read_ply}[ext](path)


def write_off(path, V, F):
    with open(path, "w") as f:
        f.write(f"OFF\n{len(V)} {len(F)} 0\n")
        np.savetxt(f, V, fmt="%.9g")
        np.savetxt(f, np.column_stack([np.full(len(F), 3), F]), fmt="%d")


# ----------------------------------------------------------------------------- up axis

AXES = {"x": np.array([1.0, 0, 0]), "y": np.array([0, 1.0, 0]), "z": np.array([0, 0, 1.0])}


def parse_axis(text):
    sign = -1.0 if text.startswith("-") else 1.0
    return sign * AXES[text.lstrip("+-")]


def detect_up(V, F, slab=0.05):
    """The up axis of a mesh, by this rule: a model stands on its lowest part, and what it
    stands on (a foot sole, a cut wrist, the base of a figure) faces the floor. So

      up = the signed axis d maximising the area of faces whose outward normal points down
           (n . d < -0.5) among the faces in the bottom `slab` of the extent along d.

    On the paper's meshes this gives +z for eight and hand (the hand stands on its wrist) and +y
    for elk and bear: upright in renders along each axis, checked by eye. A mesh with no preferred floor (a
    sphere) gets whichever axis scores first among +y, +z, +x (y up is the OFF/OBJ habit);
    render_mesh.py --up overrides the rule."""
    tri = V[F]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area = np.linalg.norm(n, axis=1) / 2
    n = n / np.maximum(2 * area, 1e-300)[:, None]
    centroid = tri.mean(axis=1)
    best, best_score = AXES["y"], -1.0
    for name in ("y", "z", "x"):
        for sign in (1.0, -1.0):
            d = sign * AXES[name]
            h = centroid @ d
            lo, hi = (V @ d).min(), (V @ d).max()
            low = h <= lo + slab * (hi - lo)
            score = area[low & (n @ d < -0.5)].sum() / area.sum()
            if score > best_score + 1e-9:
                best, best_score = d, score
    return best


# ----------------------------------------------------------------------------- camera

def camera_basis(up, azim_deg, elev_deg):
    """Orthonormal (right, screen_up, toward_viewer) rows. The camera circles the up axis by
    azim and looks down on the model by elev; azim 0 looks from the second axis after `up` in the
    x, y, z cycle (for y up: azim 0 looks from +x, azim 90 from -z)."""
    up = up / np.linalg.norm(up)
    k = int(np.argmax(np.abs(up)))
    front = np.zeros(3)
    front[(k + 2) % 3] = 1.0  # y up -> front +x; z up -> front +y; x up -> front +z
    side = np.cross(up, front)
    a, e = np.radians(azim_deg), np.radians(elev_deg)
    horiz = np.cos(a) * front + np.sin(a) * side
    toward = np.cos(e) * horiz + np.sin(e) * up
    right = np.cross(up, toward)
    right /= np.linalg.norm(right)
    screen_up = np.cross(toward, right)
    return np.array([right, screen_up, toward])


def view_toward(direction, up, max_elev=60.0):
    """(azim, elev) of camera_basis() that looks at the model from `direction` (e.g. from the
    model's centre toward a region), the elevation clipped so the up axis still reads as up."""
    up = up / np.linalg.norm(up)
    front = camera_basis(up, 0.0, 0.0)[2]
    side = np.cross(up, front)
    d = direction / np.linalg.norm(direction)
    azim = np.degrees(np.arctan2(d @ side, d @ front))
    elev = np.clip(np.degrees(np.arcsin(np.clip(d @ up, -1, 1))), -max_elev, max_elev)
    return float(azim), float(elev)


# ----------------------------------------------------------------------------- rasterizer

def rasterize(P, F, face_rgb, width, height):
    """P: vertices in pixel coordinates (x right, y down, z toward the viewer). Every pixel
    centre inside a triangle (barycentric test) becomes a fragment with the triangle's
    interpolated depth; each pixel keeps its nearest fragment (the z-buffer's depth test, done
    for all fragments at once by a sort instead of a per-triangle loop, which is 10-50x faster
    in numpy). Returns (rgb image, mask of covered pixels)."""
    tri = P[F]
    lo = np.maximum(np.floor(tri[:, :, :2].min(axis=1) - 0.5).astype(int), 0)
    hi = np.minimum(np.ceil(tri[:, :, :2].max(axis=1) - 0.5).astype(int), [width - 1, height - 1])
    extent = (hi - lo).max(axis=1) + 1
    pix, z, tid = [], [], []
    # Triangles are bucketed by the side of their pixel bounding box (a power of two), so each
    # bucket is one array of shape (triangles, side, side) and no bucket wastes much work.
    side = 1
    while True:
        sel = np.nonzero((extent <= side) & (extent > side // 2) & (hi >= lo).all(axis=1))[0]
        for chunk in np.array_split(sel, max(1, len(sel) * side * side // 4_000_000 + 1)):
            if len(chunk):
                _fragments(tri[chunk], lo[chunk], side, width, height, chunk, pix, z, tid)
        if side >= extent.max(initial=1):
            break
        side *= 2
    img = np.ones((height, width, 3))
    covered = np.zeros(height * width, bool)
    if pix:
        pix, z, tid = np.concatenate(pix), np.concatenate(z), np.concatenate(tid)
        order = np.lexsort((z, pix))              # by pixel, then depth ascending
        last = np.r_[pix[order][1:] != pix[order][:-1], True]  # nearest fragment of each pixel
        keep = order[last]
        img.reshape(-1, 3)[pix[keep]] = face_rgb[tid[keep]]
        covered[pix[keep]] = True
    return img, covered.reshape(height, width)


def _fragments(tri, lo, side, width, height, ids, pix, z, tid):
    """Appends the fragments of triangles `tri` (k×3×3, pixel coords) on a side×side pixel grid
    starting at `lo` (k×2)."""
    off = np.arange(side)
    X = lo[:, 0, None, None] + off[None, None, :] + 0.5   # k×1×side
    Y = lo[:, 1, None, None] + off[None, :, None] + 0.5   # k×side×1
    x0, y0, z0 = (tri[:, 0, c, None, None] for c in range(3))
    x1, y1, z1 = (tri[:, 1, c, None, None] for c in range(3))
    x2, y2, z2 = (tri[:, 2, c, None, None] for c in range(3))
    det = (y1 - y2) * (x0 - x2) + (x2 - x1) * (y0 - y2)
    det = np.where(np.abs(det) < 1e-12, np.nan, det)      # edge-on: covers no pixel centre
    b0 = ((y1 - y2) * (X - x2) + (x2 - x1) * (Y - y2)) / det
    b1 = ((y2 - y0) * (X - x2) + (x0 - x2) * (Y - y2)) / det
    b2 = 1 - b0 - b1
    inside = (b0 >= -1e-9) & (b1 >= -1e-9) & (b2 >= -1e-9) & (X < width) & (Y < height)
    k, r, c = np.nonzero(inside)
    pix.append((lo[k, 1] + r) * width + lo[k, 0] + c)
    z.append((b0 * z0 + b1 * z1 + b2 * z2)[k, r, c])
    tid.append(ids[k])


def render(V, F, colours=None, up=None, azim=30.0, elev=15.0, size=(800, 600), fit=None,
           supersample=2):
    """RGB float image (height×width×3) of the mesh, Lambert-shaded per face by a light over the
    viewer's left shoulder, white background. The view is fitted to the vertices `fit` (default
    V): pass a run's input as `fit` when drawing its output, so both are drawn at one scale."""
    if up is None:
        up = detect_up(V, F)
    R = camera_basis(np.asarray(up, float), azim, elev)
    fit = V if fit is None else fit
    centre = (fit.min(axis=0) + fit.max(axis=0)) / 2
    w, h = size[0] * supersample, size[1] * supersample
    half = np.abs((fit - centre) @ R[:2].T).max(axis=0)  # half extents on screen, model units
    scale = 0.92 * min(w / (2 * half[0]), h / (2 * half[1]))
    C = (V - centre) @ R.T  # camera coordinates: right, up, toward viewer
    P = np.column_stack([w / 2 + scale * C[:, 0], h / 2 - scale * C[:, 1], C[:, 2]])
    tri = C[F]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    n[n[:, 2] < 0] *= -1  # two-sided: a face seen from behind (inside-out input) is still lit
    light = np.array([-0.4, 0.5, 1.0])
    light /= np.linalg.norm(light)
    shade = 0.25 + 0.75 * np.clip(n @ light, 0, 1)
    base = np.full((len(F), 3), 0.72) if colours is None else np.asarray(colours, float)
    img, _ = rasterize(P, F, np.clip(base * shade[:, None], 0, 1), w, h)
    if supersample > 1:  # box-filter down: smooth edges without a per-edge coverage computation
        img = img.reshape(size[1], supersample, size[0], supersample, 3).mean(axis=(1, 3))
    return img


def save_png(path, img):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.imsave(path, np.clip(img, 0, 1))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("mesh")
    ap.add_argument("png")
    ap.add_argument("--up", default="auto", help="auto (detect_up's rule) or x|y|z|-x|-y|-z")
    ap.add_argument("--azim", type=float, default=30.0, help="degrees about the up axis")
    ap.add_argument("--elev", type=float, default=15.0, help="degrees above the horizon")
    ap.add_argument("--size", default="800x600", help="WIDTHxHEIGHT in pixels")
    ap.add_argument("--title", default="", help="drawn above the image (uses a matplotlib figure)")
    a = ap.parse_args()
    V, F, C = read_mesh(a.mesh)
    up = detect_up(V, F) if a.up == "auto" else parse_axis(a.up)
    width, height = (int(s) for s in a.size.split("x"))
    img = render(V, F, C, up=up, azim=a.azim, elev=a.elev, size=(width, height))
    if a.title:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig = plt.figure(figsize=(width / 100, height / 100 + 0.4), dpi=100)
        ax = fig.add_axes([0, 0, 1, height / (height + 40)])
        ax.imshow(img)
        ax.set_axis_off()
        fig.suptitle(a.title)
        fig.savefig(a.png)
    else:
        save_png(a.png, img)
    return 0


if __name__ == "__main__":
    sys.exit(main())
