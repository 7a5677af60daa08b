#!/usr/bin/env python3
"""The large-mesh benchmark (issue "Large meshes and many cores"): bear and bear subdivided once
and twice (every triangle split in four at its edge midpoints: 110,592 and 442,368 faces, made
deterministically from data/meshes/bear.off), each run for a few frames in the coloured order (or
--order sequential, the tool's default) with collisions on at several thread counts. Prints a
markdown table of the step time, the broad phase's time, the time outside the time loop (reading,
checking, preparing, writing) and the peak memory. In the sequential order the broad phase runs on
a spare thread during the solve (--speculative-broad-phase auto): its column is then that work plus
the broad phase after the solve, without the time the main thread waited for it.

The "same result" column says whether every thread count wrote the same bytes as the first. With
--phases, a second table gives each phase's time per step at every thread count (where the time
goes, and which phase stops scaling). With --save DIR, every run's summary is kept there.

Usage: lab/scripts/scale_benchmark.py [--build build | --tool PATH] [--frames 10] [--threads 1,2]
                                  [--levels 0,1,2] [--order coloured|sequential]
                                  [--extra "--delta 2e-4"] [--phases] [--save DIR]
Needs: the built tool and data/meshes/bear.off (scripts/fetch_paper_meshes.sh)."""
import argparse
import hashlib
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def read_off(path):
    with open(path) as f:
        words = f.read().split()
    assert words[0] == "OFF", path
    nv, nf = int(words[1]), int(words[2])
    at = 4
    points = [tuple(float(w) for w in words[at + 3 * i: at + 3 * i + 3]) for i in range(nv)]
    at += 3 * nv
    faces = []
    for _ in range(nf):
        n = int(words[at])
        assert n == 3, "triangles only"
        faces.append(tuple(int(w) for w in words[at + 1: at + 4]))
        at += 4
    return points, faces


def subdivide(points, faces):
    """Every triangle split in four at its edge midpoints; midpoints shared between neighbours, new
    vertices numbered in the order the faces first meet them (deterministic)."""
    points = list(points)
    middle = {}

    def mid(a, b):
        key = (min(a, b), max(a, b))
        if key not in middle:
            pa, pb = points[a], points[b]
            points.append(tuple(0.5 * (x + y) for x, y in zip(pa, pb)))
            middle[key] = len(points) - 1
        return middle[key]

    out = []
    for a, b, c in faces:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return points, out


def write_off(path, points, faces):
    with open(path, "w") as f:
        f.write(f"OFF\n{len(points)} {len(faces)} 0\n")
        f.writelines(f"{x!r} {y!r} {z!r}\n" for x, y, z in points)
        f.writelines(f"3 {a} {b} {c}\n" for a, b, c in faces)


def write_levels(directory, levels):
    """bear.off subdivided 0, 1, ... times, written to directory as bear_x1.off, bear_x4.off, ...
    for each level listed: {level: (path, faces)}."""
    points, faces = read_off(os.path.join(ROOT, "data", "meshes", "bear.off"))
    meshes = {}
    for level in range(max(levels) + 1):
        if level in levels:
            path = os.path.join(directory, f"bear_x{4 ** level}.off")
            write_off(path, points, faces)
            meshes[level] = (path, len(faces))
        if level < max(levels):
            points, faces = subdivide(points, faces)
    return meshes


# The summary's per-step phase times (table2), in the order the step runs them.
PHASES = [("broad_phase_ms_per_step", "broad phase"),
          ("broad_phase_grid_ms_per_step", "- its grid (build or patch)"),
          ("broad_phase_cell_loop_ms_per_step", "- its cell loop"),
          ("broad_phase_pair_output_ms_per_step", "- its pair output"),
          ("broad_phase_records_ms_per_step", "- its pair records"),
          ("filter_ms_per_step", "filter"),
          ("narrow_phase_ms_per_step", "narrow phase"), ("response_ms_per_step", "response"),
          ("collision_ms_per_step", "collision, all"),
          ("constraint_solve_ms_per_step", "constraint solve"), ("step_ms", "step")]


def run(tool, mesh, frames, threads, order, tmp, extra, save):
    summary = os.path.join(tmp, "s.json")
    output = os.path.join(tmp, "o.off")
    cmd = [tool, "run", mesh, "-o", output, "--frames", str(frames), "--order", order,
           "--threads", str(threads), "--summary", summary, "-q"] + extra
    start = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    total = time.perf_counter() - start
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{p.stdout}{p.stderr}")
    with open(output, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    s = json.load(open(summary))
    if save:
        name = f"{os.path.splitext(os.path.basename(mesh))[0]}_{order}_{threads}thr.json"
        with open(os.path.join(save, name), "w") as f:
            json.dump(s, f, indent=1)
    t2 = s["table2"]
    # Sequential order: the spare thread's work plus the part after the solve, less the main
    # thread's wait for that work (which overlaps it). With one thread there is no spare thread:
    # the work runs inside the wait, and the background time is not recorded.
    background = t2["background_broad_phase_ms_per_step"]
    broad = (t2["broad_phase_ms_per_step"] + background -
             min(t2["background_wait_ms_per_step"], background))
    return {"faces": s["faces"], "step_ms": t2["step_ms"], "broad_ms": broad,
            "pairs": t2["pairs_after_broad_phase_per_step"], "table2": t2, "digest": digest,
            "outside_s": total - s["wall_seconds"], "read_s": s["setup"]["read_and_check_seconds"],
            "prepare_s": s["setup"]["prepare_seconds"],
            # The tool's own peak (VmHWM); /usr/bin/time's and wait4's maximum resident size
            # would include this script's memory at the fork (bear x16's points: ~400 MB).
            "peak_mb": s["peak_memory_mb"]}


def print_phases(name, rows, threads):
    """Each phase's time per step at every thread count, and its speed-up at the last count."""
    print(f"\n{name}: time per step by phase (ms)")
    head = "| phase | " + " | ".join(f"{t} thr" for t in threads)
    head += f" | speed-up, {threads[-1]} over {threads[0]} thr |"
    print(head)
    print("|" + "---|" * (head.count("|") - 1))
    for key, label in PHASES:
        if any(key not in rows[t]["table2"] for t in threads):
            continue  # a tool older than the row
        ms = [rows[t]["table2"][key] for t in threads]
        gain = f"{ms[0] / ms[-1]:.2f}x" if ms[-1] > 0 else "-"
        print(f"| {label} | " + " | ".join(f"{m:.2f}" for m in ms) + f" | {gain} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--tool", help="the tool to run (default: BUILD/shellcontract)")
    ap.add_argument("--frames", type=int, default=10)
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--levels", default="0,1,2")
    ap.add_argument("--order", default="coloured", choices=["coloured", "sequential"])
    ap.add_argument("--extra", default="", help="more options of every run, one string")
    ap.add_argument("--phases", action="store_true", help="also a table of the phases per mesh")
    ap.add_argument("--save", help="a folder to keep every run's summary in")
    a = ap.parse_args()
    extra = a.extra.split()
    tool = a.tool or os.path.join(a.build, "shellcontract")
    if a.save:
        os.makedirs(a.save, exist_ok=True)
    threads = [int(t) for t in a.threads.split(",")]
    levels = [int(l) for l in a.levels.split(",")]
    with tempfile.TemporaryDirectory() as tmp:
        meshes = {level: path for level, (path, _) in write_levels(tmp, levels).items()}
        head = "| mesh | faces | " + " | ".join(f"step, {t} thr (ms)" for t in threads)
        head += f" | step per 1k faces, {threads[0]} thr (ms) | broad phase, {threads[0]} thr (ms)"
        head += " | broad phase per 1k faces (ms) | candidate pairs per face"
        head += " | read + check (s) | prepare (s) | outside the loop (s) | peak memory (MB)"
        head += " | same result |"
        print(f"{a.order} order, collisions on, {a.frames} frames, default pressure"
              f"{', ' + a.extra if a.extra else ''}; {os.uname().nodename}, {os.cpu_count()} CPUs")
        print(head)
        print("|" + "---|" * (head.count("|") - 1))
        all_rows = {}
        for level in levels:
            rows = {t: run(tool, meshes[level], a.frames, t, a.order, tmp, extra, a.save)
                    for t in threads}
            all_rows[level] = rows
            same = all(r["digest"] == rows[threads[0]]["digest"] for r in rows.values())
            r0 = rows[threads[0]]
            cells = [f"{rows[t]['step_ms']:.1f}" for t in threads]
            print(f"| bear x{4 ** level} | {r0['faces']} | " + " | ".join(cells) +
                  f" | {1e3 * r0['step_ms'] / r0['faces']:.3f} | {r0['broad_ms']:.1f}"
                  f" | {1e3 * r0['broad_ms'] / r0['faces']:.3f} | {r0['pairs'] / r0['faces']:.2f} | {r0['read_s']:.2f} | "
                  f"{r0['prepare_s']:.2f} | {r0['outside_s']:.2f} | "
                  f"{max(r['peak_mb'] for r in rows.values()):.0f} | {'yes' if same else 'NO'} |",
                  flush=True)
        if a.phases:
            for level in levels:
                print_phases(f"bear x{4 ** level}", all_rows[level], threads)


if __name__ == "__main__":
    main()
