#!/usr/bin/env python3
"""What an embedded Dask cluster costs while its one task only waits (as a sweep's task waits for
its job's process): CPU milliseconds per second and context switches (wake-ups) per second of
the whole process, over a task that sleeps for --seconds. CPU time and wake-ups hardly depend on
what else the machine runs, so this can be measured while others build.

Configurations, all with one single-threaded worker:

  threads-default  processes=False with Dask's default configuration
  threads-quiet    processes=False with the sweep's QUIET_WORKERS and no memory limit, as
                   shellcontract.sweep starts it (sweep_dask.embedded_cluster)
  processes-quiet  processes=True (a nanny and a worker process) with the same configuration,
                   as the sweep started it before: the worker process counted too (psutil)

usage: PYTHONPATH=build/python lab/sweep/idle_cost.py [--seconds 10]
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import time

PROBE = r"""
import json, os, resource, sys, time
import dask
mode, seconds = sys.argv[1], float(sys.argv[2])
from shellcontract import sweep_dask
from distributed import Client, LocalCluster

def nap(s):
    time.sleep(s)
    return os.getpid()

if mode == "threads-default":
    cluster = LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                           dashboard_address=None, silence_logs=40)
elif mode == "threads-quiet":
    cluster = sweep_dask.embedded_cluster(1)
else:
    dask.config.set(sweep_dask.QUIET_WORKERS)
    cluster = LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                           dashboard_address=None, silence_logs=40)
client = Client(cluster)
worker_pid = client.submit(nap, 0.1, pure=False).result()
time.sleep(1.0)  # past the start-up

def usage():
    r = resource.getrusage(resource.RUSAGE_SELF)
    cpu, switches = r.ru_utime + r.ru_stime, r.ru_nvcsw + r.ru_nivcsw
    if worker_pid != os.getpid():
        import psutil
        p = psutil.Process(worker_pid)
        t, c = p.cpu_times(), p.num_ctx_switches()
        cpu += t.user + t.system
        switches += c.voluntary + c.involuntary
    return cpu, switches

cpu0, sw0 = usage()
t0 = time.monotonic()
client.submit(nap, seconds, pure=False).result()
t1 = time.monotonic()
cpu1, sw1 = usage()
print(json.dumps({"cpu_ms_per_s": 1000.0 * (cpu1 - cpu0) / (t1 - t0),
                  "switches_per_s": (sw1 - sw0) / (t1 - t0)}))
client.close()
cluster.close()
"""

MODES = ("threads-default", "threads-quiet", "processes-quiet")


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--seconds", type=float, default=10.0)
    p.add_argument("--modes", default=",".join(MODES))
    a = p.parse_args()
    print("| configuration | CPU (ms per s) | context switches per s |")
    print("|---|---:|---:|")
    for mode in a.modes.split(","):
        out = subprocess.run([sys.executable, "-c", PROBE, mode, str(a.seconds)],
                             capture_output=True, text=True, check=True).stdout
        r = json.loads(out.strip().splitlines()[-1])
        print("| {} | {:.1f} | {:.1f} |".format(mode, r["cpu_ms_per_s"], r["switches_per_s"]),
              flush=True)
    print("\nload average (1 min) at the end: {:.2f}".format(os.getloadavg()[0]))


if __name__ == "__main__":
    main()
