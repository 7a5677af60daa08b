"""The temporaries through which the sweep rewrites its tables (sweep_output.write_atomic): one
that a sweep killed with SIGKILL while writing left in DIR is removed by the next sweep of the
folder, and only such a one: named as the sweep names them, this user's, no other file's name,
not new, and locked by no process (a shard writing its table holds the lock); a sweep stopped by
Ctrl-C or SIGTERM removes its own. Before, each killed write left a temporary (as large as the
table) for good."""
import fcntl
import os
import signal
import subprocess
import sys
import time
import uuid

import pytest

from shellcontract import sweep_output

from test_sweep import results, run_sweep, sweep_env, write_sweep

pytest.importorskip("distributed")

SPEC = {"meshes": ["meshes/ico1.off"], "options": {"frames": 2}}
OLD = time.time() - 3600


def temporary(out, table="results.csv", text="job,status\n", old=True):
    p = out / "{}.tmp-{}".format(table, uuid.uuid4().hex)
    p.write_text(text)
    if old:
        os.utime(p, (OLD, OLD))
    return p


def test_a_later_sweep_removes_the_stale_temporaries_and_only_those(cli, mesh_dir, tmp_path):
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    out = tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    stale = [temporary(out), temporary(out, "results.json")]
    held = temporary(out, "results.json")  # another shard writing its table right now
    fresh = temporary(out, old=False)  # an earlier version's writer, which took no lock
    mine = tmp_path / "mine.txt"
    mine.write_text("the user's own\n")
    linked = out / "results.csv.tmp-{}".format(uuid.uuid4().hex)
    os.link(mine, linked)
    os.utime(linked, (OLD, OLD))
    others = [out / "results.csv.tmp-mine", out / "notes.csv.tmp-{}".format(uuid.uuid4().hex)]
    for p in others:
        p.write_text("the user's own\n")
        os.utime(p, (OLD, OLD))
    link = out / "results.csv.tmp-{}".format(uuid.uuid4().hex)
    link.symlink_to(mine)
    kept = [held, fresh, linked, link] + others
    if os.geteuid() == 0:
        theirs = temporary(out)
        os.chown(theirs, 1, 1)
        kept.append(theirs)
    with open(held, "r+") as f:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX)
        r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    assert "removed 2 temporary files of the results tables that a killed sweep left in {}".format(
        out) in r.stderr
    assert not [p for p in stale if os.path.lexists(p)]
    assert [p for p in kept if os.path.lexists(p)] == kept
    assert mine.read_text() == "the user's own\n" and len(results(out)) == 1


WRITER = """
import os, sys, time
from shellcontract import sweep_output
os.replace = lambda a, b: (print("writing", flush=True), time.sleep(600))
sweep_output.write_atomic(sys.argv[1], "job,status\\n" * 1000)
"""


@pytest.mark.parametrize("stop", [signal.SIGKILL, signal.SIGINT])
def test_a_writer_holds_its_temporary_until_it_is_gone(cli, tmp_path, monkeypatch, stop):
    """A table's writer stopped while its temporary is there (before the rename): while it lives
    its temporary is never removed, old or not; killed (SIGKILL), it leaves it unlocked, and the
    next sweep removes it; stopped by Ctrl-C, it removes it itself."""
    monkeypatch.setattr(sweep_output, "STALE_TEMPORARY_SECONDS", 0.0)
    table = tmp_path / "results.csv"
    writer = subprocess.Popen([sys.executable, "-c", WRITER, str(table)], env=sweep_env(cli),
                              stdout=subprocess.PIPE, text=True)
    try:
        assert writer.stdout.readline() == "writing\n"
        left = [p for p in tmp_path.iterdir() if p.name.startswith("results.csv.tmp-")]
        assert len(left) == 1
        assert sweep_output.remove_stale_temporaries(str(tmp_path)) == 0
        assert left[0].exists()
        writer.send_signal(stop)
        writer.wait(timeout=60)
    finally:
        if writer.poll() is None:
            writer.kill()
            writer.wait()
    if stop == signal.SIGINT:
        assert not left[0].exists()
        return
    assert left[0].exists()
    assert sweep_output.remove_stale_temporaries(str(tmp_path)) == 1
    assert not left[0].exists() and not table.exists()
