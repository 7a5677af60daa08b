"""read_mesh and write_mesh let other Python threads run while they read, check and write (they
release the GIL around the library's work, as contract() and regions() do). Before, they held
it: a program reading meshes in a worker thread froze its user interface for the whole read.
Every call that takes arrays (contract, check, regions, write_mesh) lets them run while the
library builds and checks the mesh from them too: before, it held the GIL for that part.

The test counts the turns of another Python thread while the call runs, not durations: with the
interpreter's switch interval made longer than any call here, a thread holding the GIL is never
made to give it up, so the count cannot move unless the call releases it (exactly 0 before)."""
import sys
import threading
import time

import numpy as np
import pytest

import shellcontract as sc

# Long enough to give the counting thread its turns on a loaded machine; read_mesh takes a
# fraction of a second on it.
TORUS_SIZE = 250
# Far above a call's duration: a switch forced during the call would be taken right after it
# returns, and could be counted as a turn during it.
SWITCH_INTERVAL_S = 60.0


def torus(n, m, big=1.0, small=0.4):
    """A closed genus-1 triangle mesh on an n by m grid."""
    u = np.arange(n) * 2 * np.pi / n
    v = np.arange(m) * 2 * np.pi / m
    uu, vv = np.meshgrid(u, v, indexing="ij")
    ring = big + small * np.cos(vv)
    vertices = np.stack([ring * np.cos(uu), ring * np.sin(uu), small * np.sin(vv)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    a, b = i * m + j, (i + 1) % n * m + j
    c, d = (i + 1) % n * m + (j + 1) % m, i * m + (j + 1) % m
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return vertices, faces


@pytest.fixture(scope="module")
def big_mesh(tmp_path_factory):
    vertices, faces = torus(TORUS_SIZE, TORUS_SIZE)
    path = tmp_path_factory.mktemp("io_threads") / "torus.off"
    with open(path, "w") as f:  # written by numpy, not by the function under test
        f.write("OFF\n{} {} 0\n".format(len(vertices), len(faces)))
        np.savetxt(f, vertices, fmt="%.17g")
        np.savetxt(f, np.hstack([np.full((len(faces), 1), 3), faces]), fmt="%d")
    return path, vertices, faces


def turns_of_another_thread_during(call, attempts=3):
    """How many turns a counting Python thread took while `call()` ran, over up to `attempts`
    calls (stopping at the first that lets it run)."""
    state = {"count": 0, "stop": False}
    started = threading.Event()

    def count():
        started.set()
        while not state["stop"]:
            state["count"] += 1
            time.sleep(0.0002)  # gives the GIL back, so that this thread can start its calls

    old = sys.getswitchinterval()
    sys.setswitchinterval(SWITCH_INTERVAL_S)
    counter = threading.Thread(target=count, daemon=True)
    during = 0
    try:
        counter.start()
        started.wait()
        for _ in range(attempts):
            before = state["count"]
            call()
            during += state["count"] - before
            if during > 0:
                break
    finally:
        state["stop"] = True
        counter.join()
        sys.setswitchinterval(old)
    return during


def test_read_mesh_lets_other_threads_run(big_mesh):
    path, vertices, faces = big_mesh
    read = []
    assert turns_of_another_thread_during(lambda: read.append(sc.read_mesh(path))) > 0
    v, f = read[0]
    assert v.shape == vertices.shape and f.shape == faces.shape


def test_write_mesh_lets_other_threads_run(big_mesh, tmp_path):
    path, vertices, faces = big_mesh
    out = tmp_path / "out.off"
    assert turns_of_another_thread_during(lambda: sc.write_mesh(out, vertices, faces)) > 0
    v, f = sc.read_mesh(out)
    np.testing.assert_array_equal(v, vertices)


def test_the_check_of_arrays_lets_other_threads_run(big_mesh):
    """The arrays' check alone: a duplicate of the first face, appended last, is refused after
    the whole check has run, so that the call does nothing else (before, no turn at all)."""
    _, vertices, faces = big_mesh
    doubled = np.vstack([faces, faces[:1]])
    errors = []

    def call(function):
        def run():
            try:
                function(vertices, doubled)
            except sc.MeshError as e:
                errors.append(e)
        return run

    for function in (sc.check, sc.regions, lambda v, f: sc.contract(v, f, frames=1)):
        errors.clear()
        assert turns_of_another_thread_during(call(function)) > 0
        assert errors and len(faces) in errors[-1].faces, errors
