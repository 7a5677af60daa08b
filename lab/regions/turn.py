#!/usr/bin/python3
"""The rest's rigid turn in a run with the automatic regions (lab/regions/turn.md): runs `run MESH
--regions auto -p 0 -n N`, then fits the best rotation (Kabsch, unweighted) of the vertices outside
the regions and their one-ring band from rest to the end, and prints its angle, the rest's mean
displacement / diagonal, and that displacement after the rigid fit.

Usage: /usr/bin/python3 lab/regions/turn.py BUILD_DIR/shellcontract MESH N
"""
import sys, os, subprocess, numpy as np, tempfile
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__))); import common, sink
exe = sys.argv[1]; name = sys.argv[2]; n = sys.argv[3]
path = common.mesh_path(name); rest, faces = common.read_off(path)
with tempfile.TemporaryDirectory() as tmp:
    regions, _, _ = common.auto_regions(exe, path, tmp)
    subprocess.run([exe, "run", path, "--regions", "auto", "-p", "0", "-n", n, "-o", tmp + "/o.off", "-q"], check=True)
    end = common.read_off(tmp + "/o.off")[0]
inr = np.zeros(len(rest), bool)
for r in regions: inr[faces[r].ravel()] = True
band = inr.copy(); band[faces[inr[faces].any(1)].ravel()] = True
P, Q = rest[~band], end[~band]
cp, cq = P.mean(0), Q.mean(0)
u, s, vt = np.linalg.svd((P - cp).T @ (Q - cq)); d = np.sign(np.linalg.det(vt.T @ u.T))
R = vt.T @ np.diag([1, 1, d]) @ u.T
ang = np.degrees(np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1)))
diag = np.linalg.norm(rest.max(0) - rest.min(0))
raw = np.linalg.norm(Q - P, axis=1).mean() / diag
fit = np.linalg.norm((P - cp) @ R.T + cq - Q, axis=1).mean() / diag
print(f"{name} n={n}: turn {ang:.3f} deg, rest raw {raw:.5f}, after rigid fit {fit:.5f}")
