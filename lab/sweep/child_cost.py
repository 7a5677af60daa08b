#!/usr/bin/env python3
"""Does a run cost more as a sweep's job than as a plain call? Each of the benchmark's jobs
(lab/sweep/benchmark.py: the paper's meshes x 4 target volumes x 4 thicknesses) is run twice in
a row, as a plain `shellcontract run` and as the sweep starts it (sweep_job.run_job: through
setpriv, with --checkpoint, its messages to a file), alternating which goes first, so that both
of a pair see the same load; optionally with an embedded Dask cluster idling in this process the
whole time (--with-cluster: its background work, as during a sweep). Compares the two runs' CPU
seconds (user + system, wait4) pair by pair: a per-pair ratio hardly moves with the machine's
load, unlike sums taken minutes apart.

usage: PYTHONPATH=build/python lab/sweep/child_cost.py [--build build] [--meshes data/meshes]
           [--frames 100] [--with-cluster] [--out /tmp/sweep_child_cost]
"""
import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys

from benchmark import MESHES, TARGETS, THICKNESSES


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    p.add_argument("--build", default=os.path.join(root, "build"))
    p.add_argument("--meshes", default=os.path.join(root, "data", "meshes"))
    p.add_argument("--frames", type=int, default=100)
    p.add_argument("--with-cluster", action="store_true")
    p.add_argument("--out", default="/tmp/sweep_child_cost")
    a = p.parse_args()
    sys.path.insert(0, os.path.join(a.build, "python"))
    from shellcontract import sweep, sweep_dask, sweep_file, sweep_job
    cli = os.path.abspath(os.path.join(a.build, "shellcontract"))
    shutil.rmtree(a.out, ignore_errors=True)
    os.makedirs(a.out)
    spec = {"meshes": [os.path.join(os.path.abspath(a.meshes), m) for m in MESHES],
            "options": {"frames": a.frames, "threads": 1},
            "grid": {"target_volume": TARGETS, "thickness": THICKNESSES}}
    path = os.path.join(a.out, "sweep.json")
    with open(path, "w") as f:
        json.dump(spec, f)
    jobs = sweep_file.expand(path, sweep_file.load(path), sweep.cli_version(cli))
    cluster = client = None
    if a.with_cluster:
        from distributed import Client
        cluster = sweep_dask.embedded_cluster(1)
        client = Client(cluster)

    def children_cpu():
        r = resource.getrusage(resource.RUSAGE_CHILDREN)
        return r.ru_utime + r.ru_stime

    def plain(job):
        folder = os.path.join(a.out, "plain")
        os.makedirs(folder, exist_ok=True)
        before = children_cpu()
        subprocess.run([cli, "run", job.mesh, "-o", os.path.join(folder, job.id + ".off"),
                        "--log", os.path.join(folder, job.id + ".csv"), "--summary",
                        os.path.join(folder, job.id + ".json"), "-q"] + job.args, check=False)
        return children_cpu() - before

    def as_sweep_job(job):
        record = sweep_job.run_job(job.to_dict(), os.path.join(a.out, "sweep"), cli)
        return record["cpu_seconds"]

    ratios, sums = [], [0.0, 0.0]
    for k, job in enumerate(jobs):
        if k % 2 == 0:
            c_plain, c_job = plain(job), as_sweep_job(job)
        else:
            c_job, c_plain = as_sweep_job(job), plain(job)
        ratios.append(c_job / c_plain)
        sums[0] += c_plain
        sums[1] += c_job
        print("{} {}: plain {:.3f} s, as a sweep's job {:.3f} s ({:+.1f} %)".format(
            os.path.basename(job.mesh), " ".join(job.args), c_plain, c_job,
            100.0 * (c_job / c_plain - 1.0)), flush=True)
    if client is not None:
        client.close()
        cluster.close()
    print("\n{} pairs{}; CPU of the job against its plain call: median {:+.1f} % (quartiles "
          "{:+.1f} %, {:+.1f} %), sums {:.2f} s against {:.2f} s ({:+.1f} %); load average "
          "(1 min) at the end {:.2f}".format(
              len(ratios), ", an embedded cluster idling meanwhile" if a.with_cluster else "",
              100.0 * (statistics.median(ratios) - 1.0),
              *(100.0 * (q - 1.0) for q in statistics.quantiles(ratios, n=4)[::2]),
              sums[1], sums[0], 100.0 * (sums[1] / sums[0] - 1.0), os.getloadavg()[0]))


if __name__ == "__main__":
    main()
