#!/usr/bin/python3
"""Wrinkle wavelength, relief and silhouette of a contracted shell (issue #24, item 6).

Item 6 asks that the wrinkle size come from the material, not from the mesh: at V/V0 0.7 the
default run's dominant wrinkle wavelength must agree within 25 % on bear and on bear subdivided
once (bear x4), and the silhouette must stay recognisable. This script makes bear x4, runs the
default command to V/V0 0.7 on both, and measures on each result:

* The relief h: for every vertex, its signed offset along the local normal from a quadric
  fitted by weighted least squares to its neighbourhood (moving least squares). The
  neighbourhood is a fixed physical radius: Gaussian weights exp(-d^2 / 2 sigma^2) times the
  rest vertex area, d the REST distance (in units of the rest bounding-box diagonal D), cut at
  2.5 sigma, and only neighbours whose rest normal agrees with the vertex's (n0_i . n0_j > 0).
  Rest distances and rest normals keep the front and back sheets of a flattened result apart;
  a quadric, not a plain average, so curvature of the large shape leaves no offset.
  Nothing in it counts vertices or Laplacian iterations, so the filter is the same on any
  resolution of the same surface.
* The isotropic autocorrelation C(r) = <h_i h_j> / sqrt(<h_i^2> <h_j^2>) over the vertex pairs
  of each bin (normalised per bin: see autocorrelation()), pairs binned by their
  distance r in the RESULT (Euclidean), pairs with disagreeing rest normals left out, each pair
  weighted by the rest vertex areas (anchors drawn with probability proportional to area,
  partners weighted by area), so vertex density does not bias it.
* Two wavelengths from C, both through J0 = the C(r) of a wave pattern of wavelength L on a
  surface, averaged over directions (parallel folds or a random pattern with that wavelength):
  L_zero = 2 pi r0 / 2.4048, r0 the first zero crossing of C (J0's first zero is at 0.383 L),
  and L_half = 2 pi r_half / 1.5211, r_half where C first falls to 1/2. Not "2 x the first
  zero": that holds for neither a 1D cosine (4 x) nor J0 (2.61 x). L_zero is the wavelength when
  C oscillates; when it decays without oscillating (roughness with no one wavelength), r0 is
  where C wanders about zero and noise decides it, and L_half (the correlation length, in the
  units of a wavelength) is the size that stays defined. Linear interpolation between bins; a
  crossing below ~1.5 mean edges is at the mesh's resolution limit (the self-test shows -8 %
  for L_half at 4.3 edges). The first minimum of C (J0's at 0.610 L) was tried and dropped:
  the quadric filter bends C beyond its zero (-30 % on the self-test's L = 0.03 D).
* The RMS relief sqrt(<h^2>) / D.
* The silhouette, seen along -z (the issue's picture: the bear lies in the x-y plane, head and
  ears toward +y; looking down -y one sees only the top of the head): input and result are
  rasterised as binary masks in one frame; the result's mask is scaled about its centroid to the
  input's area and its centroid moved onto the input's, so uniform shrinking and drift do not
  count; IoU of the whole mask, and of the rows of the input's top 25 % along y (head and ears)
  and top 10 % (the ears).

Usage:
  lab/scripts/wrinkle_wavelength.py --self-test [--sigmas 0.01,0.025]
  lab/scripts/wrinkle_wavelength.py [--exe build/shellcontract] [--out DIR] [--k-b 0.01,0.001,0.1]
                                [--sigmas 0.01,0.025] [--png docs/images/wrinkles_bear_vs_bear4.png]
                                [--load "--target-volume 0.7 --frames 200"] [--k-b material]
Prints markdown tables: the runs with their silhouette numbers, the wavelengths, their ratios.
Each run is the default command with --stop-volume-ratio 0.7 --validate end (and --k-b); --load
replaces "--stop-volume-ratio 0.7" by other options that take the shell to V/V0 0.7 (a target
volume: a deflation at a controlled rate instead of the default pressure's crush); --k-b material
passes no --k-b, so that with --solver xpbd --young --thickness in --load k_B is the material's.
"""
import argparse
import json
import os
import shlex
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
from render_mesh import rasterize, read_mesh, render, save_png  # noqa: E402
from scale_benchmark import read_off, subdivide, write_off  # noqa: E402

J01 = 2.404825557695773   # first zero of J0
J0_HALF = 1.5210931       # J0(x) = 0.5
SIGMA = 0.025             # smoothing radius / D: above both meshes' edges (0.0088 D, 0.0044 D)


# ----------------------------------------------------------------------------- geometry

def vertex_area_normals(V, F):
    """(lumped vertex areas, vertex area vectors): a third of each face's area / area vector."""
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]) / 2
    a = np.linalg.norm(n, axis=1)
    area = np.zeros(len(V))
    vec = np.zeros((len(V), 3))
    for k in range(3):
        np.add.at(area, F[:, k], a / 3)
        np.add.at(vec, F[:, k], n / 3)
    return area, vec


def unit(v):
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-300)


def neighbour_blocks(P, queries, radius):
    """Yields (q, j, d): query ids q (k), candidate ids j (m) and their k x m distances, for the
    queries grouped by a grid of cell side `radius` (every pair closer than radius is among them)."""
    cell = np.floor((P - P.min(axis=0)) / radius).astype(np.int64)
    key = (cell[:, 0] * 1_000_003 + cell[:, 1]) * 1_000_003 + cell[:, 2]
    order = np.argsort(key, kind="stable")
    skey = key[order]
    uniq, start = np.unique(skey, return_index=True)
    end = np.r_[start[1:], len(skey)]
    where = {int(u): (s, e) for u, s, e in zip(uniq, start, end)}
    qkey = key[queries]
    for u in np.unique(qkey):
        q = queries[qkey == u]
        c = cell[q[0]]
        parts = []
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    k = ((c[0] + dx) * 1_000_003 + c[1] + dy) * 1_000_003 + c[2] + dz
                    if int(k) in where:
                        s, e = where[int(k)]
                        parts.append(order[s:e])
        j = np.concatenate(parts)
        d = np.linalg.norm(P[q][:, None, :] - P[j][None, :, :], axis=2)
        yield q, j, d


def relief(X0, X, F, sigma):
    """Signed normal offset h of each vertex of X from the weighted quadric through its rest
    neighbourhood (module docstring). X0, X in units of D. Returns (h, rest vertex areas)."""
    a0, n0 = vertex_area_normals(X0, F)
    _, nx = vertex_area_normals(X, F)
    n0 = unit(n0)
    h = np.zeros(len(X))
    rc = 2.5 * sigma
    for q, j, d in neighbour_blocks(X0, np.arange(len(X0)), rc):
        w = a0[j][None, :] * np.exp(-0.5 * (d / sigma) ** 2)
        w *= (d < rc) & (n0[q] @ n0[j].T > 0)
        nbar = unit(w @ nx[j])                                   # k x 3 smoothed normal
        t1 = unit(np.cross(nbar, np.where(np.abs(nbar[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])))
        t2 = np.cross(nbar, t1)
        c = (w @ X[j]) / w.sum(axis=1, keepdims=True)            # local origin: weighted centroid
        R = X[j][None, :, :] - c[:, None, :]                     # k x m x 3
        u, v, z = (np.einsum("kmc,kc->km", R, t) for t in (t1, t2, nbar))
        phi = np.stack([np.ones_like(u), u, v, u * u, u * v, v * v], axis=2)  # k x m x 6
        M = np.einsum("km,kma,kmb->kab", w, phi, phi) + 1e-14 * np.eye(6)
        b = np.einsum("km,kma,km->ka", w, phi, z)
        beta = np.linalg.solve(M, b[..., None])[..., 0]
        ri = X[q] - c
        ui, vi, zi = (np.einsum("kc,kc->k", ri, t) for t in (t1, t2, nbar))
        fit = (beta * np.stack(
            [np.ones_like(ui), ui, vi, ui * ui, ui * vi, vi * vi], axis=1)).sum(axis=1)
        h[q] = zi - fit
    return h, a0, n0


def autocorrelation(X, h, area, n0, rmax=0.1, dr=0.001, anchors=4000, seed=1):
    """C(r) on bins of width dr up to rmax (module docstring); returns (bin centres, C, counts).
    Each bin is normalised by its own pairs, C = sum w h_i h_j / sqrt(sum w h_i^2 sum w h_j^2),
    not by the global <h^2>: the relief is not stationary (crinkled parts are both rougher and
    more compressed, so they own most of the short pairs), and a global normalisation then
    reads C(r) > 1 at short r. C(0) = 1 (the i = i term) is prepended at r = 0."""
    h = h - (area * h).sum() / area.sum()
    rng = np.random.default_rng(seed)
    q = np.sort(rng.choice(len(X), size=min(anchors, len(X)), replace=False, p=area / area.sum()))
    nb = int(round(rmax / dr))
    num, sii, sjj = np.zeros(nb), np.zeros(nb), np.zeros(nb)
    cnt = np.zeros(nb, np.int64)
    for qq, j, d in neighbour_blocks(X, q, rmax):
        ok = (d < rmax) & (d > 0) & (n0[qq] @ n0[j].T > 0)
        k, m = np.nonzero(ok)
        b = (d[k, m] / dr).astype(int)
        w = area[j[m]]
        hi, hj = h[qq[k]], h[j[m]]
        num += np.bincount(b, weights=w * hi * hj, minlength=nb)
        sii += np.bincount(b, weights=w * hi * hi, minlength=nb)
        sjj += np.bincount(b, weights=w * hj * hj, minlength=nb)
        cnt += np.bincount(b, minlength=nb)
    r = (np.arange(nb) + 0.5) * dr
    # On a surface the pair count of a bin grows like r. Bins far below that (below the
    # nearest-neighbour distance, or in the gaps of a regular mesh's distance lattice) hold a
    # few pairs of one kind and read wild values (0.01 where its neighbours read 0.7 on the
    # self-test's icosphere), so a bin is kept only with a quarter of the typical count per r.
    density = np.median(cnt[r > 0.5 * rmax] / r[r > 0.5 * rmax])
    keep = (cnt >= 50) & (cnt >= 0.25 * density * r)
    C = np.r_[1.0, num[keep] / np.sqrt(sii[keep] * sjj[keep])]
    return np.r_[0.0, r[keep]], C, np.r_[0, cnt[keep]]


def wavelength(r, C):
    """(L_half, L_zero): the wavelength of the J0 that has C's half-value distance, 2 pi r_half /
    1.5211, and the one that has C's first zero, 2 pi r0 / j01 (nan if C stays positive). For a
    wave pattern both give L; on a rough surface with no single wavelength C decays without
    oscillating, its first zero sits where C is at noise level and is decided by noise, while
    L_half stays a well-defined size (the correlation length, in the units of a wavelength)."""
    def crossing(level):
        i = np.nonzero(C < level)[0]
        if not len(i):
            return float("nan")
        i = i[0]
        return r[i - 1] + (r[i] - r[i - 1]) * (C[i - 1] - level) / (C[i - 1] - C[i])
    return 2 * np.pi * crossing(0.5) / J0_HALF, 2 * np.pi * crossing(0.0) / J01


def measure(V0, V, F, sigma=SIGMA):
    """Wavelengths and RMS relief of result V over rest V0, in units of the rest diagonal."""
    D = np.linalg.norm(V0.max(axis=0) - V0.min(axis=0))
    h, area, n0 = relief(V0 / D, V / D, F, sigma)
    r, C, _ = autocorrelation(V / D, h, area, n0)
    rms = np.sqrt((area * h * h).sum() / area.sum())
    half, zero = wavelength(r, C)
    return {"half": half, "zero": zero, "rms": rms, "r": r, "C": C}


# ----------------------------------------------------------------------------- silhouette

def silhouette(V0, V, F0, F, px=600):
    """IoUs of the result's mask (seen along -z, scaled to the input's area about its centroid
    and moved onto the input's centroid) with the input's mask: whole, top 25 % rows, top 10 %."""
    lo, hi = V0[:, :2].min(axis=0), V0[:, :2].max(axis=0)
    s = 0.8 * px / (hi - lo).max()

    def mask(P2, Fm):
        P = np.column_stack([px / 2 + s * (P2[:, 0] - (lo[0] + hi[0]) / 2),
                             px / 2 - s * (P2[:, 1] - (lo[1] + hi[1]) / 2), np.zeros(len(P2))])
        return rasterize(P, Fm, np.zeros((len(Fm), 3)), px, px)[1]

    m0 = mask(V0[:, :2], F0)
    m1 = mask(V[:, :2], F)
    yy, xx = np.nonzero(m0)
    c0 = np.array([xx.mean(), yy.mean()])
    y1, x1 = np.nonzero(m1)
    c1 = np.array([x1.mean(), y1.mean()])
    k = np.sqrt(m0.sum() / m1.sum())
    # Map the result's 2D points so that its mask centroid goes to c0 and its area to m0's.
    P2 = V[:, :2].copy()
    pix = np.column_stack([px / 2 + s * (P2[:, 0] - (lo[0] + hi[0]) / 2),
                           px / 2 - s * (P2[:, 1] - (lo[1] + hi[1]) / 2)])
    pix = c0 + k * (pix - c1)
    m2 = rasterize(np.column_stack([pix, np.zeros(len(pix))]), F, np.zeros((len(F), 3)),
                   px, px)[1]

    def iou(rows):
        a, b = m0[rows], m2[rows]
        return (a & b).sum() / (a | b).sum()

    top, bottom = yy.min(), yy.max()   # image rows grow downward: top = head
    out = {"iou": iou(slice(None)),
           "iou_top25": iou(slice(top, top + int(0.25 * (bottom - top)) + 1)),
           "iou_top10": iou(slice(top, top + int(0.10 * (bottom - top)) + 1)),
           "area_ratio": m1.sum() / m0.sum()}
    return out


# ----------------------------------------------------------------------------- self-test

def icosphere(level):
    t = (1 + 5 ** 0.5) / 2
    P = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
         (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    Fl = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
          (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
          (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        P, Fl = subdivide(P, Fl)
    V = unit(np.array(P, float))
    return V, np.array(Fl)


def legendre(l, x):
    p0, p1 = np.ones_like(x), x
    for n in range(1, l):
        p0, p1 = p1, ((2 * n + 1) * x * p1 - n * p0) / (n + 1)
    return p1


def self_test(sigmas):
    """Unit spheres carrying a random field of spherical-harmonic degree l (a sum of 300 zonal
    harmonics P_l(x . u_m) about random axes u_m, Gaussian coefficients: isotropic in
    expectation, C(gamma) = P_l(cos gamma)); its wavelength is 2 pi / sqrt(l (l + 1)) (Jeans).
    Displaced along the normal with RMS 0.2 % of the radius, on icospheres of 20,480 and
    81,920 faces (edges 0.0069 D and 0.0035 D, close to bear's and bear x4's)."""
    rng = np.random.default_rng(7)
    D = 2 * np.sqrt(3)
    spheres = {level: icosphere(level) for level in (5, 6)}
    print("| field | expected L/D | sigma/D | faces | L_half/D | error | L_zero/D | error "
          "| RMS/D (expected 0.000577) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for lam in (0.03, 0.06):
        l = int(round(np.sqrt((2 * np.pi / (lam * D)) ** 2 + 0.25) - 0.5))
        expected = 2 * np.pi / np.sqrt(l * (l + 1)) / D
        axes = unit(rng.normal(size=(300, 3)))
        coef = rng.normal(size=300)
        for sigma in sigmas:
            for level, (V, F) in spheres.items():
                field = sum(c * legendre(l, V @ u) for c, u in zip(coef, axes))
                field *= 0.002 / np.sqrt((field ** 2).mean())
                m = measure(V, V * (1 + field)[:, None], F, sigma)
                print(f"| degree {l} | {expected:.4f} | {sigma} | {len(F)} | {m['half']:.4f} "
                      f"| {100 * (m['half'] / expected - 1):+.1f} % | {m['zero']:.4f} "
                      f"| {100 * (m['zero'] / expected - 1):+.1f} % | {m['rms']:.6f} |",
                      flush=True)


# ----------------------------------------------------------------------------- runs

def make_bear4(path):
    P, Fl = read_off(os.path.join(ROOT, "data/meshes/bear.off"))
    P, Fl = subdivide(P, Fl)
    write_off(path, P, Fl)


def run(exe, mesh, out, load, extra):
    summary = out[:-4] + ".json"
    cmd = ([exe, "run", mesh, "-o", out, "--summary", summary, "-q"] + load + ["--validate", "end"]
           + extra)
    rc = subprocess.run(cmd).returncode
    with open(summary) as f:
        s = json.load(f)
    return rc, s


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("--self-test", action="store_true", help="check the wavelength measure on "
                    "spheres carrying fields of known wavelength, then exit")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build/shellcontract"))
    ap.add_argument("--out", default="/tmp/wrinkles", help="folder for meshes and summaries")
    ap.add_argument("--k-b", default="0.01",
                    help="comma-separated --k-b values to run; 'material': no --k-b (with "
                    "--solver xpbd --young --thickness in --load, k_B then comes from the material)")
    ap.add_argument("--sigmas", default="0.01,0.025", help="comma-separated smoothing radii / D")
    ap.add_argument("--load", default="--stop-volume-ratio 0.7",
                    help="run options that take the shell to V/V0 0.7 (default: the default run, "
                    "stopped there)")
    ap.add_argument("--png", default="", help="write the top-view renders (input, bear, bear x4 "
                    "at 0.7; first --k-b value) side by side here")
    a = ap.parse_args()
    sigmas = [float(x) for x in a.sigmas.split(",")]
    if a.self_test:
        self_test(sigmas)
        return 0
    os.makedirs(a.out, exist_ok=True)
    bear = os.path.join(ROOT, "data/meshes/bear.off")
    bear4 = os.path.join(a.out, "bear4.off")
    if not os.path.exists(bear4):
        make_bear4(bear4)
    runs, waves, renders = [], [], {}
    for kb in a.k_b.split(","):
        for name, mesh in (("bear", bear), ("bear x4", bear4)):
            out = os.path.join(a.out, f"{name.replace(' ', '')}_kb{kb}.off")
            k_b = [] if kb == "material" else ["--k-b", kb]
            rc, s = run(a.exe, mesh, out, shlex.split(a.load), k_b)
            V0, F, _ = read_mesh(mesh)
            V, F1, _ = read_mesh(out)
            assert len(V) == len(V0) and (F1 == F).all(), "output must keep the input's order"
            D = np.linalg.norm(V0.max(axis=0) - V0.min(axis=0))
            edge = np.linalg.norm(V0[F] - V0[np.roll(F, 1, axis=1)], axis=2).mean() / D
            sil = silhouette(V0, V, F, F)
            runs.append(f"| {name} | {kb} | {len(F)} | {rc} | {s['frames_run']} "
                        f"| {s['final_volume_ratio']:.3f} | {s.get('new_intersections', 'n/a')} "
                        f"| {sil['area_ratio']:.3f} | {sil['iou']:.3f} | {sil['iou_top25']:.3f} "
                        f"| {sil['iou_top10']:.3f} |")
            print(runs[-1], flush=True)
            for sigma in sigmas:
                m = measure(V0, V, F, sigma)
                waves.append((name, kb, sigma, edge, m))
                print(f"  sigma {sigma}: L_half/D {m['half']:.4f} L_zero/D {m['zero']:.4f} "
                      f"RMS/D {m['rms']:.5f}", flush=True)
            if kb == a.k_b.split(",")[0]:
                renders.setdefault("input", (V0, F, V0))
                renders[name] = (V, F, V0)
    print(f"\nrun options: {a.load} --validate end --k-b K_B")
    frames = "frames to 0.7" if a.load == ap.get_default("load") else "frames run"
    print(f"\n| mesh | k_B | faces | exit | {frames} | V/V0 | new self-intersections "
          "| mask area / input's | IoU | IoU top 25 % | IoU top 10 % |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    print("\n".join(runs))
    print("\n| mesh | k_B | sigma/D | L_half/D | L_half / mean edge | L_zero/D | relief RMS/D |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, kb, sigma, edge, m in waves:
        print(f"| {name} | {kb} | {sigma} | {m['half']:.4f} | {m['half'] / edge:.2f} "
              f"| {m['zero']:.4f} | {m['rms']:.5f} |")
    print("\n| k_B | sigma/D | L_half: bear x4 / bear | L_zero: bear x4 / bear |")
    print("|---:|---:|---:|---:|")
    for w in waves:
        for v in waves:
            if w[0] == "bear" and v[0] == "bear x4" and w[1:3] == v[1:3]:
                print(f"| {w[1]} | {w[2]} | {v[4]['half'] / w[4]['half']:.3f} "
                      f"| {v[4]['zero'] / w[4]['zero']:.3f} |")
    if a.png:
        # Seen from -z (azim 90 about +y), the issue's view: head and ears at the top.
        imgs = [render(V, Fm, up=np.array([0, 1.0, 0]), azim=90, elev=0, size=(600, 640), fit=fit)
                for V, Fm, fit in renders.values()]
        save_png(a.png, np.concatenate(imgs, axis=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
