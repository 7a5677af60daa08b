#!/usr/bin/env python3
"""The sweep engine's own cost, apart from the runs (issue 57, point 8): the sweep drives a
stand-in `shellcontract` that only sleeps, so every CPU second counted is the engine's (Python,
Dask, the results files) and none is a run's. CPU time and context switches hardly depend on what
else the machine runs, unlike wall times, so this can be measured while others build.

Each mode runs the same N jobs of S seconds each, from an empty folder, under `perf stat` (every
process of the sweep, children included):

  plain   the stand-in called N times from a Python loop (the jobs alone)
  serial  --shard 0/1: the jobs one after the other in the sweep's own process, no Dask
  dask    --workers 1: the embedded Dask cluster of one worker

and the report gives, per mode, CPU seconds (total and per job), context switches, wall time
and the median gap from one job's end to the next one's start (the stand-in logs both; the
last two load-dependent: compare them only within one sitting, read them as absolute figures
only on a quiet machine).

usage: lab/sweep/engine_cost.py [--python-path build/python] [--jobs 64] [--sleep 0.5]
                                [--rounds 2] [--modes plain,serial,dask] [--out /tmp/sweep_engine_cost]
"""
import argparse
import json
import os
import re
import shutil
import stat
import statistics
import subprocess
import sys
import time

# A stand-in CLI: `--version` as the real one, `run ... -o MESH ...` sleeps then writes the
# output mesh (so that the job's folder looks like a real one's) and exits 0.
FAKE_CLI = """#!/bin/sh
if [ "$1" = "--version" ]; then echo "shellcontract engine-cost-stand-in"; exit 0; fi
out=""
prev=""
for a in "$@"; do
  if [ "$prev" = "-o" ]; then out="$a"; fi
  prev="$a"
done
echo "start $(date +%s.%N)" >> "$ENGINE_COST_TIMES"
sleep {sleep}
[ -n "$out" ] && : > "$out"
echo "end $(date +%s.%N)" >> "$ENGINE_COST_TIMES"
exit 0
"""


def median_gap(path):
    """Median milliseconds from one stand-in job's end to the next one's start (the jobs run one
    after the other in every mode here): what the engine adds on the jobs' critical path."""
    start, end = [], []
    with open(path) as f:
        for line in f:
            kind, t = line.split()
            (start if kind == "start" else end).append(float(t))
    gaps = [start[i + 1] - end[i] for i in range(len(end) - 1)]
    return 1000.0 * statistics.median(gaps) if gaps else float("nan")


def perf_stat(cmd, env):
    """(task-clock CPU seconds, context switches, wall seconds) of cmd and all its children."""
    start = time.monotonic()
    r = subprocess.run(["perf", "stat", "-x", ",", "-e", "task-clock,context-switches"] + cmd,
                       env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall = time.monotonic() - start
    if r.returncode != 0:
        sys.exit("failed ({}): {}\n{}".format(r.returncode, " ".join(cmd), r.stderr[-2000:]))
    values = {}
    for line in r.stderr.splitlines():
        parts = line.split(",")
        if len(parts) > 2 and re.match(r"^[0-9.]+$", parts[0]):
            values[parts[2]] = float(parts[0])
    return values["task-clock"] / 1000.0, values["context-switches"], wall


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    p.add_argument("--python-path", default=os.path.join(root, "build", "python"),
                   help="the folder holding the shellcontract package to measure")
    p.add_argument("--mesh", default=os.path.join(root, "meshes", "ico1.off"))
    p.add_argument("--jobs", type=int, default=64)
    p.add_argument("--sleep", type=float, default=0.5, help="seconds each stand-in job sleeps")
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--modes", default="plain,serial,dask")
    p.add_argument("--out", default="/tmp/sweep_engine_cost")
    a = p.parse_args()
    shutil.rmtree(a.out, ignore_errors=True)
    os.makedirs(a.out)
    cli = os.path.join(a.out, "shellcontract")
    with open(cli, "w") as f:
        f.write(FAKE_CLI.format(sleep=a.sleep))
    os.chmod(cli, os.stat(cli).st_mode | stat.S_IXUSR)
    sweep = {"meshes": [os.path.abspath(a.mesh)], "options": {"frames": 1},
             "grid": {"target_volume": [round(0.2 + 0.7 * k / a.jobs, 6) for k in range(a.jobs)]}}
    sweep_path = os.path.join(a.out, "sweep.json")
    with open(sweep_path, "w") as f:
        json.dump(sweep, f)
    env = dict(os.environ, PYTHONPATH=os.path.abspath(a.python_path), SHELLCONTRACT_CLI=cli)
    # plain: the stand-in called N times from a Python loop, as the benchmark's plain calls (the
    # jobs' own cost, which the two sweep modes contain too).
    plain = ("import subprocess, sys\n"
             "for k in range({n}):\n"
             "    subprocess.run([{cli!r}, 'run', {mesh!r}, '-o', {out!r}], check=True)\n").format(
                 n=a.jobs, cli=cli, mesh=os.path.abspath(a.mesh),
                 out=os.path.join(a.out, "plain.off"))
    modes = {"plain": ["-c", plain],
             "serial": ["-m", "shellcontract.sweep", sweep_path, "--shard", "0/1", "-o"],
             "dask": ["-m", "shellcontract.sweep", sweep_path, "--workers", "1", "-o"]}
    chosen = a.modes.split(",")
    results = {m: [] for m in chosen}
    for k in range(a.rounds):
        for m in chosen:
            folder = os.path.join(a.out, "{}{}".format(m, k))
            cmd = [sys.executable] + modes[m] + ([folder] if m != "plain" else [])
            times = os.path.join(a.out, "times_{}{}.txt".format(m, k))
            cpu, switches, wall = perf_stat(cmd, dict(env, ENGINE_COST_TIMES=times))
            results[m].append((cpu, switches, wall, median_gap(times)))
            print("round {} {}: CPU {:.2f} s, {} context switches, wall {:.2f} s, gap between "
                  "jobs {:.1f} ms".format(k + 1, m, cpu, int(switches), wall, results[m][-1][3]),
                  flush=True)
    load = os.getloadavg()[0]
    print("\n{} stand-in jobs of {} s; medians of {} rounds; load average (1 min) at the end "
          "{:.2f}\n".format(a.jobs, a.sleep, a.rounds, load))
    med = {m: [statistics.median(r[i] for r in results[m]) for i in range(4)] for m in chosen}
    base = med.get("plain", [0.0, 0.0, a.jobs * a.sleep, 0.0])
    print("| mode | CPU (s) | CPU beyond plain (s) | the same per job (ms) | context switches | "
          "switches beyond plain per job | wall beyond plain (s) | gap between jobs (ms) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for m in chosen:
        cpu, sw, wall, gap = med[m]
        print("| {} | {:.2f} | {:.2f} | {:.1f} | {:.0f} | {:.1f} | {:.2f} | {:.1f} |".format(
            m, cpu, cpu - base[0], 1000.0 * (cpu - base[0]) / a.jobs, sw,
            (sw - base[1]) / a.jobs, wall - base[2], gap))

if __name__ == "__main__":
    main()
