"""contract()'s checkpoints behave as the CLI's (docs/design/output-safety.md, "Two runs and one
checkpoint"; docs/design/sweeps.md, "Saving again after a resume"): a run holds the lock
`.FILE.lock` beside its checkpoint, so that a second run naming it, Python's or the CLI's, is
refused before any work; resume= without checkpoint= goes on saving to the file it resumed
from, as often as the interrupted run did. Before, contract() took no lock (two runs saved
into one file in turn) and a resumed run saved nothing; each test here failed then."""
import fcntl
import os
import shutil
import signal
import subprocess
import sys
import time

import pytest

import shellcontract

OPTIONS = dict(frames=30, pressure=0)
HELD = "another shellcontract run is saving to this checkpoint or resuming from it"


def stop_at(frame):
    return lambda f, v, m: f < frame  # False at `frame`: the run stops there


def lock_file(path):
    """Where the documented lock of checkpoint `path` is: `.NAME.lock` in its folder."""
    return path.parent / ("." + path.name + ".lock")


def checkpointed(v, f, path, every=4):
    r = shellcontract.contract(v, f, callback=stop_at(4), checkpoint=path, checkpoint_every=every,
                               **OPTIONS)
    assert r.status == "cancelled" and r.summary["frames_run"] == 4
    return r


def first_frame_after(v, f, path):
    """The frame a run resumed from `path` starts with (the one after the checkpoint's)."""
    seen = []
    shellcontract.contract(v, f, resume=path, callback=lambda fr, vv, m: seen.append(fr) or False)
    return seen[0]


def test_a_checkpoint_locked_by_another_run_is_refused_before_any_work(tmp_path, ico2):
    v, f = ico2
    path = tmp_path / "c.ckpt"
    checkpointed(v, f, path)
    before = path.read_bytes()
    # What another run holds while it saves there (the CLI's flock on the same file).
    fd = os.open(lock_file(path), os.O_RDWR | os.O_CREAT, 0o666)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        frames = []
        record = lambda fr, vv, m: frames.append(fr)  # noqa: E731
        for arguments in (dict(checkpoint=path), dict(resume=path),
                          dict(resume=path, checkpoint=tmp_path / "other.ckpt")):
            with pytest.raises(ValueError, match=HELD) as refused:
                shellcontract.contract(v, f, callback=record, **dict(OPTIONS, **arguments))
            assert str(path) in str(refused.value)
        assert frames == []  # no frame was run
        assert path.read_bytes() == before and not (tmp_path / "other.ckpt").exists()
    finally:
        os.close(fd)
    # Released: the same run goes on, and leaves no lock file.
    assert first_frame_after(v, f, path) == 5
    assert not lock_file(path).exists()


def test_a_run_holds_the_lock_against_the_cli_and_another_contract(cli, tmp_path, ico2, mesh_dir):
    v, f = ico2
    path = tmp_path / "c.ckpt"
    seen = {}
    command = [cli, "run", str(mesh_dir / "ico2.off"), "-o", str(tmp_path / "cli.off"), "-q",
               "--frames", "3", "--checkpoint", str(path)]

    def during_the_run(frame, vertices, metrics):
        if frame != 2:
            return None
        seen["lock file"] = lock_file(path).exists()
        seen["cli"] = subprocess.run(command, capture_output=True, text=True)
        try:
            shellcontract.contract(v, f, checkpoint=path, frames=3)
        except ValueError as e:
            seen["contract"] = str(e)
        return False

    shellcontract.contract(v, f, callback=during_the_run, checkpoint=path, checkpoint_every=1,
                           **OPTIONS)
    assert seen["lock file"]
    assert seen["cli"].returncode == 1, seen["cli"].stderr
    assert HELD in seen["cli"].stderr
    assert not (tmp_path / "cli.off").exists()
    assert HELD in seen.get("contract", "")
    # The checkpoint is this run's (stopped at frame 2), and the lock file went with the run.
    assert not lock_file(path).exists()
    assert first_frame_after(v, f, path) == 3
    again = subprocess.run(command, capture_output=True, text=True)
    assert again.returncode == 0, again.stderr


SLOW = """
import sys, shellcontract
v, f = shellcontract.read_mesh(sys.argv[1])
def started(frame, vertices, metrics):
    if frame == 1:
        print("running", flush=True)
shellcontract.contract(v, f, frames=1000000, pressure=0, checkpoint=sys.argv[2], callback=started)
"""


def test_sigterm_ends_a_python_process_without_leaving_its_lock_file(tmp_path, mesh_dir):
    # In a Python process SIGTERM keeps its default action (the process ends by it); the
    # library's handler removes the lock file on the way, as it does its temporaries.
    path = tmp_path / "c.ckpt"
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.dirname(os.path.dirname(shellcontract.__file__)) + os.pathsep + \
        env.get("PYTHONPATH", "")
    proc = subprocess.Popen([sys.executable, "-c", SLOW, str(mesh_dir / "ico2.off"), str(path)],
                            env=env, stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline() == "running\n"
        assert lock_file(path).exists()
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=30) == -signal.SIGTERM
        assert not lock_file(path).exists()
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


@pytest.mark.parametrize("every,saved", [(None, 8), (3, 9)], ids=["the checkpoint's", "given"])
def test_resume_goes_on_saving_to_the_checkpoint_it_resumed_from(tmp_path, ico2, every, saved):
    """Before: nothing saved after the resume (the file still held frame 4)."""
    v, f = ico2
    path = tmp_path / "c.ckpt"
    checkpointed(v, f, path, every=4)
    copy = tmp_path / "copy.ckpt"

    def copy_at_10(frame, vertices, metrics):
        if frame == 10:
            # What the file held at frame 10: the last periodic save, with the log and volume
            # history it keeps beside it (copied with it, as a checkpoint is).
            for suffix in ("", ".log", ".history"):
                if os.path.exists(str(path) + suffix):
                    shutil.copyfile(str(path) + suffix, str(copy) + suffix)
            return False
        return None

    extra = {} if every is None else dict(checkpoint_every=every)
    r = shellcontract.contract(v, f, resume=path, callback=copy_at_10, **extra)
    assert r.status == "cancelled"
    assert first_frame_after(v, f, copy) == saved + 1
    # The stop saved too, as a signal does, and no lock file is left.
    assert first_frame_after(v, f, path) == 11
    assert not lock_file(path).exists()



def test_a_resume_of_a_checkpoint_held_is_refused_as_held_before_it_is_read(tmp_path, ico2):
    """resume= reads the checkpoint under its lock: the run holding it may be saving there, and
    its save that holds the log itself removes the files beside. Here they are gone while the
    lock is held: each resume is refused as held, naming the checkpoint as before. Before, the
    checkpoint was read first, and a missing file beside was the error (a FileNotFoundError,
    "its volume history ...: cannot open file"), the lock never reached."""
    v, f = ico2
    path = tmp_path / "c.ckpt"
    checkpointed(v, f, path, every=2)  # saves at frames 2 and 4: the log beside (format 5)
    assert os.path.exists(str(path) + ".log")
    fd = os.open(lock_file(path), os.O_RDWR | os.O_CREAT, 0o666)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        os.remove(str(path) + ".log")
        os.remove(str(path) + ".history")
        for arguments, option in ((dict(resume=path), "resume"),
                                  (dict(resume=path, checkpoint=path), "checkpoint"),
                                  (dict(resume=path, checkpoint=tmp_path / "d.ckpt"), "resume")):
            with pytest.raises(BlockingIOError, match=HELD) as refused:
                shellcontract.contract(v, f, **arguments)
            assert str(refused.value).startswith("%s '%s'" % (option, path)), refused.value
        assert not (tmp_path / "d.ckpt").exists()
    finally:
        os.close(fd)
    os.remove(lock_file(path))
    # Released: the checkpoint is read, and refused for a missing file beside.
    with pytest.raises(FileNotFoundError, match="its (volume history|log)"):
        shellcontract.contract(v, f, resume=path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.ckpt"]
