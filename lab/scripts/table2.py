#!/usr/bin/env python3
"""Reproduces the paper's Table 2 (collision detection cost) with our pipeline.

For each of the paper's meshes (data/meshes, see scripts/fetch_paper_meshes.sh) it runs
`shellcontract run` with collision handling on and prints, per time step: the VF + EE pairs
without culling (what Bridson's method solves a cubic for), after the broad phase, after the
non-penetration filter, the narrow-phase queries, those left for the cubic's root isolation
after the separating-axis test, and the time of each stage; plus the whole run's collision
time beside the paper's. "broad ms" is what the step's own thread spends on the broad phase;
in parentheses the speculative broad phase's task on the spare thread during the solve.

Usage: lab/scripts/table2.py [--build build] [--frames 200] [--pressure P] [meshes...]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

# Paper's Table 2: (cubic solves without culling, their time s, the paper's CCD time s).
PAPER = {"elk": (2.69e9, 10256.66, 20.88), "bear": (1.70e9, 6772.54, 5.66),
         "kitten": (7.49e8, 2911.07, 4.63), "hand": (5.78e8, 2187.18, 3.51),
         "eight": (1.76e7, 67.71, 0.48)}


def main():
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # lab/scripts/ -> the repository
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(root, "build"))
    ap.add_argument("--frames", type=int, default=200)
    ap.add_argument("--pressure", type=float, default=None)
    ap.add_argument("meshes", nargs="*", default=["eight", "hand", "elk", "bear"])
    args = ap.parse_args()
    exe = os.path.join(args.build, "shellcontract")
    print("| mesh | faces | pairs without culling / step | after broad phase | after filter | "
          "narrow queries | cubic solves | broad ms (background) | filter ms | narrow ms | response ms | CCD ms / solve ms | "
          "CCD total s (ours, %d frames) | paper: cubic solves, their s, paper's CCD s |" % args.frames)
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.meshes:
            mesh = os.path.join(root, "data", "meshes", name + ".off")
            if not os.path.exists(mesh):
                print("| %s | (absent: run scripts/fetch_paper_meshes.sh) |" % name)
                continue
            summary = os.path.join(tmp, name + ".json")
            cmd = [exe, "run", mesh, "-o", os.path.join(tmp, name + ".off"), "--frames",
                   str(args.frames), "--summary", summary, "-q"]
            if args.pressure is not None:
                cmd += ["--pressure", str(args.pressure)]
            subprocess.run(cmd, check=True)
            with open(summary) as f:
                s = json.load(f)
            t = s["table2"]
            ccd_s = t["collision_ms_per_step"] * s["frames_run"] / 1e3
            paper = PAPER.get(name)
            paper_text = "%.3g, %.2f, %.2f" % paper if paper else "-"
            print("| %s | %d | %.4g | %.4g | %.4g | %.4g | %.4g | %.3f (%.3f) | %.3f | %.3f | %.3f | %.1f / %.1f | %.2f | %s |" % (
                name, s["faces"], t["pairs_no_culling_per_step"], t["pairs_after_broad_phase_per_step"],
                t["pairs_after_filter_per_step"], t["narrow_queries_per_step"], t["cubic_solves_per_step"],
                t["broad_phase_ms_per_step"], t.get("background_broad_phase_ms_per_step", 0.0),
                t["filter_ms_per_step"], t["narrow_phase_ms_per_step"], t["response_ms_per_step"],
                t["collision_ms_per_step"], t["constraint_solve_ms_per_step"], ccd_s, paper_text))
    return 0


if __name__ == "__main__":
    sys.exit(main())
