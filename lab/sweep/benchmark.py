#!/usr/bin/env python3
"""The sweep engine's benchmark (issue 57, point 8): 64 jobs (the paper's meshes eight, hand, elk
and bear x 4 target volumes x 4 thicknesses, 100 frames each) run

  1. as 64 plain `shellcontract run` calls, one after the other (the reference),
  2. through the sweep on an embedded cluster of 1 worker,
  3. through the sweep on an embedded cluster of 2 workers,

and reports the speed-up of 2 workers over 1 (the issue asks at least 1.8x on a 2-core machine)
and the sweep's per-job overhead, 1 worker against the plain calls (at most 5 %). Every sweep
starts from an empty folder, so nothing is skipped. Run it on a quiet machine: the figures mean
nothing while other work shares the cores.

usage: lab/sweep/benchmark.py [--build build] [--meshes data/meshes] [--out /tmp/sweep_bench]
                              [--frames 100] [--rounds 3] [--page lab/sweep/README.md]
"""
import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import time

MESHES = ["eight.off", "hand.off", "elk.off", "bear.off"]
TARGETS = [0.3, 0.4, 0.5, 0.6]
THICKNESSES = [0.001, 0.002, 0.004, 0.008]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    p.add_argument("--build", default=os.path.join(root, "build"))
    p.add_argument("--meshes", default=os.path.join(root, "data", "meshes"))
    p.add_argument("--out", default="/tmp/shellcontract_sweep_benchmark")
    p.add_argument("--frames", type=int, default=100)
    p.add_argument("--rounds", type=int, default=3, help="alternating rounds of the three (median)")
    p.add_argument("--page", default=None, help="append the table to this Markdown file")
    a = p.parse_args()
    cli = os.path.join(a.build, "shellcontract")
    env = dict(os.environ, PYTHONPATH=os.path.join(a.build, "python"), SHELLCONTRACT_CLI=cli)
    shutil.rmtree(a.out, ignore_errors=True)
    os.makedirs(a.out)
    sweep = {"meshes": [os.path.join(os.path.abspath(a.meshes), m) for m in MESHES],
             "options": {"frames": a.frames, "threads": 1},
             "grid": {"target_volume": TARGETS, "thickness": THICKNESSES}}
    sweep_path = os.path.join(a.out, "sweep.json")
    with open(sweep_path, "w") as f:
        json.dump(sweep, f)

    listing = subprocess.run([sys.executable, "-m", "shellcontract.sweep", sweep_path, "-o",
                              os.path.join(a.out, "unused"), "--dry-run"], env=env, check=True,
                             capture_output=True, text=True).stdout.splitlines()

    def children_cpu():
        """CPU seconds (user + system) of every finished child process, theirs included: less
        sensitive than wall time to other work on the machine."""
        r = resource.getrusage(resource.RUSAGE_CHILDREN)
        return r.ru_utime + r.ru_stime

    plain_job_cpu = {}  # job id -> CPU seconds of its plain call, last round

    def plain_calls(folder):
        """The jobs as plain CLI calls with their own arguments, one after the other."""
        os.makedirs(folder)
        start = time.monotonic()
        cpu = children_cpu()
        for line in listing:
            job, mesh, *args = line.split()
            mesh = os.path.join(os.path.dirname(sweep_path), mesh)
            ext = os.path.splitext(mesh)[1]
            before = children_cpu()
            rc = subprocess.run([cli, "run", mesh, "-o", os.path.join(folder, job + ext),
                                 "--log", os.path.join(folder, job + ".csv"), "--summary",
                                 os.path.join(folder, job + ".json"), "-q"] + args).returncode
            plain_job_cpu[job] = children_cpu() - before
            if rc not in (0, 5):
                sys.exit("plain run of job {} exited {}".format(job, rc))
        return time.monotonic() - start, children_cpu() - cpu

    def sweep_run(folder, workers):
        start = time.monotonic()
        cpu = children_cpu()
        subprocess.run([sys.executable, "-m", "shellcontract.sweep", sweep_path, "-o", folder,
                        "--workers", str(workers)], env=env, check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        return time.monotonic() - start, children_cpu() - cpu

    job_ratios = []  # a sweep job's CPU over the same job's plain call in the same round

    def jobs_cpu(folder):
        """The CPU seconds of the sweep's job processes alone (cpu_seconds of the job records):
        the rest of the sweep's CPU time is the engine's (Python, Dask, the results files)."""
        total = 0.0
        for job in os.listdir(os.path.join(folder, "jobs")):
            with open(os.path.join(folder, "jobs", job, "job.json")) as f:
                seconds = json.load(f).get("cpu_seconds") or 0.0
            total += seconds
            if seconds and plain_job_cpu.get(job):
                job_ratios.append(seconds / plain_job_cpu[job])
        return total

    # Rounds of the three, alternating, so that a slow spell of the machine falls on all three
    # alike; each sweep starts in an empty folder (nothing skipped).
    load_start = os.getloadavg()
    rounds, cpu, split = [], [], []
    for k in range(a.rounds):
        w = {"plain": plain_calls(os.path.join(a.out, "plain{}".format(k))),
             1: sweep_run(os.path.join(a.out, "sweep1_{}".format(k)), 1),
             2: sweep_run(os.path.join(a.out, "sweep2_{}".format(k)), 2)}
        t = {key: v[0] for key, v in w.items()}
        cpu.append({key: v[1] for key, v in w.items()})
        rounds.append(t)
        jobs1 = jobs_cpu(os.path.join(a.out, "sweep1_{}".format(k)))
        split.append((jobs1, cpu[-1][1] - jobs1))
        print("round {}: plain {:.1f} s, 1 worker {:.1f} s, 2 workers {:.1f} s (CPU {:.1f}, {:.1f}, "
              "{:.1f} s; 1 worker's CPU: jobs {:.2f} s, engine {:.2f} s)".format(
                  k + 1, t["plain"], t[1], t[2], cpu[-1]["plain"], cpu[-1][1], cpu[-1][2],
                  jobs1, cpu[-1][1] - jobs1), flush=True)

    n = len(listing)
    med = {key: statistics.median(t[key] for t in rounds) for key in ("plain", 1, 2)}
    speedup = statistics.median(t[1] / t[2] for t in rounds)
    overhead = statistics.median(100.0 * (t[1] / t["plain"] - 1.0) for t in rounds)
    cpu_overhead = statistics.median(100.0 * (c[1] / c["plain"] - 1.0) for c in cpu)
    lines = [
        "{} rounds; medians of the wall times, and of each round's ratios:".format(len(rounds)),
        "",
        "| what | wall time (s) | per job (s) |",
        "|---|---:|---:|",
        "| {} plain CLI calls, serial | {:.1f} | {:.2f} |".format(n, med["plain"],
                                                              med["plain"] / n),
        "| sweep, 1 worker | {:.1f} | {:.2f} |".format(med[1], med[1] / n),
        "| sweep, 2 workers | {:.1f} | {:.2f} |".format(med[2], med[2] / n),
        "",
        "speed-up of 2 workers over 1: {:.2f}x; sweep overhead (1 worker against the plain "
        "calls): {:+.1f} % in wall time, {:+.1f} % in CPU time (every process of the sweep, "
        "Dask's included)".format(speedup, overhead, cpu_overhead),
        "",
        "the 1-worker sweep's CPU, split: its job processes {:+.1f} % against the plain calls, "
        "the engine (every other process and thread) {:.1f} % of the plain calls' "
        "(medians); one job's process against the same job's plain call in the same round: "
        "{:+.1f} % (median of {} pairs)".format(
            statistics.median(100.0 * (j / c["plain"] - 1.0) for (j, _), c in zip(split, cpu)),
            statistics.median(100.0 * e / c["plain"] for (_, e), c in zip(split, cpu)),
            100.0 * (statistics.median(job_ratios) - 1.0) if job_ratios else float("nan"),
            len(job_ratios)),
        "",
        "each round (plain, 1 worker, 2 workers; wall s / CPU s): " + "; ".join(
            "{:.1f}/{:.1f}, {:.1f}/{:.1f}, {:.1f}/{:.1f}".format(
                t["plain"], c["plain"], t[1], c[1], t[2], c[2]) for t, c in zip(rounds, cpu)),
    ]
    lines.insert(0, "load average (1, 5, 15 min) at the start {:.2f} {:.2f} {:.2f}, at the end "
                    "{:.2f} {:.2f} {:.2f}; wall times taken above 1.5 are not a quiet "
                    "machine's".format(*load_start, *os.getloadavg()))
    lines.insert(1, "")
    print("\n".join(lines))
    if a.page:
        with open(a.page, "a") as f:
            f.write("\n" + "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
