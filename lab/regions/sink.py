#!/usr/bin/python3
"""Issue "Regions a person would choose", item 2: does the local contraction on the automatic
regions work out of the box? Writes lab/regions/sink.md.

For each mesh (bear, hand, elk, kitten, bumpy_sphere):
  1. the regions `shellcontract regions MESH` finds (the same finder `run --regions auto` uses);
  2. `run MESH --regions auto -p 0`: per region the mean inward displacement of its vertices
     along the rest vertex normal ("sink"), as a fraction of the bounding-box diagonal; the rest
     = the mean displacement of the vertices outside the regions and their one-ring band (the
     summary's measure), as a fraction of the diagonal and of the smallest region sink; the new
     self-intersections (CGAL, at the end, from the summary);
  3. under the default pressure, `run MESH --regions auto` against the same with `--inward none`
     (regions measured, not contracted): the ratio of each region's sink, smallest over regions.
Pass: every region sinks >= 1 % of the diagonal, rest <= a tenth of the smallest sink, no new
intersection, ratio >= 2.

With --parts the regions are instead the labelled parts of lab/regions/labels.py's `parts_of`
(the faces whose centroid lies within r of P, each face to the first part that takes it; parts
named in --drop left out), written to a face list and run with `--regions FILE`: the local
contraction on the caps a person would circle, whatever the finder proposes.

With --face-list MESH=FILE (repeatable) the regions of MESH are the face list FILE (e.g. written
by `shellcontract regions MESH --face-list FILE --region-at X,Y,Z ...`); only those meshes run.

Usage: /usr/bin/python3 lab/regions/sink.py [--build build] [--meshes bear,hand,...] [--frames N]
       [--run-args "--dimple mirror"] [--parts [--drop "head"]] [--face-list MESH=FILE ...]
       [--title T] [--out FILE [--append]]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

MESHES = ["bear", "hand", "elk", "kitten", "bumpy_sphere"]


def run(exe, mesh, tmp, args):
    out, summary = os.path.join(tmp, "o.off"), os.path.join(tmp, "s.json")
    for p in (out, summary):
        if os.path.exists(p):
            os.remove(p)
    subprocess.run([exe, "run", mesh, "-o", out, "--summary", summary, "-q", "--validate", "end"] + args,
                   check=False, stderr=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
    with open(summary) as f:
        s = json.load(f)
    return s, common.read_off(out)[0]


def per_region_sink(rest, faces, end, regions):
    n = common.rest_normals(rest, faces)
    return [float(np.mean(-np.einsum("ij,ij->i", end[vs] - rest[vs], n[vs])))
            for vs in (sorted({int(v) for fi in r for v in faces[fi]}) for r in regions)]


def rest_motion(rest, faces, end, regions):
    in_region = np.zeros(len(rest), bool)
    for r in regions:
        in_region[faces[r].ravel()] = True
    band = in_region.copy()
    touching = in_region[faces].any(axis=1)
    band[faces[touching].ravel()] = True
    d = np.linalg.norm(end - rest, axis=1)[~band]
    return float(d.mean()) if len(d) else 0.0, float(np.percentile(d, 95)) if len(d) else 0.0


def part_regions(name, rest, faces, drop):
    """Face lists of the labelled parts of `name` (labels.parts_of), or None without labels."""
    import labels  # noqa: E402 (read only: the labelled set is lab/regions/labels.py's)
    parts = labels.parts_of(name, rest)
    if parts is None:
        return None
    cent = common.face_centroids(rest, faces)
    taken = np.zeros(len(faces), bool)
    out = []
    for part, p, r in parts:
        mask = (np.linalg.norm(cent - p, axis=1) <= r) & ~taken
        taken |= mask
        if part not in drop and mask.any():
            out.append([int(i) for i in np.flatnonzero(mask)])
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--meshes", default=",".join(MESHES))
    ap.add_argument("--frames", type=int, default=0, help="0 = the tool's default")
    ap.add_argument("--run-args", default="", help="more options for every run, e.g. '--dimple mirror'")
    ap.add_argument("--parts", action="store_true", help="sink the labelled parts (labels.py), not the finder's")
    ap.add_argument("--drop", default="", help="with --parts: comma-separated part names to leave out")
    ap.add_argument("--face-list", action="append", default=[], help="MESH=FILE: sink FILE's regions on MESH")
    ap.add_argument("--title", default="", help="the section's title (default: the run options)")
    ap.add_argument("--append", action="store_true", help="add a section to --out instead of rewriting it")
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "sink.md"))
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    frames = (["--frames", str(a.frames)] if a.frames else []) + a.run_args.split()
    given = dict(item.split("=", 1) for item in a.face_list)
    if given:
        a.meshes = ",".join(given)
    rows = ["| mesh | regions | smallest sink / diag | largest sink / diag | rest / diag (mean, 95 %) | "
            "rest / smallest sink | new intersections | default -p: smallest sink ratio on/off | pass |",
            "|---|---|---|---|---|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as tmp:
        for name, path, rest, faces, diag in common.each_mesh(a.meshes.split(",")):
            if name in given:
                source = os.path.abspath(given[name])
                regions = common.read_face_list(source)
            elif a.parts:
                regions = part_regions(name, rest, faces, set(filter(None, a.drop.split(","))))
                if regions is None:
                    print(f"{name}: no labelled parts, skipped", file=sys.stderr)
                    continue
                source = os.path.join(tmp, name + "_parts.txt")
                with open(source, "w") as fo:
                    fo.write("".join(" ".join(map(str, r)) + "\n" for r in regions))
            else:
                regions, _, _ = common.auto_regions(exe, path, tmp)
                source = "auto"
            if not regions:
                rows.append(f"| {name} | 0 | - | - | - | - | - | - | no |")
                continue
            s0, end0 = run(exe, path, tmp, ["--regions", source, "-p", "0"] + frames)
            sink = per_region_sink(rest, faces, end0, regions)
            rest_mean, rest95 = rest_motion(rest, faces, end0, regions)
            s_on, end_on = run(exe, path, tmp, ["--regions", source] + frames)
            s_off, end_off = run(exe, path, tmp, ["--regions", source, "--inward", "none"] + frames)
            on = per_region_sink(rest, faces, end_on, regions)
            off = per_region_sink(rest, faces, end_off, regions)
            ratios = [o / f if f > 1e-12 else np.inf for o, f in zip(on, off)]
            lo = min(sink)
            ok = (lo >= 0.01 * diag and rest_mean <= 0.1 * lo and s0.get("new_intersections", 1) == 0
                  and min(ratios) >= 2.0)
            rows.append(f"| {name} | {len(regions)} | {lo / diag:.4f} | {max(sink) / diag:.4f} | "
                        f"{rest_mean / diag:.5f}, {rest95 / diag:.5f} | {rest_mean / lo if lo > 0 else np.inf:.3f} | "
                        f"{s0.get('new_intersections')} (on/off runs: {s_on.get('new_intersections')}/"
                        f"{s_off.get('new_intersections')}) | {min(ratios):.2f} | {'yes' if ok else 'no'} |")
            print(rows[-1], flush=True)
    what = "FILE" if given else "the labelled parts" if a.parts else "auto"
    title = a.title or (f"`run MESH --regions {what}` " + " ".join(frames)).strip()
    commit = subprocess.run(["git", "-C", common.ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip() or "unknown"
    command = " ".join(["lab/regions/sink.py"] + [f"'{x}'" if " " in x else x for x in sys.argv[1:]])
    section = f"## {title}\n\n`{command}`, code at commit {commit}.\n\n" + "\n".join(rows) + "\n"
    if a.append and os.path.exists(a.out):
        with open(a.out) as f:
            text = f.read().rstrip("\n") + "\n\n" + section
    else:
        text = ("# Local contraction on the automatic regions\n\n"
                "Generated by `lab/regions/sink.py` (its docstring has the measures; one section per "
                "call, `--append`). Sink: mean inward displacement of a region's vertices along the "
                "rest normal; rest: mean displacement of the vertices outside the regions and their "
                "one-ring band; both / the bounding-box diagonal.\n\n" + section)
    with open(a.out, "w") as f:
        f.write(text)
    print(section)


if __name__ == "__main__":
    main()
