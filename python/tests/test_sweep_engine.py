"""The sweep engine's ways of keeping its cost down (lab/sweep/README.md) keep what they replace:
a job's run still gets SIGTERM (and saves) when the process that started it dies, through
setpriv as through the preexec_fn fallback; Ctrl-C on the embedded cluster, whose workers are
threads of the sweep's process, still stops the running jobs, which save; the results tables,
rewritten at most once a second while the sweep runs, still end whole."""
import json
import os
import signal
import subprocess
import sys
import time

import pytest

from shellcontract import sweep_file, sweep_job, sweep_results
from test_sweep import done_jobs, results, sweep_env, wait_until, write_sweep

pytest.importorskip("distributed")


def processes_naming(text):
    """Pids of the processes whose command line contains `text` (a test's own tmp_path)."""
    pids = []
    for name in os.listdir("/proc"):
        if not name.isdigit() or int(name) == os.getpid():
            continue
        try:
            with open("/proc/{}/cmdline".format(name), "rb") as f:
                if text.encode() in f.read():
                    pids.append(int(name))
        except OSError:
            pass
    return pids


def kill_left_over(tmp_path):
    for pid in processes_naming(str(tmp_path)):
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:
            pass


# A job that runs far longer than the test: it ends only if it is told to.
ENDLESS = {"meshes": ["meshes/ico3.off"], "options": {"frames": 1000000, "threads": 1}}

STARTER = """import sys
from shellcontract import sweep_job
if sys.argv[1] == "preexec":
    sweep_job._SETPRIV = []  # as on a machine without util-linux's setpriv
sweep_job.run_job(__import__("json").loads(sys.argv[2]), sys.argv[3], sys.argv[4], None, 20)
"""


def endless_job(cli, mesh_dir, tmp_path, launch):
    """The job of a one-job sweep that runs a million frames on ico3, for a starter that sets its
    death signal by `launch` ("setpriv" skips where setpriv cannot set it)."""
    if launch == "setpriv" and not sweep_job._death_signal_prefix():
        pytest.skip("no setpriv with --pdeathsig here")
    path = write_sweep(tmp_path, mesh_dir, "endless.json", ENDLESS, meshes=("ico3.off",))
    version = subprocess.run([cli, "--version"], capture_output=True, text=True).stdout.strip()
    return sweep_file.expand(str(path), sweep_file.load(str(path)), version)[0]


@pytest.mark.parametrize("launch", ["setpriv", "preexec"])
def test_a_job_saves_and_stops_when_the_process_that_started_it_dies(cli, mesh_dir, tmp_path,
                                                                     launch):
    job = endless_job(cli, mesh_dir, tmp_path, launch)
    out = tmp_path / "out"
    starter = subprocess.Popen([sys.executable, "-c", STARTER, launch, json.dumps(job.to_dict()),
                                str(out), cli], env=sweep_env(cli))
    try:
        # The run is under way (it has saved once, so it has its signal handlers).
        checkpoint = out / ".work" / "checkpoints" / (job.id + ".ckpt")
        wait_until(checkpoint.is_file)
        messages = list((out / ".work").glob(job.id + ".*/messages.txt"))
        assert len(messages) == 1
        starter.kill()  # SIGKILL: nothing of the starter's own code runs
        starter.wait()
        # Without the parent-death signal the run would go on (a million frames) and never
        # print where it saved; with it, it gets SIGTERM, saves and exits 130.
        wait_until(lambda: "--resume" in messages[0].read_text(), timeout=60)
        wait_until(lambda: not processes_naming(str(tmp_path)), timeout=30)
    finally:
        if starter.poll() is None:
            starter.kill()
        kill_left_over(tmp_path)


# The starter held up between the start of the job's process and the setting of its death signal
# (`$1`: a file it creates then), so that it can be killed there: the moment a sweep killed as it
# starts a job is in. A shell in front of setpriv, or a delay in front of the preexec_fn.
HELD_STARTER = """import os, sys, time
from shellcontract import sweep_job
flag = sys.argv[5]
if sys.argv[1] == "preexec":
    sweep_job._SETPRIV = []
    set_signal = sweep_job._die_with_parent

    def held(*args):
        open(flag, "w").close()
        time.sleep(3)
        set_signal(*args)
    sweep_job._die_with_parent = held
else:
    prefix = sweep_job._death_signal_prefix
    sweep_job._death_signal_prefix = lambda: (
        ["/bin/sh", "-c", 'touch "$0"; sleep 3; exec "$@"', flag] + prefix())
sweep_job.run_job(__import__("json").loads(sys.argv[2]), sys.argv[3], sys.argv[4], None, 20)
"""


@pytest.mark.parametrize("launch", ["setpriv", "preexec"])
def test_a_job_whose_starter_died_before_its_death_signal_was_set_does_not_run(
        cli, mesh_dir, tmp_path, launch):
    # Before: the signal, set after its parent had gone, never came, and the run went on to its
    # end orphaned, holding its attempt's lock (test_sweep_killed_and_run_again_redoes_no_
    # finished_job then found its folder left after the rerun).
    job = endless_job(cli, mesh_dir, tmp_path, launch)
    out = tmp_path / "out"
    flag = tmp_path / "started"
    starter = subprocess.Popen([sys.executable, "-c", HELD_STARTER, launch,
                                json.dumps(job.to_dict()), str(out), cli, str(flag)],
                               env=sweep_env(cli))
    try:
        wait_until(flag.exists)
        starter.kill()  # SIGKILL, before the child has set its parent-death signal
        starter.wait()
        # The child ends without running the job (it would run a million frames).
        wait_until(lambda: not processes_naming(str(tmp_path)), timeout=20)
        assert not (out / ".work" / "checkpoints" / (job.id + ".ckpt")).exists()
    finally:
        if starter.poll() is None:
            starter.kill()
        kill_left_over(tmp_path)


# SIGTERM (Slurm's scancel) as Ctrl-C, here through the tool's `sweep` command (which becomes the
# Python sweep, the same process): before, it ended the sweep by the signal, its jobs' working
# folders left behind and the tables not written. Slurm's SIGUSR1 (`sbatch --signal`) alike, as
# the CLI's `run` takes it: before, it still did.
@pytest.mark.parametrize("sig,front", [(signal.SIGINT, "python"), (signal.SIGTERM, "tool"),
                                       (signal.SIGUSR1, "tool")],
                         ids=["SIGINT", "SIGTERM", "SIGUSR1"])
def test_ctrl_c_on_the_embedded_cluster_stops_the_jobs_which_save(cli, mesh_dir, tmp_path, sig,
                                                                  front):
    # Two jobs that end only if told to, one per worker: Ctrl-C certainly finds both running.
    spec = dict(ENDLESS, grid={"pressure": [2, 3]})
    path = write_sweep(tmp_path, mesh_dir, "endless.json", spec, meshes=("ico3.off",))
    out = tmp_path / "out"
    checkpoints = out / ".work" / "checkpoints"
    command = [sys.executable, "-m", "shellcontract.sweep"] if front == "python" else [cli, "sweep"]
    proc = subprocess.Popen(command + [str(path), "-o", str(out), "--workers", "2",
                                       "--checkpoint-every", "5"], env=sweep_env(cli),
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        wait_until(lambda: checkpoints.is_dir() and len(list(checkpoints.glob("*.ckpt"))) == 2)
        (out / "results.csv").unlink()  # written when the sweep began; the stop writes it anew
        proc.send_signal(sig)
        # Without the sweep stopping its workers' jobs itself, closing the cluster would wait
        # for runs that never end.
        _, err = proc.communicate(timeout=60)
        assert proc.returncode == 130, err
        assert "run the same command again" in err, err
        # Both runs have ended (none goes on behind the sweep's back) and left nothing half-done:
        # no working folder, no job folder, both jobs pending with their checkpoints.
        assert processes_naming(str(tmp_path)) == []
        assert [p.name for p in (out / ".work").iterdir()] == ["checkpoints"]
        assert done_jobs(out) == []
        assert [r["status"] for r in results(out)] == ["pending", "pending"]
        assert {p.stem for p in checkpoints.glob("*.ckpt")} == {r["job"] for r in results(out)}
    finally:
        if proc.poll() is None:
            proc.kill()
        kill_left_over(tmp_path)


class Clock:
    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


def test_results_tables_are_rewritten_at_most_once_a_second_and_end_whole(mesh_dir, tmp_path):
    spec = {"meshes": ["meshes/ico1.off"], "grid": {"pressure": [1, 2, 3]}}
    path = write_sweep(tmp_path, mesh_dir, "s.json", spec, meshes=("ico1.off",))
    data = sweep_file.load(str(path))
    jobs = sweep_file.expand(str(path), data, "test-version")
    out = tmp_path / "out"
    (out / "jobs").mkdir(parents=True)

    def finish(job):
        """A job's outcome as run_job leaves it: its folder with its record."""
        record = {"job": job.id, "status": "ok", "exit_code": 0, "output": ""}
        (out / "jobs" / job.id).mkdir()
        (out / "jobs" / job.id / "job.json").write_text(json.dumps(record))
        return record

    def statuses():
        return [r["status"] for r in results(out)]

    clock = Clock()
    tables = sweep_results.Writer(jobs, sweep_file.varying_names(data), str(out), str(tmp_path),
                                  clock=clock)
    tables.record(jobs[0], finish(jobs[0]))  # the first outcome is written at once
    assert statuses() == ["ok", "pending", "pending"]
    clock.now += 0.5
    tables.record(jobs[1], finish(jobs[1]))  # half a second later: not yet
    assert statuses() == ["ok", "pending", "pending"]
    finish(jobs[2])  # another shard's job, which this sweep never hears of
    clock.now += sweep_results.Writer.INTERVAL_SECONDS
    tables.record(jobs[1], sweep_job.read_record(str(out), jobs[1].id))
    assert statuses() == ["ok", "ok", "pending"]  # due: written, from what this sweep holds
    tables.flush()  # the last write reads every folder
    assert statuses() == ["ok", "ok", "ok"]


def test_working_folders_a_killed_sweep_left_are_removed_and_running_ones_kept(cli, mesh_dir,
                                                                               tmp_path):
    spec = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4}}
    path = write_sweep(tmp_path, mesh_dir, "s.json", spec, meshes=("ico1.off",))
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out),
                        "--shard", "0/1"], env=sweep_env(cli), capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    work = out / ".work"
    # What a sweep killed with SIGKILL leaves: attempts' folders (one replacing an earlier
    # outcome, .old), their lock files released, or none (killed before the lock was made).
    for name in ("0123456789abcdef.0badf00d", "0123456789abcdef.0badf00d.old",
                 "fedcba9876543210.12345678"):
        (work / name).mkdir()
        (work / name / "messages.txt").write_text("half a run\n")
    (work / "0123456789abcdef.0badf00d.lock").write_text("")
    # An attempt that runs (its lock held by another process: another shard, a worker).
    live = work / "1111111111111111.22222222"
    live.mkdir()
    (work / (live.name + ".lock")).write_text("")
    holder = subprocess.Popen(
        [sys.executable, "-c", "import fcntl, os, sys, time\n"
         "fd = os.open(sys.argv[1], os.O_RDWR); fcntl.flock(fd, fcntl.LOCK_EX)\n"
         "print('locked', flush=True); time.sleep(120)", str(work / (live.name + ".lock"))],
        stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "locked"
        r = subprocess.run([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out),
                            "--shard", "0/1"], env=sweep_env(cli), capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        assert "removed the working folders of 2 attempts that a killed sweep left" in r.stderr
        assert sorted(p.name for p in work.iterdir()) == [
            "1111111111111111.22222222", "1111111111111111.22222222.lock", "checkpoints"]
    finally:
        holder.kill()
        holder.wait()
