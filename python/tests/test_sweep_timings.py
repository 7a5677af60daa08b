"""The sweep's two timings, how long a job's attempt waits for another attempt that holds the
job's lock (lock_wait, 15 s) and how often a sweep on a cluster without workers says so again
(note_every, 60 s), are keyword arguments of shellcontract.sweep.main, checked, and sent with
each job to its worker. No environment variable changes them: they were read from
SHELLCONTRACT_TEST_* variables, one of them when the package's sweep was imported."""
import math
import os
import re
import subprocess
import sys
import threading

import pytest

import shellcontract
from shellcontract import sweep, sweep_job
from test_sweep import results, run_sweep, sweep_env, wait_until, write_sweep
from test_sweep_lock import SHORT, hold_tool_lock, sweep_with

# The variables the sweep used to read, with values it could not take as numbers.
OLD_HOOKS = {"SHELLCONTRACT_TEST_WAIT_NOTE_S": "garbage",
             "SHELLCONTRACT_TEST_JOB_LOCK_WAIT_S": "garbage"}


def logging_cli(tmp_path, cli):
    """A stand-in executable that runs the real one, then notes the call and its exit code in
    calls.txt (after the run: a line says the run was refused, not only started)."""
    fake = tmp_path / "logging_cli.sh"
    fake.write_text("#!/bin/sh\n'{}' \"$@\"\nrc=$?\necho \"$* -> $rc\" >> '{}'\nexit $rc\n".format(
        cli, tmp_path / "calls.txt"))
    fake.chmod(0o755)
    return fake


def runs_of(tmp_path, job):
    """The lines of calls.txt of `run`s of the job (its checkpoint is on the command line)."""
    try:
        lines = (tmp_path / "calls.txt").read_text().splitlines()
    except FileNotFoundError:
        return []
    return [line for line in lines if line.startswith("run ") and job + ".ckpt " in line]


def one_job_to_run_again(cli, mesh_dir, tmp_path):
    """A finished sweep of two jobs whose first is to run again: (the sweep file, DIR, the
    first job's id, that job's checkpoint path, which a run's lock covers)."""
    path = write_sweep(tmp_path, mesh_dir, "c.json", SHORT, meshes=("ico1.off",))
    out = tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    job = results(out)[0]["job"]
    (out / "jobs" / job / "job.json").unlink()
    return path, out, job, out / ".work" / "checkpoints" / (job + ".ckpt")


def test_the_old_variables_do_not_break_the_sweep(cli):
    # Before: SHELLCONTRACT_TEST_WAIT_NOTE_S was read when sweep_progress was imported, so a value
    # that is no number made `import shellcontract.sweep`, and every `shellcontract sweep`, a
    # traceback (exit 1).
    env = dict(sweep_env(cli), **OLD_HOOKS)
    r = subprocess.run([sys.executable, "-c", "import shellcontract.sweep as s; print("
                        "s.sweep_progress.WAIT_NOTE_SECONDS, s.sweep_job.JOB_LOCK_WAIT_SECONDS)"],
                       env=env, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["60.0", "15.0"]  # the documented defaults
    r = subprocess.run([cli, "sweep", "--help"], env=env, capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 0 and "SWEEP.json" in r.stdout, r.stderr


def test_no_module_of_the_package_reads_a_test_variable():
    # The package as it ships (the build's copy, which the tests import).
    folder = os.path.dirname(shellcontract.__file__)
    readers = [name for name in sorted(os.listdir(folder)) if name.endswith(".py")
               and "SHELLCONTRACT_TEST" in open(os.path.join(folder, name)).read()]
    assert readers == []


def test_the_environment_does_not_shorten_the_lock_wait(cli, mesh_dir, tmp_path):
    # Before: SHELLCONTRACT_TEST_JOB_LOCK_WAIT_S=0, in any environment the sweep inherited, made a
    # job whose run met another run's lock `running elsewhere` at once. The other run ends here
    # right after the job's first run was refused: within the wait, so the job runs.
    path, out, job, checkpoint = one_job_to_run_again(cli, mesh_dir, tmp_path)
    fake = logging_cli(tmp_path, cli)
    fd = hold_tool_lock(str(checkpoint))

    def release_once_refused():
        try:
            wait_until(lambda: any(line.endswith("-> 1") for line in runs_of(tmp_path, job)),
                       timeout=200)
        finally:
            os.close(fd)

    releaser = threading.Thread(target=release_once_refused)
    releaser.start()
    try:
        r = sweep_with(cli, [str(path), "-o", str(out), "--shard", "0/1", "--cli", str(fake)],
                       env={"SHELLCONTRACT_TEST_JOB_LOCK_WAIT_S": "0"})
    finally:
        releaser.join()
    assert r.returncode == 0, r.stderr
    assert [row["status"] for row in results(out)] == ["ok", "ok"], r.stderr
    assert len(runs_of(tmp_path, job)) >= 2  # refused, then run


BAD = [("lock_wait", -1), ("lock_wait", -0.0001), ("lock_wait", math.nan), ("lock_wait", math.inf),
       ("lock_wait", 2e9), ("lock_wait", "1"), ("lock_wait", None), ("lock_wait", True),
       ("note_every", 0), ("note_every", -5), ("note_every", math.nan), ("note_every", "60")]


@pytest.mark.parametrize("name,value", BAD, ids=["{}={!r}".format(n, v) for n, v in BAD])
def test_a_bad_timing_is_refused_naming_it_before_anything(mesh_dir, tmp_path, name, value):
    path = write_sweep(tmp_path, mesh_dir, "c.json", SHORT, meshes=("ico1.off",))
    out = tmp_path / "out"
    least = {"lock_wait": ">= 0", "note_every": "> 0"}[name]  # no wait; a note not said at once
    with pytest.raises(ValueError, match=r"^{}: expected a number of seconds {} and <= 1e\+09, "
                                         r"got {}$".format(name, least, re.escape(repr(value)))):
        sweep.main([str(path), "-o", str(out), "--shard", "0/1"], **{name: value})
    assert not out.exists()


def test_a_bad_lock_wait_is_refused_by_the_jobs_own_function(tmp_path):
    # run_job is also called alone (a worker's task): it checks what it is given too.
    with pytest.raises(ValueError, match="^lock_wait: expected a number of seconds >= 0"):
        sweep_job.run_job({"id": "x", "mesh": "m.off", "options": {}, "args": []}, str(tmp_path),
                          "shellcontract", lock_wait=-1)
    assert os.listdir(tmp_path) == []


def test_the_lock_wait_reaches_the_embedded_clusters_workers(cli, mesh_dir, tmp_path):
    # lock_wait=0: the job's attempt leaves the job at the first refusal, one run; with the
    # default it would try again every half second for 15 s.
    path, out, job, checkpoint = one_job_to_run_again(cli, mesh_dir, tmp_path)
    fake = logging_cli(tmp_path, cli)
    fd = hold_tool_lock(str(checkpoint))
    try:
        r = sweep_with(cli, [str(path), "-o", str(out), "--cli", str(fake)], lock_wait=0)
    finally:
        os.close(fd)
    assert r.returncode == 3, r.stderr
    assert [row["status"] for row in results(out)] == ["running elsewhere", "ok"], r.stderr
    assert [line.endswith("-> 1") for line in runs_of(tmp_path, job)] == [True]
