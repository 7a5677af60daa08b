#!/usr/bin/env python3
"""Measures the local contraction (issue "Local contraction", items 1-3) and writes
lab/pages/local-contraction.md.

1. Locality: `run MESH -p 0 --regions R` (no global pressure, 200 frames, default strength; R:
   auto, bumpy_sphere's bumps file, and the face lists that `shellcontract regions` writes for the
   hand and bear with the thresholds of FACE_LISTS): the
   regions' mean inward displacement along the rest normal ("sink") against the mean displacement
   of the vertices outside the regions and their one-ring band ("rest"), both from the summary
   and as fractions of the bounding-box diagonal, and the new self-intersections (CGAL, at the end).
2. Depth: the same on bumpy_sphere over S; "centre sink / radius" is, per region, the inward
   displacement of its vertex farthest from its rim plane over the rim's mean radius (rest), the
   smallest over the regions.
3. With the global pressure on: default runs with `--regions auto` (and camel, and the face lists of
   section 1) against `--inward none` (the same regions measured, not contracted); 3b: the same
   with `--target-volume 0.9`.
4. What moves the locality of section 1: the hand (auto regions) and bear with its automatic
   regions below 5 % of the area (`--region-max-area 0.05`: the head region left out), `-p 0`, the
   default mechanism, one option changed at a time.

Every variant is run for both mechanisms (`--inward volume`, the default, and `--inward force`).

Usage: /usr/bin/python3 lab/scripts/local_contraction_table.py [--build build] [--out FILE]
Needs the paper's meshes (scripts/fetch_paper_meshes.sh); a mesh that is absent is skipped.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUMPY = os.path.join(ROOT, "meshes", "bumpy_sphere.off")
BUMPS = os.path.join(ROOT, "meshes", "bumpy_sphere.bumps.txt")


def read_off(path):
    tokens = " ".join(line.split("#")[0] for line in open(path)).split()
    i = 1 if tokens[0] == "OFF" else 0
    nv, nf = int(tokens[i]), int(tokens[i + 1])
    i += 3
    v = np.array(tokens[i:i + 3 * nv], float).reshape(nv, 3)
    i += 3 * nv
    faces = []
    for _ in range(nf):
        n = int(tokens[i])
        faces.append([int(x) for x in tokens[i + 1:i + 1 + n]])
        i += 1 + n
    return v, np.array(faces)


def run(exe, mesh, tmp, args):
    out, summary = os.path.join(tmp, "o.off"), os.path.join(tmp, "s.json")
    subprocess.run([exe, "run", mesh, "-o", out, "--summary", summary, "-q", "--validate", "end"] + args,
                   check=False, stderr=subprocess.DEVNULL)
    with open(summary) as f:
        s = json.load(f)
    return s, read_off(out)[0]


def ratio_text(on, off):
    """on / off; a region that rises without the contraction (off <= 0) and sinks with it is so marked."""
    if off > 1e-9:
        return "%.2fx" % (on / off)
    return "rises off, sinks on" if on > 0 else "-"


def centre_sink_over_radius(rest, faces, end, regions):
    """Smallest, over the regions, of the apex's inward displacement over the rim's mean radius."""
    normals = np.zeros_like(rest)
    for f in faces:
        normals[f] += np.cross(rest[f[1]] - rest[f[0]], rest[f[2]] - rest[f[0]])
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    worst = np.inf
    for region in regions:
        edges = {}
        for fi in region:
            f = faces[fi]
            for k in range(3):
                e = tuple(sorted((f[k], f[(k + 1) % 3])))
                edges[e] = edges.get(e, 0) + 1
        rim = sorted({v for e, n in edges.items() if n == 1 for v in e})
        verts = sorted({v for fi in region for v in faces[fi]})
        c = rest[rim].mean(0)
        axis = normals[verts].sum(0)
        axis /= np.linalg.norm(axis)
        apex = max(verts, key=lambda v: np.dot(rest[v] - c, axis))
        radius = np.linalg.norm(rest[rim] - c, axis=1).mean()
        worst = min(worst, -np.dot(end[apex] - rest[apex], normals[apex]) / radius)
    return worst


# Face lists chosen with `shellcontract regions` (docs/math/local-contraction.md, "Which regions"):
# the hand's regions grown a little, bear's without its head and tighter.
# The cap finder's defaults find the fingertips and bear's parts (docs/design/regions.md).
FACE_LISTS = [("hand", []), ("bear", [])]


def face_lists(exe, tmp):
    """(name, mesh path, face-list path, label) for each FACE_LISTS entry whose mesh is present."""
    out = []
    for name, thresholds in FACE_LISTS:
        path = os.path.join(ROOT, "data", "meshes", name + ".off")
        if not os.path.exists(path):
            continue
        listed = os.path.join(tmp, name + "_regions.txt")
        subprocess.run([exe, "regions", path, "-o", os.path.join(tmp, "r.ply"), "--face-list", listed] + thresholds,
                       check=True, stdout=subprocess.DEVNULL)
        out.append((name, path, listed, "face list (`regions %s`)" % " ".join(thresholds)))
    return out


SENSITIVITY = [("default", []), ("--region-shrink 0.5", ["--region-shrink", "0.5"]),
               ("--region-shrink 1", ["--region-shrink", "1"]), ("--k-b 0.001", ["--k-b", "0.001"]),
               ("--k-b 0.05", ["--k-b", "0.05"]), ("--bending none", ["--bending", "none"]),
               ("--iterations 20", ["--iterations", "20"]), ("--damping 0.5", ["--damping", "0.5"]),
               ("--collisions off", ["--collisions", "off"]), ("--frames 400", ["--frames", "400"])]


def sensitivity(exe, tmp):
    """Section 4: the locality of the hand and of bear's small regions over one option at a time."""
    subjects = []
    hand, bear = (os.path.join(ROOT, "data", "meshes", n + ".off") for n in ("hand", "bear"))
    if os.path.exists(hand):
        subjects.append(("hand", hand, []))
    if os.path.exists(bear):
        subjects.append(("bear, regions < 5 % of the area", bear, ["--region-max-area", "0.05"]))
    if not subjects:
        return []
    lines = ["", "## 4. What moves the locality: `-p 0`, one option changed at a time", "",
             "| option | " + " | ".join("%s: sink, rest, sink / rest" % n for n, _, _ in subjects) + " |",
             "|---|" + "---:|" * len(subjects)]
    for label, extra in SENSITIVITY:
        row = "| %s |" % label
        for _, path, select in subjects:
            s, _ = run(exe, path, tmp, ["-p", "0", "--regions", "auto"] + select + extra)
            sink, rest = s["region_inward_displacement"], s["outside_region_displacement"]
            row += " %.4f, %.5f, %.1fx |" % (sink, rest, sink / max(rest, 1e-12))
        lines.append(row)
        print(row, file=sys.stderr)
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "lab", "pages", "local-contraction.md"))
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    meshes = [("bumpy_sphere", BUMPY, BUMPS)] + [
        (n, os.path.join(ROOT, "data", "meshes", n + ".off"), "auto") for n in ("hand", "bear", "elk", "kitten")]
    meshes = [m for m in meshes if os.path.exists(m[1])]
    mechanisms = ("volume", "force")
    lines = ["# Local contraction: locality, depth, and with the global pressure", "",
             "Generated by `/usr/bin/python3 lab/scripts/local_contraction_table.py` (its docstring says what "
             "each column measures). Lengths are fractions of the bounding-box diagonal; 200 frames; "
             "collisions on; \"new SI\" = new self-intersecting face pairs at the end (CGAL).", ""]
    with tempfile.TemporaryDirectory() as tmp:
        lines += ["## 1. Locality: `-p 0 --regions R`, default strength (`--region-shrink 0.7`)", "",
                  "| mesh | regions | mechanism | sink | rest | sink / rest | V/V0 | new SI |",
                  "|---|---|---|---:|---:|---:|---:|---:|"]
        listed = face_lists(exe, tmp)
        subjects = [(n, p, r, "file" if r != "auto" else "auto") for n, p, r in meshes[:3]]
        subjects += [(n, p, r, label) for n, p, r, label in listed]
        for name, path, regions, label in subjects:
            for mech in mechanisms:
                s, _ = run(exe, path, tmp, ["-p", "0", "--regions", regions, "--inward", mech])
                sink, rest = s["region_inward_displacement"], s["outside_region_displacement"]
                lines.append("| %s | %s | %s | %.4f | %.4f | %.1fx | %.3f | %d |" % (
                    name, label, mech, sink, rest, sink / max(rest, 1e-12),
                    s["final_volume_ratio"], s.get("new_intersections", -1)))
            print(lines[-1], file=sys.stderr)
        lines += ["", "## 2. Depth: bumpy_sphere, `-p 0 --regions meshes/bumpy_sphere.bumps.txt`, over S", "",
                  "| mechanism | S | sink | rest | sink / rest | centre sink / radius (smallest region) | new SI |",
                  "|---|---:|---:|---:|---:|---:|---:|"]
        rest_x, faces = read_off(BUMPY)
        bumps = [[int(x) for x in line.split()] for line in open(BUMPS) if line.strip()]
        for mech in mechanisms:
            for shrink in (0.3, 0.5, 0.7, 1.0):
                s, end = run(exe, BUMPY, tmp, ["-p", "0", "--regions", BUMPS, "--inward", mech,
                                                "--region-shrink", str(shrink)])
                sink, rest = s["region_inward_displacement"], s["outside_region_displacement"]
                lines.append("| %s | %.1f | %.4f | %.4f | %.1fx | %.2f | %d |" % (
                    mech, shrink, sink, rest, sink / max(rest, 1e-12),
                    centre_sink_over_radius(rest_x, faces, end, bumps), s.get("new_intersections", -1)))
                print(lines[-1], file=sys.stderr)
        # Every mesh of the table where --regions auto finds regions, camel too, and the face lists.
        camel = os.path.join(ROOT, "data", "meshes", "camel.off")
        pressed = meshes + ([("camel", camel, "auto")] if os.path.exists(camel) else [])
        pressed += [(n + " (face list)", p, r) for n, p, r, _ in listed]
        lines += ["", "## 3. With the global pressure: default run, contraction on against off", "",
                  "`volume` is the default mechanism: each region's dimple and, under the global pressure, "
                  "the region load 2 S P on its faces (docs/math/local-contraction.md, section 5).", "",
                  "| mesh | regions | sink off (`--inward none`) | sink on, volume | ratio | sink on, force | ratio |",
                  "|---|---:|---:|---:|---:|---:|---:|"]
        for name, path, regions in pressed:
            off, _ = run(exe, path, tmp, ["--regions", regions, "--inward", "none"])
            row = "| %s | %d | %.4f |" % (name, off["regions"], off["region_inward_displacement"])
            for mech in mechanisms:
                on, _ = run(exe, path, tmp, ["--regions", regions, "--inward", mech])
                b = off["region_inward_displacement"]
                row += " %.4f | %s |" % (on["region_inward_displacement"],
                                        ratio_text(on["region_inward_displacement"], b))
            lines.append(row)
            print(row, file=sys.stderr)
        lines += ["", "## 3b. With a target volume: `--target-volume 0.9`, contraction on against off", "",
                  "| mesh | regions | sink off (`--inward none`) | sink on (volume) | ratio |",
                  "|---|---:|---:|---:|---:|"]
        for name, path, regions in pressed:
            off, _ = run(exe, path, tmp, ["--regions", regions, "--inward", "none", "--target-volume", "0.9"])
            on, _ = run(exe, path, tmp, ["--regions", regions, "--target-volume", "0.9"])
            b = off["region_inward_displacement"]
            lines.append("| %s | %d | %.4f | %.4f | %s |" % (
                name, off["regions"], b, on["region_inward_displacement"],
                ratio_text(on["region_inward_displacement"], b)))
            print(lines[-1], file=sys.stderr)
        lines += sensitivity(exe, tmp)
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote", a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
