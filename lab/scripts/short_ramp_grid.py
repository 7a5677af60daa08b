#!/usr/bin/env python3
"""Short target-volume ramps, two builds side by side (lab/pages/short-ramps.md).

Usage: short_ramp_grid.py OLD_CLI NEW_CLI [MESH_DIR]

Runs `run MESH --target-volume R -n N` for every mesh, R and N of the grid with each binary and
prints one markdown row per case: the final V/V0 and whether the target was reached (exit 0).
"""
import json
import os
import subprocess
import sys
import tempfile

MESHES = ("ico2", "ico3", "torus", "bumpy_sphere")
RATIOS = (0.05, 0.1, 0.2, 0.3, 0.5)
FRAMES = (4, 6, 8)


def run(cli, mesh, ratio, frames, folder):
    out, summary = os.path.join(folder, "r.off"), os.path.join(folder, "s.json")
    subprocess.run([cli, "run", mesh, "-o", out, "--target-volume", str(ratio), "-n", str(frames),
                    "-q", "--summary", summary], stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL, check=False)
    with open(summary, encoding="utf-8") as f:
        s = json.load(f)
    return "{:.4g} {}".format(s["final_volume_ratio"], "ok" if s["target_reached"] else "no")


def main():
    old, new = sys.argv[1], sys.argv[2]
    mesh_dir = sys.argv[3] if len(sys.argv) > 3 else "meshes"
    print("| mesh | R | frames | old: V/V0, reached | new: V/V0, reached |")
    print("|---|---:|---:|---|---|")
    counts = {"old": 0, "new": 0}
    with tempfile.TemporaryDirectory() as folder:
        for name in MESHES:
            mesh = os.path.join(mesh_dir, name + ".off")
            for ratio in RATIOS:
                for frames in FRAMES:
                    a, b = run(old, mesh, ratio, frames, folder), run(new, mesh, ratio, frames, folder)
                    counts["old"] += a.endswith("ok")
                    counts["new"] += b.endswith("ok")
                    print("| {} | {} | {} | {} | {} |".format(name, ratio, frames, a, b))
    print("\nreached: old {old}, new {new} of {n}".format(
        n=len(MESHES) * len(RATIOS) * len(FRAMES), **counts))


if __name__ == "__main__":
    main()
