"""A sweep job that another attempt runs (the same sweep twice at once, a rerun while an earlier
cluster's jobs run, a lost worker's run still saving) is left to that attempt: not run, not
recorded, its files not removed; the temporaries of a save killed mid-way go with the job's
checkpoint; and the tool's messages about the job's checkpoint are recognised in a folder whose
path the tool escapes."""
import fcntl
import json
import os
import signal
import subprocess
import sys
import threading

import pytest

from shellcontract.sweep_progress import Progress
from test_sweep import results, run_sweep, sweep_env, wait_until, write_sweep

SHORT = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4}, "grid": {"pressure": [2, 3]}}
# One job of a few seconds (1 thread), saving every 5 frames.
LONG = {"meshes": ["meshes/ico3.off"], "options": {"frames": 6000, "threads": 1}}


def stopped_state(pid):
    """Whether /proc says the process is stopped (or gone: nothing more of it can happen)."""
    try:
        with open("/proc/{}/stat".format(pid)) as f:
            return f.read().rsplit(")", 1)[1].split()[0] in ("T", "t", "Z", "X")
    except (OSError, IndexError):
        return True


def sweep_command(**params):
    """A sweep's command, to which its arguments are added: sweep.main called with `params`, the
    timings the command line does not take (lock_wait, note_every), as keyword arguments."""
    return [sys.executable, "-c", "import sys; from shellcontract import sweep; "
            "sys.exit(sweep.main(sys.argv[1:], **{!r}))".format(params)]


def sweep_with(cli, args, env=None, **params):
    """run_sweep with the variables `env` added to its environment, and sweep.main's keyword
    arguments `params`."""
    return subprocess.run(sweep_command(**params) + args, env=dict(sweep_env(cli), **(env or {})),
                          capture_output=True, text=True, timeout=240)


def runs_saving_to(folder):
    """Pids of the tool's runs whose command line names `folder` (the job's checkpoints)."""
    pids = []
    for name in os.listdir("/proc"):
        try:
            with open("/proc/{}/cmdline".format(name), "rb") as f:
                args = f.read().split(b"\0")
        except OSError:
            continue
        if b"run" in args and any(str(folder).encode() in a for a in args):
            pids.append(int(name))
    return pids


def test_a_second_sweep_leaves_a_running_job_to_the_first(cli, mesh_dir, tmp_path):
    # Before: the second sweep's run met the first's checkpoint lock (exit 1), the job became a
    # final "bad usage", its running checkpoint was removed, the first sweep's "ok" was dropped,
    # and every later sweep skipped the job.
    path = write_sweep(tmp_path, mesh_dir, "long.json", LONG, meshes=("ico3.off",))
    out = tmp_path / "out"
    checkpoints = out / ".work" / "checkpoints"
    first = subprocess.Popen([sys.executable, "-m", "shellcontract.sweep", str(path), "-o",
                              str(out), "--shard", "0/1", "--checkpoint-every", "5"],
                             env=sweep_env(cli), stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE, text=True)
    stopped = []
    try:
        wait_until(lambda: list(checkpoints.glob("*.ckpt")) and runs_saving_to(checkpoints))
        # The first sweep's run is held still, so that it runs for as long as the second sweep
        # takes, on any machine.
        stopped = runs_saving_to(checkpoints)
        for pid in stopped:
            os.kill(pid, signal.SIGSTOP)
        # A file creation under way when the signal came completes before the run stops: list
        # the folder once every run is seen stopped (state T), not when kill() returns.
        wait_until(lambda: all(stopped_state(pid) for pid in stopped))
        before = sorted(p.name for p in checkpoints.iterdir())
        second = sweep_with(cli, [str(path), "-o", str(out), "--shard", "0/1"],
                            lock_wait=0.5)
        assert second.returncode == 3, second.stderr  # the job has no outcome yet
        assert "running elsewhere" in second.stderr and "bad usage" not in second.stderr, \
            second.stderr
        assert "0 done, 0 failed, 1 left" in second.stderr, second.stderr
        assert not (out / "jobs").exists() or not list((out / "jobs").iterdir())
        assert sorted(p.name for p in checkpoints.iterdir()) == before
        assert [r["status"] for r in results(out)] == ["running elsewhere"]
    finally:
        for pid in stopped:
            os.kill(pid, signal.SIGCONT)
    _, err = first.communicate(timeout=240)
    assert first.returncode == 0, err
    assert [r["status"] for r in results(out)] == ["ok"]
    assert list(checkpoints.iterdir()) == []
    third = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert third.returncode == 0 and "1 done already" in third.stderr, third.stderr


def hold_tool_lock(checkpoint):
    """The tool's lock of `checkpoint` (checkpoint_lock.hpp: flock on .<name>.lock beside it),
    as a run of the job holds it that outlived the sweep's own lock."""
    fd = os.open(os.path.join(os.path.dirname(checkpoint), "." + os.path.basename(checkpoint)
                              + ".lock"), os.O_RDWR | os.O_CREAT)
    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    return fd


def test_a_run_holding_the_tools_lock_is_waited_for_and_else_left_running(cli, mesh_dir, tmp_path):
    # Before: the tool's refusal (exit 1, "another shellcontract run is saving to this
    # checkpoint") made the job a final "bad usage", which every later sweep skipped.
    path = write_sweep(tmp_path, mesh_dir, "c.json", SHORT, meshes=("ico1.off",))
    out = tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    ids = [row["job"] for row in results(out)]
    for job in ids:
        (out / "jobs" / job / "job.json").unlink()  # both jobs to run again
    checkpoint = out / ".work" / "checkpoints" / (ids[0] + ".ckpt")
    fd = hold_tool_lock(str(checkpoint))
    try:
        r = sweep_with(cli, [str(path), "-o", str(out), "--shard", "0/1"],
                       lock_wait=1)
        assert r.returncode == 3, r.stderr
        assert [row["status"] for row in results(out)] == ["running elsewhere", "ok"], r.stderr
        assert "another shellcontract run is saving to this checkpoint" in r.stderr, r.stderr
        assert not (out / "jobs" / ids[0] / "job.json").exists()
        # Released within the wait (a stopped run that saved and ended): the job runs.
        threading.Timer(1.0, os.close, [fd]).start()
        r = sweep_with(cli, [str(path), "-o", str(out), "--shard", "0/1"],
                       lock_wait=60)
        fd = None
    finally:
        if fd is not None:
            os.close(fd)
    assert r.returncode == 0, r.stderr
    assert [row["status"] for row in results(out)] == ["ok", "ok"]
    assert list(checkpoint.parent.iterdir()) == []


# A save's temporary (src/mesh/file_safety.cpp, create_exclusive_file: "." + the file's name +
# ".tmp." + 12 letters or digits), as a run SIGKILLed during a checkpoint save leaves it.
def temporary(job):
    return ".{}.ckpt.tmp.AOzIkorZMtAV".format(job)


def test_a_done_jobs_save_temporaries_are_removed_and_nothing_else(cli, mesh_dir, tmp_path):
    # Before: only FILE, FILE.log and FILE.history were removed; a temporary as large as the
    # checkpoint stayed in DIR/.work/checkpoints for good.
    path = write_sweep(tmp_path, mesh_dir, "c.json", SHORT, meshes=("ico1.off",))
    out = tmp_path / "out"
    assert run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"]).returncode == 0
    ids = [row["job"] for row in results(out)]
    (out / "jobs" / ids[0] / "job.json").unlink()  # the first runs again, the second is done
    checkpoints = out / ".work" / "checkpoints"
    kept = [".{}.ckpt.tmp.short".format(ids[0]), ".{}.ckpt.tmp.AOzIkorZMtAV.x".format(ids[1]),
            temporary("0123456789abcdef"), "{}.ckpt.tmp.AOzIkorZMtAV".format(ids[0]), "notes.txt"]
    for name in kept + [temporary(ids[0]), temporary(ids[1])]:
        (checkpoints / name).write_bytes(b"a save's temporary")
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0 and "1 done already" in r.stderr, r.stderr
    assert sorted(p.name for p in checkpoints.iterdir()) == sorted(kept)


def test_a_done_jobs_files_stay_while_a_run_holds_the_tools_lock(cli, mesh_dir, tmp_path):
    # Before: a sweep that found the job done removed its checkpoint and files beside whatever
    # held them.
    path = write_sweep(tmp_path, mesh_dir, "c.json", SHORT, meshes=("ico1.off",))
    out = tmp_path / "out"
    assert run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"]).returncode == 0
    job = results(out)[0]["job"]
    checkpoint = out / ".work" / "checkpoints" / (job + ".ckpt")
    names = [job + ".ckpt", job + ".ckpt.log", job + ".ckpt.history", temporary(job)]
    for name in names:
        (checkpoint.parent / name).write_bytes(b"a run's")
    fd = hold_tool_lock(str(checkpoint))
    try:
        r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
        assert r.returncode == 0 and "2 done already" in r.stderr, r.stderr
        assert all((checkpoint.parent / name).exists() for name in names)
    finally:
        os.close(fd)
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    assert [p.name for p in checkpoint.parent.iterdir()] == ["." + job + ".ckpt.lock"]


def make_folder(tmp_path, name):
    return os.path.join(os.fsdecode(bytes(tmp_path)), os.fsdecode(name))


# Paths the tool writes otherwise than they are (printable(): a byte that is no UTF-8, a tab, and
# a path cut after 200 characters).
ESCAPED = [b"out\xe9", b"out\tx", b"d" * 160]


@pytest.mark.parametrize("name", ESCAPED, ids=["latin1", "tab", "long"])
def test_a_refused_checkpoint_is_recognised_in_a_folder_the_tool_escapes(cli, mesh_dir, tmp_path,
                                                                       name):
    # Before: the raw path was looked for in the tool's message, and the job was a final
    # "bad input".
    path = write_sweep(tmp_path, mesh_dir, "c.json", SHORT, meshes=("ico1.off",))
    out = make_folder(tmp_path, name)
    assert run_sweep(cli, [str(path), "-o", out, "--shard", "0/1"]).returncode == 0
    ids = [row["job"] for row in results(out)]
    os.remove(os.path.join(out, "jobs", ids[0], "job.json"))
    checkpoint = os.path.join(out, ".work", "checkpoints", ids[0] + ".ckpt")
    with open(checkpoint, "wb") as f:
        f.write(b"not a checkpoint")
    r = run_sweep(cli, [str(path), "-o", out, "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    assert [row["status"] for row in results(out)] == ["ok", "ok"], r.stderr
    with open(os.path.join(out, "jobs", ids[0], "job.json")) as f:
        assert json.load(f)["resumed"] is False
    with open(os.path.join(out, "jobs", ids[0], "messages.txt"), "rb") as f:
        assert b"checkpoint was refused (shellcontract run: checkpoint" in f.read()
    assert os.listdir(os.path.dirname(checkpoint)) == []


# The tool's messages when it cannot read the checkpoint or a file beside (file_safety.cpp's
# open_regular and read_regular_file, prefixed by checkpoint.cpp and checkpoint_log.cpp).
@pytest.mark.parametrize("tail,status", [
    (": cannot open file: input/output error (a failing disk?)", "checkpoint not read"),
    (": its log {ckpt}.log: cannot read file: Too many open files after 0 bytes (the checkpoint "
     "keeps the run's log in that file beside it: move or copy the checkpoint and its files beside "
     "together)", "checkpoint not read"),
    (": its log {ckpt}.log: cannot open file: no such file (the checkpoint keeps the run's log in "
     "that file beside it: move or copy the checkpoint and its files beside together)", "ok"),
], ids=["EIO", "EMFILE beside", "missing beside"])
def test_a_checkpoint_that_could_not_be_read_is_kept(cli, mesh_dir, tmp_path, tail, status):
    # Before: any exit 2 naming the checkpoint was a refusal: a checkpoint that a passing read
    # error kept from being read was removed, and the job ran from its first frame.
    fake = tmp_path / "fake_cli.sh"
    fake.write_text("#!/bin/sh\n"
                    "case \"$*\" in *--resume*)\n"
                    "  echo \"shellcontract run: checkpoint $CKPT$TAIL\" >&2; exit 2;;\n"
                    "esac\n"
                    "exec '{}' \"$@\"\n".format(cli))
    fake.chmod(0o755)
    path = write_sweep(tmp_path, mesh_dir, "c.json", SHORT, meshes=("ico1.off",))
    out = tmp_path / "out"
    assert run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"]).returncode == 0
    ids = [row["job"] for row in results(out)]
    (out / "jobs" / ids[0] / "job.json").unlink()
    checkpoint = out / ".work" / "checkpoints" / (ids[0] + ".ckpt")
    checkpoint.write_bytes(b"a checkpoint")
    r = sweep_with(cli, [str(path), "-o", str(out), "--shard", "0/1", "--cli", str(fake)],
                   env={"CKPT": str(checkpoint), "TAIL": tail.format(ckpt=checkpoint)})
    assert [row["status"] for row in results(out)] == [status, "ok"], r.stderr
    if status == "ok":  # refused: removed, and the job ran from its first frame
        assert r.returncode == 0 and not checkpoint.exists(), r.stderr
        return
    assert r.returncode == 3, r.stderr
    assert checkpoint.read_bytes() == b"a checkpoint"
    # The next sweep resumes from it (the tool refuses this one's contents: from frame 0).
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0 and [row["status"] for row in results(out)] == ["ok", "ok"], r.stderr
    assert "checkpoint was refused" in (out / "jobs" / ids[0] / "messages.txt").read_text()


def test_progress_counts_a_job_running_elsewhere_as_left():
    import io
    p = Progress(3, stream=io.StringIO(), tty=False)
    p.job_finished({"status": "running elsewhere", "message": "another attempt"}, "job 0")
    p.job_finished({"status": "ok"}, "job 1")
    assert (p.done, p.failed, p.left) == (1, 0, 2)


def test_a_lone_job_lock_of_a_done_job_is_removed_by_the_next_sweep(cli, mesh_dir, tmp_path):
    # A sweep killed after removing a done job's checkpoint files and before releasing its lock
    # leaves DIR/.work/checkpoints/<id>.lock alone. Before: no later sweep removed it (it was not
    # counted as one of the job's files).
    spec = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4}, "grid": {"pressure": [2, 3]}}
    path = write_sweep(tmp_path, mesh_dir, "c.json", spec, meshes=("ico1.off",))
    out = tmp_path / "out"
    assert run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"]).returncode == 0
    job = results(out)[0]["job"]
    (out / ".work" / "checkpoints" / (job + ".lock")).write_bytes(b"")
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0 and "2 done already" in r.stderr, r.stderr
    assert [p.name for p in (out / ".work" / "checkpoints").iterdir()] == []
