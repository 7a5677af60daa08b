#!/usr/bin/env python3
"""Measures the paper's Fig. 20 claim on the automatically selected spherical regions (the paper
specifies its regions by hand): with the anisotropic energy the regions sink in faster and the
volume ratio falls faster and ends smaller.

For each mesh it runs `shellcontract run` for --frames frames without the anisotropic energy
(regions selected and measured only) and with each anisotropic energy, material and inward-term
option, and prints the regions' mean inward displacement along the rest normal (normalized
units), its ratio to the run without, V/V0, and V/V0's relative difference.

The claim is measured at a moderate outside pressure (--pressure, default 0.5) so that the
whole shell does not contract so much that it hides the regions' own motion; the regions get
the default extra pressure of the anisotropic runs (see `shellcontract run --help`).

Usage: lab/scripts/measure_regions.py [--build build] [--frames 100] [--pressure 0.5] [meshes...]
  meshes are paths, or names of data/meshes/*.off (see scripts/fetch_paper_meshes.sh)
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

VARIANTS = [
    ("arap", ["--aniso", "arap"]),
    ("stvk", ["--aniso", "stvk"]),
    ("sqrt", ["--aniso", "sqrt"]),
    ("active-fiber 0.9", ["--aniso", "active-fiber", "--fiber-target", "0.9"]),
    ("arap, inversion-aware", ["--aniso", "arap", "--inversion-aware"]),
    ("arap, paper k_A (--inward projection)", ["--aniso", "arap", "--inward", "projection"]),
    ("arap, no inward term", ["--aniso", "arap", "--inward", "none"]),
    ("arap, fibre 1,0,0", ["--aniso", "arap", "--fiber", "1,0,0"]),
    ("arap, corotated", ["--aniso", "arap", "--material", "corotated"]),
    ("arap, linear", ["--aniso", "arap", "--material", "linear"]),
    ("arap, mooney-rivlin", ["--aniso", "arap", "--material", "mooney-rivlin"]),
]


def run(exe, mesh, frames, pressure, extra, tmp):
    summary = os.path.join(tmp, "s.json")
    subprocess.run([exe, "run", mesh, "-o", os.path.join(tmp, "o.off"), "--frames", str(frames),
                    "--pressure", str(pressure), "--measure-regions", "--summary", summary, "-q"] + extra,
                   check=True)
    with open(summary) as f:
        return json.load(f)


def main():
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # lab/scripts/ -> the repository
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(root, "build"))
    ap.add_argument("--frames", type=int, default=100)
    ap.add_argument("--pressure", type=float, default=0.5)
    ap.add_argument("meshes", nargs="*",
                    default=[os.path.join(root, "meshes", "bumpy_sphere.off"), "hand", "elk", "bear"])
    args = ap.parse_args()
    exe = os.path.join(args.build, "shellcontract")
    with tempfile.TemporaryDirectory() as tmp:
        for mesh in args.meshes:
            path = mesh if os.path.exists(mesh) else os.path.join(root, "data", "meshes", mesh + ".off")
            base = run(exe, path, args.frames, args.pressure, ["--aniso", "none"], tmp)
            print("\n%s: %d regions; without anisotropy: sink %.5f, V/V0 %.4f (%d frames)" % (
                os.path.basename(path), base["regions"], base["region_inward_displacement"],
                base["final_volume_ratio"], args.frames))
            print("| variant | sink | sink / without | V/V0 | V/V0 vs without |")
            print("|---|---:|---:|---:|---:|")
            for label, extra in VARIANTS:
                s = run(exe, path, args.frames, args.pressure, extra, tmp)
                # A region that does not sink at all without anisotropy (a convex bump under a
                # pressure below buckling) makes the ratio meaningless: print "-" then.
                b = base["region_inward_displacement"]
                ratio = "%.2f" % (s["region_inward_displacement"] / b) if b > 1e-6 else "- (no sink without)"
                dv = (s["final_volume_ratio"] - base["final_volume_ratio"]) / base["final_volume_ratio"]
                print("| %s | %.5f | %s | %.4f | %+.1f %% |" % (
                    label, s["region_inward_displacement"], ratio, s["final_volume_ratio"], 100 * dv))
    return 0


if __name__ == "__main__":
    sys.exit(main())
