#!/usr/bin/env python3
"""Memory bandwidth of this machine with 1, 2, 4, ... worker processes, each copying its own
256 MB array (numpy's copy, one thread each): how far memory-bound work can scale with cores.
A copy moves its bytes twice (read and write); the table counts both. Used by
lab/pages/scale.md to say what bounds the many-core speed-up.

Usage: lab/scripts/memory_bandwidth.py [--workers 1,2,4,8,16] [--mb 256] [--repeats 5]"""
import argparse
import multiprocessing as mp
import time

import numpy as np


def worker(nbytes, repeats, start, out):
    src = np.ones(nbytes // 8)
    dst = np.empty_like(src)
    np.copyto(dst, src)  # touch the pages before timing
    start.wait()
    t0 = time.perf_counter()
    for _ in range(repeats):
        np.copyto(dst, src)
    out.put(time.perf_counter() - t0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--workers", default="1,2,4,8,16")
    ap.add_argument("--mb", type=int, default=256)
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args()
    nbytes = a.mb << 20
    print(f"copy of {a.mb} MB per worker, {a.repeats} repeats, {mp.cpu_count()} CPUs")
    print("| workers | GB/s, all together | GB/s per worker | over 1 worker |")
    print("|---|---|---|---|")
    base = None
    for n in [int(w) for w in a.workers.split(",")]:
        start, out = mp.Barrier(n), mp.Queue()
        procs = [mp.Process(target=worker, args=(nbytes, a.repeats, start, out)) for _ in range(n)]
        for p in procs:
            p.start()
        slowest = max(out.get() for _ in procs)
        for p in procs:
            p.join()
        total = 2 * nbytes * a.repeats * n / slowest / 1e9
        base = base or total
        print(f"| {n} | {total:.1f} | {total / n:.1f} | {total / base:.2f}x |", flush=True)


if __name__ == "__main__":
    main()
