#!/usr/bin/env python3
"""Turns the lines 'target-volume MESH R=..: ...' that tests/long/test_target_volume_grid.cpp prints
into the markdown table of lab/pages/target-volume.md (stdin to stdout)."""
import re
import sys

print("| mesh | R | frame reached | worst \\|V/V0 - R\\| over frames 351-400 | V/V0 at frame 400 | wall s |")
print("|---|---:|---:|---:|---:|---:|")
pattern = re.compile(r"target-volume (\S+) R=([\d.]+): frame reached (-?\d+), worst \|V/V0-R\| over the "
                     r"last 50 frames (\S+), final (\S+), (\S+) s")
for line in sys.stdin:
    m = pattern.match(line)
    if m:
        mesh, r, reached, worst, final, wall = m.groups()
        reached = reached if int(reached) >= 0 else "not within 0.005"
        print(f"| {mesh} | {r} | {reached} | {float(worst):.2g} | {float(final):.4f} | {float(wall):.1f} |")
