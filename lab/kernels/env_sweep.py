#!/usr/bin/python3
"""Bear's default run (200 frames, 2 threads) with a binary built with broad_phase_env.patch, an
environment switch of that patch set to each value in turn, ROUNDS rounds: the medians of the
broad phase's stages, the pairs it emits and the solve (ms per step, the summary's table2).
collision_coherence.md, section 13.

  SC_CELL_FACTOR=F   the grid's cell size over the median box extent (GRID_CELL_FACTOR, 3)
  SC_GROW=G          every swept box grown by G more (normalized units) on each side: what the
                     grid of a Verlet list with margin G would cost to build

Usage: /usr/bin/python3 lab/kernels/env_sweep.py BIN VAR V1,V2,... ROUNDS [THREADS=2] [FRAMES=200]
"""
import json
import os
import statistics as st
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
KEYS = ['collision_ms_per_step', 'constraint_solve_ms_per_step', 'broad_phase_ms_per_step',
        'broad_phase_grid_ms_per_step', 'broad_phase_cell_loop_ms_per_step',
        'broad_phase_pair_output_ms_per_step', 'broad_phase_records_ms_per_step',
        'pairs_after_broad_phase_per_step']


def main():
    exe, var, values, rounds = sys.argv[1], sys.argv[2], sys.argv[3].split(','), int(sys.argv[4])
    threads = sys.argv[5] if len(sys.argv) > 5 else '2'
    frames = sys.argv[6] if len(sys.argv) > 6 else '200'
    mesh = os.path.join(HERE, '..', '..', 'data', 'meshes', 'bear.off')
    res = {v: {k: [] for k in KEYS} for v in values}
    with tempfile.TemporaryDirectory() as tmp:
        out, summary = os.path.join(tmp, 'out.off'), os.path.join(tmp, 'summary.json')
        for _ in range(rounds):
            for v in values:
                subprocess.run([exe, 'run', mesh, '-o', out, '-q', '--threads', threads, '-n', frames,
                                '--summary', summary], check=True, env=dict(os.environ, **{var: v}))
                t = json.load(open(summary))['table2']
                for k in KEYS:
                    res[v][k].append(t[k])
    names = [k.replace('_per_step', '').replace('broad_phase_', 'bp ') for k in KEYS]
    print(f'| {var} | ' + ' | '.join(names) + ' |')
    print('|---' * (len(KEYS) + 1) + '|')
    for v in values:
        print(f'| {v} | ' + ' | '.join(f'{st.median(res[v][k]):.2f}' for k in KEYS) + ' |')


if __name__ == '__main__':
    main()
