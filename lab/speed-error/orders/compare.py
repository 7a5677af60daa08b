#!/usr/bin/env python3
"""Sequential against coloured Gauss-Seidel order at equal time (issue 58, point 1), from the CSVs
of `shellcontract bench error --orders both` in this folder.

For every sequential rung (one thread), the most accurate coloured rung (one thread) that takes
at most as long per step; the coloured order is "no worse" there when its Hausdorff error is at
most the sequential rung's. Errors are deterministic; the times are medians over the steps and
drift with the machine, which is why the verdict asks a clear margin of nothing: any coloured
rung no slower and no less accurate.

usage: lab/speed-error/orders/compare.py [CSV ...]   (default: every *.csv here)
"""
import csv
import glob
import os
import sys


def rungs(path):
    with open(path) as f:
        return [r for r in csv.DictReader(f) if r["row_type"] == "rung" and r["threads"] == "1"]


def main(paths):
    print("| mesh | sequential rung (iter x sub) | ms/step | hausdorff | best coloured rung no slower "
          "| ms/step | hausdorff | coloured no worse |")
    print("|---|---|---:|---:|---|---:|---:|---|")
    worse = 0
    for path in paths:
        rows = rungs(path)
        mesh = os.path.splitext(os.path.basename(path))[0]
        seq = [r for r in rows if r["order"] == "sequential"]
        col = [r for r in rows if r["order"] == "coloured"]
        for s in seq:
            t = float(s["ms_per_step"])
            fast = [c for c in col if float(c["ms_per_step"]) <= t]
            if not fast:
                print("| {} | {} x {} | {:.3g} | {:.3g} | none | - | - | - |".format(
                    mesh, s["iterations"], s["substeps"], t, float(s["hausdorff"])))
                continue
            c = min(fast, key=lambda r: float(r["hausdorff"]))
            ok = float(c["hausdorff"]) <= float(s["hausdorff"])
            worse += not ok
            print("| {} | {} x {} | {:.3g} | {:.3g} | {} x {} | {:.3g} | {:.3g} | {} |".format(
                mesh, s["iterations"], s["substeps"], t, float(s["hausdorff"]), c["iterations"],
                c["substeps"], float(c["ms_per_step"]), float(c["hausdorff"]),
                "yes" if ok else "**no**"))
    print("\nsequential rungs where every no-slower coloured rung is less accurate: {}".format(worse))


if __name__ == "__main__":
    here = os.path.dirname(os.path.abspath(__file__))
    main(sys.argv[1:] or sorted(glob.glob(os.path.join(here, "*.csv"))))
