#!/usr/bin/env python3
"""Measures issue 4's speed point: collision handling time per step against the constraint
solve's, on bear at strong pressure (P = 4, 300 frames), over repeated runs.

One run prints one ratio, and on a shared VM single runs scatter by 20-35% (docs/design/self-collision.md),
so this runs the job several times and reports the median, the range and how
many runs stay at or below 1. Each run is

    shellcontract run MESH -o OUT -q --pressure P --frames F --summary S.json

and its ratio is table2.collision_ms_per_step / table2.constraint_solve_ms_per_step. With
--compare OTHER_BUILD the runs alternate between the two builds (A B A B ...), so that both see
the same phases of the machine: use it to judge a change (e.g. a worktree of an older commit,
built with `cmake -B build -DCMAKE_BUILD_TYPE=Release`).

Usage: lab/scripts/collision_ratio.py [--build build] [--compare OTHER_BUILD] [--runs 15]
                                  [--pressure 4] [--frames 300] [--mesh data/meshes/bear.off]
                                  [--json OUT.json]
Exit code 0, or 2 for bad arguments (missing executable or mesh); a failed run stops the script
with its exit code.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

FIELDS = [  # (column, table2 key)
    ("collision ms", "collision_ms_per_step"),
    ("solve ms", "constraint_solve_ms_per_step"),
    ("background ms", "background_broad_phase_ms_per_step"),
    # the task's largest part (0 from builds before 2026-11-25, which do not report it)
    ("cell loop ms", "background_cell_loop_ms_per_step"),
    ("wait ms", "background_wait_ms_per_step"),
]


def run_once(exe, mesh, pressure, frames, tmp, tag):
    summary = os.path.join(tmp, tag + ".json")
    cmd = [exe, "run", mesh, "-o", os.path.join(tmp, tag + ".off"), "-q", "--pressure",
           str(pressure), "--frames", str(frames), "--summary", summary]
    done = subprocess.run(cmd)
    if done.returncode != 0:
        print("collision_ratio: '%s' failed with exit code %d" % (" ".join(cmd), done.returncode),
              file=sys.stderr)
        sys.exit(done.returncode)
    with open(summary) as f:
        t = json.load(f)["table2"]
    row = {key: t.get(key, 0.0) for _, key in FIELDS}
    solve = row["constraint_solve_ms_per_step"]
    row["ratio"] = row["collision_ms_per_step"] / solve if solve > 0 else float("inf")
    return row


def summarize(rows):
    ratios = [r["ratio"] for r in rows]
    out = {"runs": len(rows), "ratio_median": statistics.median(ratios), "ratio_min": min(ratios),
           "ratio_max": max(ratios), "runs_at_or_below_1": sum(r <= 1.0 for r in ratios)}
    for _, key in FIELDS:
        out[key + "_median"] = statistics.median(r[key] for r in rows)
    return out


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(root, "build"))
    ap.add_argument("--compare", default=None, help="a second build directory, run alternately")
    ap.add_argument("--runs", type=int, default=15, help="runs per build (default 15)")
    ap.add_argument("--pressure", type=float, default=4.0)
    ap.add_argument("--frames", type=int, default=300)
    ap.add_argument("--mesh", default=os.path.join(root, "data", "meshes", "bear.off"))
    ap.add_argument("--json", default=None, help="also write the runs and summaries here")
    args = ap.parse_args()
    builds = [("A", args.build)] + ([("B", args.compare)] if args.compare else [])
    for _, build in builds:
        exe = os.path.join(build, "shellcontract")
        if not os.access(exe, os.X_OK):
            print("collision_ratio: no executable %s (build first: README)" % exe, file=sys.stderr)
            return 2
    if not os.path.exists(args.mesh):
        print("collision_ratio: no mesh %s (scripts/fetch_paper_meshes.sh)" % args.mesh,
              file=sys.stderr)
        return 2
    if args.runs < 1:
        print("collision_ratio: --runs must be at least 1", file=sys.stderr)
        return 2

    rows = {tag: [] for tag, _ in builds}
    print("run build  ratio  " + "  ".join(name for name, _ in FIELDS), flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(args.runs):
            for tag, build in builds:
                r = run_once(os.path.join(build, "shellcontract"), args.mesh, args.pressure,
                             args.frames, tmp, tag)
                rows[tag].append(r)
                print("%3d %s  %.3f  " % (i + 1, tag, r["ratio"]) +
                      "  ".join("%.2f" % r[key] for _, key in FIELDS), flush=True)
    summaries = {}
    for tag, build in builds:
        s = summarize(rows[tag])
        summaries[tag] = s
        print("%s (%s): ratio median %.3f, min %.3f, max %.3f, %d of %d runs at or below 1; "
              "medians: %s" % (tag, build, s["ratio_median"], s["ratio_min"], s["ratio_max"],
                               s["runs_at_or_below_1"], s["runs"],
                               ", ".join("%s %.2f" % (name, s[key + "_median"])
                                         for name, key in FIELDS)))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"options": vars(args), "builds": dict(builds), "runs": rows,
                       "summary": summaries}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
