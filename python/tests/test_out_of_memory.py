"""Memory running out while a mesh file is read: MemoryError naming the file, with the CLI's
message (its exit code 3), not the ValueError of a file refused for its content. Each limit in a
child process of its own: the address space (RLIMIT_AS) held to what the process has plus a
headroom, stepped up from none until the file is read; where the reader's own allocations fail
depends on the machine, hence the steps."""
import os
import subprocess
import sys

import pytest

CHILD = r"""
import resource, sys
import shellcontract

def address_space():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    return -1

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


def test_reading_a_mesh_without_the_memory_raises_memory_error(mesh_dir):
    if not os.path.exists("/proc/self/status"):
        pytest.skip("no /proc/self/status")
    path = str(mesh_dir / "bumpy_sphere.off")
    reader_said = []
    for kib in range(0, 256 * 1024, 256):
        out = subprocess.run([sys.executable, "-c", CHILD, path, str(kib)], capture_output=True,
                             text=True, timeout=120, env=os.environ).stdout.strip()
        if out == "read":
            break
        assert not out.startswith("ValueError"), (kib, out)
        if out.startswith("MemoryError: " + path + ": out of memory: reading it needs more memory"):
            reader_said.append(out)
    else:
        pytest.fail("not read with 256 MiB of headroom")
    assert reader_said, "no limit ran out while the file was read"
