#!/usr/bin/env python3
"""Why the broad phase's candidate pairs per face grow with the resolution (issue "Large meshes and
many cores", its linear-cost point). Runs bear and bear subdivided (scale_benchmark.py's meshes) for
a few frames in the coloured order, keeps the last two frames, and counts with
build/lab/benchmarks/pair_growth the candidate pairs per face of that last step:
  - with the step's swept boxes (k = 1: what the broad phase finds);
  - as the union over k sub-intervals of the step (what a broad phase that slices each step into k
    parts would find, before any response moves a vertex);
  - with no motion at all (the last frame against itself), with and without the inflation;
once under the default options and once with the contact distance (--delta) in proportion to the
mean edge length (bear's ratio). Writes lab/pages/pair-growth.md (or --out).

Usage: lab/scripts/pair_growth.py [--build build] [--frames 10] [--levels 0,1,2] [--out FILE]
Needs: the built tool and build/lab/benchmarks/pair_growth, data/meshes/bear.off."""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "lab", "scripts"))
from scale_benchmark import read_off, subdivide, write_off  # noqa: E402

SLICES = [1, 2, 4, 8]
DEFAULT_DELTA = 1e-4  # the tool's --delta default (CollisionOptions::delta)


def measure(tool, counter, mesh, frames, delta, tmp):
    """Runs MESH for FRAMES frames (with --delta DELTA unless None) and counts the last step's
    pairs per face."""
    name = os.path.splitext(os.path.basename(mesh))[0]
    tag = name + ("" if delta is None else f"_delta{delta:g}")
    out_dir = os.path.join(tmp, tag)
    os.makedirs(out_dir)
    summary = os.path.join(tmp, tag + ".json")
    extra = [] if delta is None else ["--delta", repr(delta)]
    cmd = [tool, "run", mesh, "-o", os.path.join(out_dir, "f.off"), "--frames", str(frames),
           "--order", "coloured", "--export-every", "1", "--export-dir", out_dir,
           "--summary", summary, "-q"] + extra
    subprocess.run(cmd, check=True)
    # The frame numbers are zero-padded to the width of the last one.
    kept = sorted(n for n in os.listdir(out_dir) if n.startswith("f_"))
    last = [os.path.join(out_dir, n) for n in kept[-2:]]
    out = subprocess.run([counter] + extra + [mesh] + last + [str(k) for k in SLICES],
                         check=True, capture_output=True, text=True).stdout
    counts = json.loads(out)
    s = json.load(open(summary))
    counts["run_mean"] = s["table2"]["pairs_after_broad_phase_per_step"] / s["faces"]
    counts["name"] = name.replace("_", " ")
    print(tag, counts, flush=True)
    return counts


def table(rows):
    lines = [
        "| mesh | faces | inflation | run | k = 1 | k = 2 | k = 4 | k = 8 | no motion | no motion, "
        "no inflation |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(f"| {r['name']} | {r['faces']} | {r['inflation']:g} | {r['run_mean']:.2f} | "
                     + " | ".join(f"{r[f'k{k}']:.2f}" for k in SLICES)
                     + f" | {r['static']:.2f} | {r['static_no_inflation']:.2f} |")
    first, last = rows[0], rows[-1]
    if len(rows) > 1:
        lines += [
            "",
            f"{last['name']} over {first['name']}, per face: "
            f"run: {last['run_mean'] / first['run_mean']:.2f}x, "
            + ", ".join(f"k = {k}: {last[f'k{k}'] / first[f'k{k}']:.2f}x" for k in SLICES)
            + f"; no motion: {last['static'] / first['static']:.2f}x.",
        ]
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--frames", type=int, default=10)
    ap.add_argument("--levels", default="0,1,2")
    ap.add_argument("--out", default=os.path.join(ROOT, "lab", "pages", "pair-growth.md"))
    a = ap.parse_args()
    if a.frames < 1:
        sys.exit("--frames must be at least 1")
    tool = os.path.join(a.build, "shellcontract")
    counter = os.path.join(a.build, "lab", "benchmarks", "pair_growth")
    for path in (tool, counter):
        if not os.path.exists(path):
            sys.exit(f"{path} not found: build the project first (scripts/build_and_test.sh)")
    levels = [int(v) for v in a.levels.split(",")]
    fixed, scaled = [], []
    with tempfile.TemporaryDirectory() as tmp:
        points, faces = read_off(os.path.join(ROOT, "data", "meshes", "bear.off"))
        for level in range(max(levels) + 1):
            if level in levels:
                name = f"bear_x{4 ** level}"
                mesh = os.path.join(tmp, name + ".off")
                write_off(mesh, points, faces)
                fixed.append(measure(tool, counter, mesh, a.frames, None, tmp))
                # Each subdivision halves every edge: DEFAULT_DELTA / 2^level keeps bear's ratio
                # of the contact distance to the mean edge length.
                if level > 0:
                    scaled.append(measure(tool, counter, mesh, a.frames,
                                          DEFAULT_DELTA / 2 ** level, tmp))
                else:
                    scaled.append(fixed[-1])
            points, faces = subdivide(points, faces)
    lines = [
        "# Candidate pairs per face: bear and bear subdivided",
        "",
        f"`/usr/bin/python3 lab/scripts/pair_growth.py --frames {a.frames} --levels {a.levels}` "
        "(writes this page). Each mesh runs "
        f"{a.frames} frames in the coloured order (`shellcontract run MESH "
        f"--frames {a.frames} --order coloured --export-every 1`); `build/lab/benchmarks/pair_growth` "
        "then counts the candidate pairs (vertex-face and edge-edge, adjacent ones left out) "
        "of the "
        f"step from frame {a.frames - 1} to frame {a.frames}, per face, with the boxes inflated by "
        "the collision step's inflation (`broad_phase_inflation`: "
        "(delta + region_margin delta) / 2 and a rounding margin, 2.5 delta).",
        "",
        "- **run**: the run's own mean over its steps (the summary's "
        "`pairs_after_broad_phase_per_step`);",
        "- **k = 1**: the step's swept boxes (what the broad phase finds at that step);",
        "- **k = 2, 4, 8**: the union of the pairs of k sub-intervals' swept boxes, what a broad "
        "phase that sliced the step would find before any response moved a vertex;",
        "- **no motion**: the last frame against itself, with the inflation and without it.",
        "",
        f"## The default options (`--delta` {DEFAULT_DELTA:g}: a fixed share of the diagonal)",
        "",
    ]
    lines += table(fixed)
    lines += [
        "",
        "## The contact distance in proportion to the edge length",
        "",
        f"The same, each mesh run with `--delta` {DEFAULT_DELTA:g} / 2^level (bear x4: "
        f"{DEFAULT_DELTA / 2:g}, bear x16: {DEFAULT_DELTA / 4:g}), which keeps bear's ratio of the "
        "contact distance to the mean edge length (each subdivision halves every edge).",
        "",
    ]
    lines += table(scaled)
    with open(a.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
