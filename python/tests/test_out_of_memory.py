"""Memory running out while a mesh file is read: MemoryError naming the file, with the CLI's
message (its exit code 3), not the ValueError of a file refused for its content. Each limit in a
child process of its own: the address space (RLIMIT_AS) held to what the process has plus a
headroom, stepped up from none until the file is read; where the reader's own allocations fail
depends on the machine, hence the steps."""
import os
import subprocess
import sys

import numpy as np
import pytest

import shellcontract

ADDRESS_SPACE = r"""
import resource, sys
import shellcontract

def address_space():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    return -1
"""

CHILD = ADDRESS_SPACE + r"""
path, headroom = sys.argv[1], int(sys.argv[2]) * 1024
soft, hard = resource.getrlimit(resource.RLIMIT_AS)
resource.setrlimit(resource.RLIMIT_AS, (address_space() + headroom, hard))
try:
    shellcontract.read_mesh(path)
    outcome = None
except BaseException as e:  # reported once the limit is lifted: a message needs memory too
    outcome = e
resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
print("read" if outcome is None else "{}: {}".format(type(outcome).__name__, outcome))
"""


def subdivided_sphere(path, v, f, levels):
    """`v`, `f` (a sphere) split `levels` times at the edges' midpoints, pushed onto the unit
    sphere, written as OFF."""
    for _ in range(levels):
        edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
        unique, index = np.unique(edges, axis=0, return_inverse=True)
        mid = v[unique].mean(axis=1)
        v = np.vstack([v, mid])
        m = (len(v) - len(mid) + index.reshape(3, -1)).T  # the midpoints of edges 01, 12, 20
        f = np.vstack([np.c_[f[:, 0], m[:, 0], m[:, 2]], np.c_[f[:, 1], m[:, 1], m[:, 0]],
                       np.c_[f[:, 2], m[:, 2], m[:, 1]], m])
        v = v / np.linalg.norm(v, axis=1)[:, None]
    with open(path, "w") as out:
        out.write("OFF\n{} {} 0\n".format(len(v), len(f)))
        out.writelines("{!r} {!r} {!r}\n".format(*p) for p in v.tolist())
        out.writelines("3 {} {} {}\n".format(*t) for t in f.tolist())


def big_sphere(mesh_dir, tmp_path):
    """ico3 split twice (20,480 faces), written as OFF: reading or running it needs more than the
    memory the interpreter and the module leave free after their import (bumpy_sphere's 1,280
    faces were read with no headroom at all once the module's start-up grew, and the test saw no
    limit run out). Skips where there is no /proc/self/status to measure the headroom from."""
    if not os.path.exists("/proc/self/status"):
        pytest.skip("no /proc/self/status")
    v, f = shellcontract.read_mesh(str(mesh_dir / "ico3.off"))
    path = str(tmp_path / "ico5.off")
    subdivided_sphere(path, np.asarray(v, dtype=float), np.asarray(f), 2)
    return path


def reports_until(child, path, done, headrooms_kib):
    """What `child` (run on `path` with each headroom in KiB, a process each) printed before it
    printed `done`, as (headroom, report) pairs; fails the test if it never did."""
    said = []
    for kib in headrooms_kib:
        out = subprocess.run([sys.executable, "-c", child, path, str(kib)], capture_output=True,
                             text=True, timeout=120, env=os.environ).stdout.strip()
        if out == done:
            return said
        said.append((kib, out))
    pytest.fail("'{}' not printed with {} KiB of headroom".format(done, headrooms_kib[-1]))


def test_reading_a_mesh_without_the_memory_raises_memory_error(mesh_dir, tmp_path):
    path = big_sphere(mesh_dir, tmp_path)
    said = reports_until(CHILD, path, "read", range(0, 256 * 1024, 256))
    for kib, out in said:
        assert not out.startswith("ValueError"), (kib, out)
    reader_said = [out for _, out in said if out.startswith(
        "MemoryError: " + path + ": out of memory: reading it needs more memory")]
    assert reader_said, "no limit ran out while the file was read"


CONTRACT_CHILD = ADDRESS_SPACE + r"""
import numpy as np

v, f = shellcontract.read_mesh(sys.argv[1])
v, f = np.asarray(v), np.asarray(f)
headroom = int(sys.argv[2]) * 1024
soft, hard = resource.getrlimit(resource.RLIMIT_AS)
resource.setrlimit(resource.RLIMIT_AS, (address_space() + headroom, hard))
try:
    shellcontract.contract(v, f, frames=2, threads=1)
    outcome = None
except BaseException as e:
    outcome = e
resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
print("ran" if outcome is None else "{}: {}".format(type(outcome).__name__, outcome))
"""


def test_contract_without_the_memory_says_what_it_was_doing(mesh_dir, tmp_path):
    """contract() on a mesh it cannot hold: a MemoryError saying what the run was doing and on
    how many vertices and faces, never pybind11's bare "std::bad_alloc" (a caller told only that
    cannot know whether its mesh or its own program is too large)."""
    path = big_sphere(mesh_dir, tmp_path)
    said = reports_until(CONTRACT_CHILD, path, "ran", range(0, 512 * 1024, 2 * 1024))
    for kib, out in said:
        assert out.startswith("MemoryError: out of memory while "), (kib, out)
    assert any("(10242 vertices, 20480 faces)" in out for _, out in said), said
