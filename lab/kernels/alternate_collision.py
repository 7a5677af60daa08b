#!/usr/bin/env python3
"""Bear's default run (60 frames, coloured order, 2 threads) with two binaries, alternating,
in one sitting: the medians of the collision step, the constraint solve and the broad phase's
parts (ms per step, the summary's table2), and the ratio collision / solve (issue 58 point 4).

Usage: lab/kernels/alternate_collision.py OLD_BINARY NEW_BINARY [ROUNDS] [MESH]
Copy the binaries to a stable folder first (a rebuild during the sitting would change them).
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

KEYS = [
    ("collision_ms_per_step", "collision"),
    ("constraint_solve_ms_per_step", "solve"),
    ("broad_phase_ms_per_step", "broad"),
    ("broad_phase_grid_ms_per_step", "grid"),
    ("broad_phase_cell_loop_ms_per_step", "cell loop"),
    ("broad_phase_pair_output_ms_per_step", "output"),
    ("broad_phase_records_ms_per_step", "records"),
    ("filter_ms_per_step", "filter"),
    ("narrow_phase_ms_per_step", "narrow"),
]


def run(binary, mesh, out_dir, tag):
    summary = os.path.join(out_dir, tag + ".json")
    subprocess.run([binary, "run", mesh, "-n", "60", "-o", os.path.join(out_dir, tag + ".off"),
                    "-q", "--summary", summary], check=True)
    t = json.load(open(summary))["table2"]
    row = {name: t[key] for key, name in KEYS}
    row["ratio"] = row["collision"] / row["solve"]
    return row


def main():
    old, new = sys.argv[1], sys.argv[2]
    rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    mesh = sys.argv[4] if len(sys.argv) > 4 else "data/meshes/bear.off"
    rows = {"old": [], "new": []}
    load_before = os.getloadavg()
    with tempfile.TemporaryDirectory() as d:
        for _ in range(rounds):
            for tag, binary in (("old", old), ("new", new)):
                rows[tag].append(run(binary, mesh, d, tag))
        same = open(os.path.join(d, "old.off"), "rb").read() == open(
            os.path.join(d, "new.off"), "rb").read()
    load_after = os.getloadavg()
    names = [name for _, name in KEYS] + ["ratio"]
    print(f"{rounds} rounds, load average before {load_before[0]:.2f}, after {load_after[0]:.2f};"
          f" outputs byte-identical: {same}")
    print("| binary | " + " | ".join(names) + " |")
    print("|---" * (len(names) + 1) + "|")
    for tag in ("old", "new"):
        med = [statistics.median(r[n] for r in rows[tag]) for n in names]
        print(f"| {tag} | " + " | ".join(f"{m:.3f}" for m in med) + " |")
    ratios = [o["collision"] / n["collision"] for o, n in zip(rows["old"], rows["new"])]
    print(f"collision old / new per round: {', '.join(f'{r:.2f}' for r in ratios)}")


if __name__ == "__main__":
    main()
