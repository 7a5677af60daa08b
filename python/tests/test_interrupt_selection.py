"""Ctrl-C while contract() selects its regions (regions="auto" on a large mesh): the run stops in
its preparation and KeyboardInterrupt is raised. The signal is sent once the finder's first stage
has ended (SC_REGION_TIMING's "region timing: curvature" line on stderr), so that it lands in the
smoothing of a mesh of 327680 faces: no sleep decides when."""
import os
import signal
import subprocess
import sys

import numpy as np

import shellcontract

CHILD = r"""
import sys
import shellcontract
v, f = shellcontract.read_mesh(sys.argv[1])
try:
    r = shellcontract.contract(v, f, frames=5, regions="auto")
except KeyboardInterrupt:
    print("KeyboardInterrupt", flush=True)
    sys.exit(3)
print("finished", r.status, flush=True)
"""


def split_in_four(v, f):
    """Each triangle into four at its edges' midpoints (a vertex per edge, shared)."""
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    mid = len(v) + inverse.reshape(3, -1).T  # per face: ab, bc, ca
    ab, bc, ca = mid[:, 0], mid[:, 1], mid[:, 2]
    a, b, c = f[:, 0], f[:, 1], f[:, 2]
    vertices = np.vstack([v, 0.5 * (v[unique[:, 0]] + v[unique[:, 1]])])
    faces = np.concatenate([np.stack(t, axis=1) for t in ((a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca))])
    return vertices, faces


def test_ctrl_c_during_the_region_selection_raises_keyboard_interrupt(tmp_path, mesh_dir):
    v, f = shellcontract.read_mesh(mesh_dir / "bumpy_sphere.off")
    for _ in range(4):
        v, f = split_in_four(v, f)
    assert len(f) == 327680
    mesh = tmp_path / "bumpy_x256.off"
    shellcontract.write_mesh(mesh, v, f)
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(mesh)], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True,
                             env=dict(os.environ, SC_REGION_TIMING="1"))
    try:
        seen = ""
        for line in child.stderr:
            seen += line
            if line.startswith("region timing: curvature"):
                break
        else:
            raise AssertionError("no curvature line: " + seen)
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=300)
    finally:
        child.kill()
        child.wait()
    assert child.returncode == 3, out + seen + err
    assert out == "KeyboardInterrupt\n"
    # The selection stopped: its later stages printed no line.
    assert "region timing: smoothing" not in err, err
