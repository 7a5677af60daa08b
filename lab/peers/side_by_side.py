#!/usr/bin/env python3
"""Our default run beside Blender's cloth (issue 58, point 5), alternating, on the paper's meshes.

Each round runs, for every mesh, first Blender's cloth (Debian's `blender`, headless, with
../shared/peers/blender_cloth.py and the scene its header names as ShellContract's peer: quality
10, bending 10, self distance 0.25 x the mean edge, gas on, pressure -0.5 x 10, self-collision on)
for --frames frames, then `shellcontract run` with its defaults on both cores until it reaches the
V/V0 Blender ended at (--stop-volume-ratio, at most --max-frames frames). Reported, as medians
over the rounds:

  step ratio   Blender's median wall time of a frame / our median wall time of a step
               (the issue's goal on bear: at least 150x);
  to same V/V0 Blender's time to its final V/V0 (its frames' step times added up) / ours to the
               same V/V0 (our steps' times added up, from the log); goal: at least 40x on every
               mesh. "not reached" when our run stops above Blender's V/V0 (the default air
               inside stops the shell near V/V0 0.5).

Only the simulation steps are timed on both sides (Blender: scene.frame_set; ours: the log's
step_ms). Run it on a quiet machine; the figures mean nothing while other work shares the cores.

With --default-run our side is the default run (`run MESH --threads 2`: its 200 frames, both
cores, no stop ratio) and Blender runs as many frames (--frames must be 200): the step ratio is then Blender's median frame
over the whole run against our median step over the whole default run, the reading of "bear's
default step" that the issue's own figure used (a whole run of ours, not its first frames);
"to same V/V0" is not computed then.

usage: lab/peers/side_by_side.py [--build build] [--meshes eight,hand,elk,bear] [--frames 20]
                                 [--rounds 3] [--out /tmp/side_by_side] [--page FILE]
                                 [--default-run]
"""
import argparse
import csv
import os
import shutil
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PEER = os.path.join(ROOT, os.pardir, "shared", "peers", "blender_cloth.py")
# The scene the peer's header names as the one compared against ShellContract's default run.
SCENE = ["--quality", "10", "--bending", "10", "--self-dist-rel", "0.25", "--gas", "1",
         "--pressure", "-0.5", "--pressure-factor", "10", "--self-collision", "1"]


def blender_run(mesh, frames, prefix):
    cmd = ["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python",
           os.path.abspath(PEER), "--", "--mesh", mesh, "--out", prefix, "--frames", str(frames),
           "--export", str(frames)] + SCENE
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(prefix + "_volume.csv") as f:
        rows = [r for r in csv.DictReader(f) if int(r["frame"]) >= 1]
    steps = [float(r["step_time_s"]) for r in rows]
    return {"frame_ms": 1000.0 * statistics.median(steps), "seconds": sum(steps),
            "final_ratio": float(rows[-1]["V_over_V0"]), "frames": len(rows)}


def our_run(cli, mesh, stop_ratio, max_frames, prefix):
    cmd = [cli, "run", mesh, "-o", prefix + ".off", "--log", prefix + ".csv", "--summary",
           prefix + ".json", "-q", "--threads", "2"]
    if stop_ratio is not None:  # else the default run: its own frames, no stop
        cmd += ["-n", str(max_frames), "--stop-volume-ratio", "{:.6f}".format(stop_ratio)]
    rc = subprocess.run(cmd).returncode
    if rc not in (0, 5):
        sys.exit("{} exited {}".format(" ".join(cmd), rc))
    with open(prefix + ".csv") as f:
        rows = list(csv.DictReader(f))
    steps = [float(r["step_ms"]) for r in rows]
    # The run ends at the frame where V/V0 reaches the stop value (the log's last value may be
    # above the printed 6-digit stop by its rounding); a run of all --max-frames did not reach it.
    reached = stop_ratio is not None and (len(rows) < max_frames or
                                          float(rows[-1]["volume_ratio"]) <= stop_ratio)
    return {"step_ms": statistics.median(steps), "seconds": sum(steps) / 1000.0,
            "reached": reached, "frames": len(rows), "final_ratio": float(rows[-1]["volume_ratio"])}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", default=os.path.join(ROOT, "build"))
    p.add_argument("--meshes", default="eight,hand,elk,bear")
    p.add_argument("--mesh-dir", default=os.path.join(ROOT, "data", "meshes"))
    p.add_argument("--frames", type=int, default=20, help="Blender's frames per run")
    p.add_argument("--max-frames", type=int, default=2000, help="our run's frame limit")
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--out", default="/tmp/shellcontract_side_by_side")
    p.add_argument("--page", default=None, help="append the table to this Markdown file")
    p.add_argument("--default-run", action="store_true",
                   help="ours: the default run (200 frames, no stop ratio); give --frames 200")
    a = p.parse_args()
    if a.default_run and a.frames != 200:
        p.error("--default-run compares the default run's 200 frames: give --frames 200")
    if not os.path.isfile(PEER):
        sys.exit("the peer script is missing: " + PEER)
    cli = os.path.join(a.build, "shellcontract")
    shutil.rmtree(a.out, ignore_errors=True)
    os.makedirs(a.out)
    meshes = a.meshes.split(",")
    results = {m: [] for m in meshes}
    for k in range(a.rounds):
        for m in meshes:
            mesh = os.path.join(a.mesh_dir, m + ".off")
            b = blender_run(mesh, a.frames, os.path.join(a.out, "{}_blender_{}".format(m, k)))
            s = our_run(cli, mesh, None if a.default_run else b["final_ratio"], a.max_frames,
                        os.path.join(a.out, "{}_ours_{}".format(m, k)))
            results[m].append((b, s))
            print("round {} {}: Blender {:.1f} ms/frame to V/V0 {:.4f} in {:.2f} s; ours {:.2f} "
                  "ms/step, {} in {:.3f} s ({} frames)".format(
                      k + 1, m, b["frame_ms"], b["final_ratio"], b["seconds"], s["step_ms"],
                      "reached" if s["reached"] else "ended at {:.4f}".format(s["final_ratio"]),
                      s["seconds"], s["frames"]), flush=True)

    lines = ["{} rounds of {} Blender frames{}; medians over the rounds:".format(
                 a.rounds, a.frames, ", ours the default run" if a.default_run else ""),
             "", "| mesh | Blender ms/frame | ours ms/step | step ratio | Blender's V/V0 | "
             "Blender s to it | ours s to it | to same V/V0 |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for m in meshes:
        rs = results[m]
        bms = statistics.median(b["frame_ms"] for b, _ in rs)
        sms = statistics.median(s["step_ms"] for _, s in rs)
        ratio = statistics.median(b["frame_ms"] / s["step_ms"] for b, s in rs)
        reached = all(s["reached"] for _, s in rs)
        same = (statistics.median(b["seconds"] / s["seconds"] for b, s in rs)
                if reached else None)
        lines.append("| {} | {:.1f} | {:.2f} | {:.0f}x | {:.4f} | {:.2f} | {} | {} |".format(
            m, bms, sms, ratio, statistics.median(b["final_ratio"] for b, _ in rs),
            statistics.median(b["seconds"] for b, _ in rs),
            "{:.3f}".format(statistics.median(s["seconds"] for _, s in rs)) if reached else "-",
            "-" if a.default_run else "{:.0f}x".format(same) if same is not None else "not reached"))
    print("\n".join(lines))
    if a.page:
        with open(a.page, "a") as f:
            f.write("\n" + "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
