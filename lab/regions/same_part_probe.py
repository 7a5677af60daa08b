#!/usr/bin/python3
"""Issue 55, the cap finder's "same part" rule (same_part.md section 5): for every seed that lies
in a kept part's same-part ball, the candidate measures of "this seed is across a crease from
the part", on the paper's meshes and on bear, hand, elk and kitten split in four.

Needs a build with lab/regions/same_part_probe.patch applied (`git apply`): with SC_SP_DEBUG set
it prints one line per seed in a ball (and per region tested by the step-5 piece rule); with
SC_SP_OFF set it takes main's decisions (every seed in a ball joins), so the seeds measured are
those main sees. The seeds across a crease are named by hand: on the hand 884 and 229 (the second
knuckle, fingertip 1: creases.md), on the split hand the seeds within half a part radius of
those, and on every mesh a seed with no convex path at all; every other seed is counted as of
the same part.

Usage: /usr/bin/python3 lab/regions/same_part_probe.py --build BUILD [--out FILE]
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_selection  # noqa: E402 (split_in_four keeps the coarse vertex ids)
import common  # noqa: E402

MESHES = ["bear", "hand", "elk", "kitten", "bumpy_sphere", "eight"]
SPLIT = ["bear", "hand", "elk", "kitten"]
ACROSS = {("hand", 884), ("hand", 229)}
INF = math.inf


def probe(exe, path, tmp):
    env = dict(os.environ, SC_SP_DEBUG="1", SC_SP_OFF="1")
    p = subprocess.run([exe, "regions", path, "--face-list", os.path.join(tmp, "f.txt")], env=env,
                       capture_output=True, text=True, check=True)
    rows = []
    for line in p.stderr.splitlines():
        t = line.split()
        if len(t) > 2 and t[0] == "SP" and t[1] == "join":
            rows.append({k: float(v) for k, v in zip(t[2::2], t[3::2])})
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True)
    ap.add_argument("--out")
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    rows = []  # (mesh, across, row)
    with tempfile.TemporaryDirectory() as tmp:
        for name in MESHES:
            if not os.path.exists(common.mesh_path(name)):
                print(f"{name}: absent, skipped", file=sys.stderr)
                continue
            for d in probe(exe, common.mesh_path(name), tmp):
                rows.append((name, d["conv"] == INF or (name, int(d["seed"])) in ACROSS, d))
        for name in SPLIT:
            if not os.path.exists(common.mesh_path(name)):
                continue
            v, f = common.read_off(common.mesh_path(name))
            v4, f4 = bench_selection.split_in_four(v, f)
            fine = os.path.join(tmp, name + "_x4.off")
            bench_selection.write_off(fine, v4, f4)
            for d in probe(exe, fine, tmp):
                p = v4[int(d["seed"])]
                near = any(np.linalg.norm(v[s] - p) < 0.5 * d["r"] for m, s in ACROSS if m == name)
                rows.append((name + " x4", d["conv"] == INF or near, d))
    rows = [r for r in rows if r[2]["any"] != INF]  # a seed that reaches no part vertex in the ball

    def fmt(x):
        return "-" if x is None else ("inf" if x == INF else f"{x:.2f}")

    def pick(group, key, fn):
        vals = [d[key] for d in group if d[key] > -1e8]  # -1e9: no concave vertex on the path
        return fn(vals) if vals else None

    out = ["| mesh | seeds in a ball: same part / across | L_c / L: same part max; across min "
           "| L_c / (pi r): same part max; across min | groove depth inside the sphere / r: same part max; "
           "across max | groove below the chord / r: same part max; across max |",
           "|---|---|---|---|---|---|"]
    names = [m for m in MESHES] + [m + " x4" for m in SPLIT]
    for n in names:
        same = [d for m, x, d in rows if m == n and not x]
        acr = [d for m, x, d in rows if m == n and x]
        out.append(f"| {n} | {len(same)} / {len(acr)} | {fmt(pick(same, 'ratio', max))}; "
                   f"{fmt(pick(acr, 'ratio', min))} | {fmt(pick(same, 'conv_pir', max))}; "
                   f"{fmt(pick(acr, 'conv_pir', min))} | {fmt(pick(same, 'sphere_depth', max))}; "
                   f"{fmt(pick(acr, 'sphere_depth', max))} | {fmt(pick(same, 'chord_depth', max))}; "
                   f"{fmt(pick(acr, 'chord_depth', max))} |")
    out.append("")
    for key in ("ratio", "conv_pir"):
        for label, sel in (("coarse", MESHES), ("all", names)):
            same = [d[key] for m, x, d in rows if m in sel and not x]
            acr = [d[key] for m, x, d in rows if m in sel and x]
            out.append(f"- {key}, {label} meshes: same part max {max(same):.3f}, across min {min(acr):.3f}, "
                       f"relative margin {min(acr) / max(same):.3f}")
    text = "\n".join(out) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    print(text, end="")


if __name__ == "__main__":
    main()
