"""Region vertices that flicker: jump toward an image and come back in the next frame.

Runs `shellcontract run MESH --regions auto [ARGS] -n FRAMES --export-dir D --export-every 1`
with each binary given, and counts, over frames FIRST..FRAMES, the vertices that move more than
1 % of the bounding-box diagonal in one frame and come back within 30 % of that move in the next
(the test RegionMirrorStep.NoRegionVertexFlickersUnderTheDefaultPressure counts the same). Also
prints the summary's V/V0, each region's sink (summary region_sinks), contacts and ms per step.

Usage: /usr/bin/python3 lab/regions/flicker.py BIN[,BIN...] [--meshes bear,hand,elk]
           [--frames 130] [--first 60] [--run-args "--target-volume 0.6"]
"""
import argparse
import json
import os
import subprocess
import tempfile

import numpy as np

import common


def positions(path):
    return common.read_off(path)[0]


def flicker(frames_dir, first, last):
    fr = [positions(os.path.join(frames_dir, "out_%03d.off" % k)) for k in range(first, last + 1)]
    v0 = positions(os.path.join(frames_dir, "out_000.off"))
    diag = np.linalg.norm(v0.max(0) - v0.min(0))
    count, frames_with, largest = 0, 0, 0.0
    for k in range(len(fr) - 2):
        there = np.linalg.norm(fr[k + 1] - fr[k], axis=1) / diag
        back = np.linalg.norm(fr[k + 2] - fr[k], axis=1) / diag
        hit = (there > 0.01) & (back < 0.3 * there)
        count += int(hit.sum())
        frames_with += int(hit.any())
        if hit.any():
            largest = max(largest, float(there[hit].max()))
    return count, frames_with, largest


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bins")
    ap.add_argument("--meshes", default="bear,hand,elk")
    ap.add_argument("--frames", type=int, default=130)
    ap.add_argument("--first", type=int, default=60)
    ap.add_argument("--run-args", default="")
    a = ap.parse_args()
    print("| binary | mesh | flickers (vertex-frames) | frames with one | largest / diag | V/V0 | "
          "region sinks | contacts per step | ms per step |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name in a.meshes.split(","):
        mesh = os.path.join(common.ROOT, "data", "meshes", name + ".off")
        for exe in a.bins.split(","):
            with tempfile.TemporaryDirectory() as tmp:
                d = os.path.join(tmp, "fr")
                summary = os.path.join(tmp, "s.json")
                subprocess.run([exe, "run", mesh, "--regions", "auto", "-o",
                                os.path.join(tmp, "out.off"), "-q", "-n", str(a.frames),
                                "--export-dir", d, "--export-every", "1", "--summary", summary]
                               + a.run_args.split(), check=True)
                count, frames_with, largest = flicker(d, a.first, a.frames)
                s = json.load(open(summary))
                t = s["table2"]
                print("| {} | {} | {} | {} | {:.3f} | {:.3f} | {} | {:.0f} | {:.1f} |".format(
                    exe, name, count, frames_with, largest, s["final_volume_ratio"],
                    ", ".join("%.4f" % x for x in s["region_sinks"]), t["contacts_per_step"],
                    t["step_ms"]))


if __name__ == "__main__":
    main()
