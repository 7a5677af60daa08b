#!/usr/bin/python3
"""Renders the automatic regions of each paper mesh (and bumpy_sphere) into
docs/images/regions_<mesh>.png: `shellcontract regions MESH -o PLY` at default thresholds, then
scripts/render_ply.py (grey = no region, one colour per region).

Usage: /usr/bin/python3 lab/regions/render_regions.py [--build build]
"""
import argparse
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

VIEWS = {"bear": ["--azim", "20"], "hand": ["--azim", "30"], "elk": ["--azim", "30"], "eight": ["--azim", "30"],
         "kitten": ["--azim", "30"], "bumpy_sphere": ["--azim", "30"]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    a = ap.parse_args()
    exe = os.path.join(a.build, "shellcontract")
    out_dir = os.path.join(common.ROOT, "docs", "images")
    with tempfile.TemporaryDirectory() as tmp:
        for name in common.PAPER + ["bumpy_sphere"]:
            path = common.mesh_path(name)
            if not os.path.exists(path):
                print(f"{name}: absent, skipped", file=sys.stderr)
                continue
            regions, table, ply = common.auto_regions(exe, path, tmp)
            png = os.path.join(out_dir, f"regions_{name}.png")
            subprocess.run([sys.executable, os.path.join(common.ROOT, "lab", "scripts", "render_ply.py"), ply, png,
                            "--size", "640x480", "--title", f"{name}: {len(regions)} regions"] + VIEWS[name],
                           check=True, stdout=subprocess.DEVNULL)
            print(f"wrote {png} ({len(regions)} regions)")


if __name__ == "__main__":
    main()
