#!/usr/bin/python3
"""How long a Verlet list of the broad phase would last on the default run's own steps
(collision_coherence.md, section 13).

Reads the frames of `shellcontract run data/meshes/bear.off -o D/out.off -q --export-dir D/fr
--export-every 1` (one step per frame). A list built at step t0 with margin g holds the pairs of
the swept boxes grown by g; a vertex has left it at step t when its start or end position has
moved more than g (largest coordinate) from the start or end position of step t0 (then its swept
box may leave its grown box). Escaped vertices are queried on their own (section 2) until more
than a given share has escaped; then the list is rebuilt. Prints, per margin (in mean edges of
the input) and share: the builds over the 200 steps, the mean life of the lists built in the
first 40 steps and after, and the escaped vertices per step.

Usage: /usr/bin/python3 lab/kernels/verlet_lifetime.py D/fr
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from motion_per_step import read_frames  # noqa: E402


def main():
    x, edge = read_frames(sys.argv[1])
    nv, steps = x.shape[1], x.shape[0] - 1
    print("| margin (mean edges) | rebuild when escaped > | builds | mean life, built in steps 0-39 | after | escaped vertices per step |")
    print("|---|---|---|---|---|---|")
    for g in (0.05, 0.1, 0.2, 0.3):
        for share in (0.01, 0.05):
            t, lives, escaped = 0, [], 0
            while t < steps:
                t0, life = t, 0
                while t < steps:
                    moved = np.maximum(np.abs(x[t] - x[t0]).max(1), np.abs(x[t + 1] - x[t0 + 1]).max(1))
                    n = int((moved > g * edge).sum())
                    if t > t0 and n > share * nv:
                        break
                    escaped += n
                    t, life = t + 1, life + 1
                lives.append((t0, life))
            early = [k for s, k in lives if s < 40]
            late = [k for s, k in lives if s >= 40]
            print(f"| {g} | {share:.0%} | {len(lives)} | {np.mean(early):.1f} | {np.mean(late):.1f} | {escaped / steps:.0f} |")


if __name__ == "__main__":
    main()
