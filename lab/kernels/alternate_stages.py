#!/usr/bin/python3
"""Bear, 60 frames (or FRAMES), with several binaries in turn, ROUNDS times, at a given thread count: the
medians of the collision step's stages and of collision / solve (ms per step, the summary's
table2). lab/kernels/alternate_collision.py's measure for more than two binaries and for one
thread (collision_coherence.md, section 8).

Usage: /usr/bin/python3 lab/kernels/alternate_stages.py BIN1,BIN2[,...] ROUNDS [THREADS=1] [MESH] [FRAMES=60]
Copy the binaries to a stable folder first (a rebuild during the sitting would change them).
"""
import json
import os
import statistics as st
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
KEYS = ['step_ms', 'collision_ms_per_step', 'constraint_solve_ms_per_step', 'broad_phase_ms_per_step',
        'broad_phase_grid_ms_per_step', 'broad_phase_cell_loop_ms_per_step',
        'broad_phase_pair_output_ms_per_step', 'filter_ms_per_step']


def main():
    bins = sys.argv[1].split(',')
    rounds = int(sys.argv[2])
    threads = sys.argv[3] if len(sys.argv) > 3 else "1"
    mesh = sys.argv[4] if len(sys.argv) > 4 else os.path.join(HERE, '..', '..', 'data', 'meshes', 'bear.off')
    frames = sys.argv[5] if len(sys.argv) > 5 else "60"
    res = {b: {k: [] for k in KEYS} for b in bins}
    with tempfile.TemporaryDirectory() as tmp:
        out, summary = os.path.join(tmp, 'out.off'), os.path.join(tmp, 'summary.json')
        for _ in range(rounds):
            for b in bins:
                subprocess.run([b, 'run', mesh, '-o', out, '-q', '--threads', threads, '-n', frames,
                                '--summary', summary], check=True, stderr=subprocess.DEVNULL)
                t = json.load(open(summary))['table2']
                for k in KEYS:
                    res[b][k].append(t[k])
    for b in bins:
        r = res[b]
        ratio = st.median([c / s for c, s in zip(r['collision_ms_per_step'], r['constraint_solve_ms_per_step'])])
        print(b, ' '.join(f"{k.replace('_ms_per_step', '').replace('broad_phase_', 'bp_')}={st.median(r[k]):.3f}"
                          for k in KEYS), 'coll/solve=%.3f' % ratio)


if __name__ == '__main__':
    main()
