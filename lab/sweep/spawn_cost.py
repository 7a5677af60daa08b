#!/usr/bin/env python3
"""What starting one job's process costs the sweep, by how it is started: Popen with a
preexec_fn (Python then forks the whole calling process, copies its page tables and runs Python
code in the copy before exec), as the sweep's jobs were started, against Popen without one
(vfork and exec), and the same through setpriv, which sets the parent-death signal and execs
the run, as they are started now. From a small process
and from one that has imported Dask distributed (the size of a sweep's worker). Each start runs
/bin/true and waits for it; wall time, and CPU time of the starting process and of the child.

usage: lab/sweep/spawn_cost.py [--starts 200]
"""
import argparse
import resource
import subprocess
import sys
import time

PROBE = r"""
import resource, subprocess, sys, time
n = int(sys.argv[2])
if sys.argv[1] == "dask":
    import distributed  # noqa: F401  (the worker's size)

def nothing():
    pass

def cpu(who):
    r = resource.getrusage(who)
    return r.ru_utime + r.ru_stime

def starts(prefix=(), **kw):
    t, s, c = time.monotonic(), cpu(resource.RUSAGE_SELF), cpu(resource.RUSAGE_CHILDREN)
    for _ in range(n):
        subprocess.Popen(list(prefix) + ["/bin/true"], stdin=subprocess.DEVNULL, **kw).wait()
    return [1000.0 * (time.monotonic() - t) / n, 1000.0 * (cpu(resource.RUSAGE_SELF) - s) / n,
            1000.0 * (cpu(resource.RUSAGE_CHILDREN) - c) / n]

rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
setpriv = ["setpriv", "--pdeathsig", "TERM", "--"]
for name, kw in (("vfork (no preexec_fn)", {"start_new_session": True}),
                 ("vfork, through setpriv --pdeathsig", {"start_new_session": True,
                                                         "prefix": setpriv}),
                 ("fork (preexec_fn)", {"start_new_session": True, "preexec_fn": nothing})):
    w, s, c = starts(**kw)
    print("| {} ({:.0f} MB) | {} | {:.2f} | {:.2f} | {:.2f} |".format(sys.argv[1], rss, name, w, s, c))
"""


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--starts", type=int, default=200)
    a = p.parse_args()
    print("| starting process | how | wall per start (ms) | its CPU (ms) | the child's CPU (ms) |")
    print("|---|---|---:|---:|---:|")
    for kind in ("python", "dask"):
        sys.stdout.write(subprocess.run([sys.executable, "-c", PROBE, kind, str(a.starts)],
                                        capture_output=True, text=True, check=True).stdout)
        sys.stdout.flush()
    import os
    print("\nload average (1 min) at the end: {:.2f}".format(os.getloadavg()[0]))


if __name__ == "__main__":
    main()
