"""An existing cluster's workers (--scheduler): each runs its own `shellcontract` executable
(its SHELLCONTRACT_CLI, its PATH), checked to be the sweep's version; a worker that cannot import
the package or finds no usable executable is refused before anything runs, naming it; Ctrl-C
stops the sweep's jobs on the workers (each saves its checkpoint) and leaves the workers usable."""
import json
import os
import shutil
import signal
import subprocess
import sys

import pytest

from shellcontract import sweep_cli, sweep_host, sweep_job
from test_sweep import results, run_sweep, start_scheduler, sweep_env, wait_until, write_sweep
from test_sweep_lock import hold_tool_lock, sweep_command
from test_sweep_timings import logging_cli, one_job_to_run_again, runs_of
from test_sweep_engine import ENDLESS, kill_left_over, processes_naming

pytest.importorskip("distributed")

SMALL = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4}, "grid": {"pressure": [2, 3]}}


@pytest.fixture
def cluster(tmp_path):
    """A `dask scheduler`; start(env, nthreads) adds a `dask worker` with that environment."""
    dask = shutil.which("dask")
    if dask is None:
        pytest.skip("the dask command (python3-distributed) is not installed")
    logs = open(tmp_path / "dask.log", "w")
    scheduler, address = start_scheduler(dask, tmp_path, None, logs)
    procs = [scheduler]

    def start(env, nthreads=1):
        procs.append(subprocess.Popen(
            [dask, "worker", address, "--nworkers", "1", "--nthreads", str(nthreads),
             "--no-nanny", "--host", "127.0.0.1", "--no-dashboard"], env=env, stdout=logs,
            stderr=logs))
        # Joined: the scheduler knows it (a sweep started before would find no worker).
        from distributed import Client
        with Client(address, timeout="30s") as client:
            client.wait_for_workers(len(procs) - 1, timeout=60)
        return procs[-1]

    try:
        yield address, start
    finally:
        for p in procs:
            if p.poll() is None:
                p.terminate()
        for p in procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
        logs.close()
        kill_left_over(tmp_path)


def fake_cli(tmp_path, cli, version=None):
    """A stand-in executable that notes each call in calls.txt, then is the real one (or says
    another version)."""
    fake = tmp_path / "fake_cli.sh"
    lines = ["#!/bin/sh", "echo \"$*\" >> '{}'".format(tmp_path / "calls.txt")]
    if version:
        lines.append("[ \"$1\" = --version ] && {{ echo '{}'; exit 0; }}".format(version))
    lines.append("exec '{}' \"$@\"".format(cli))
    fake.write_text("\n".join(lines) + "\n")
    fake.chmod(0o755)
    return fake


def test_each_worker_runs_its_own_executable(cli, mesh_dir, tmp_path, cluster):
    address, start = cluster
    env = sweep_env(cli)
    env["SHELLCONTRACT_CLI"] = str(fake_cli(tmp_path, cli))
    start(env)
    path = write_sweep(tmp_path, mesh_dir, "s.json", SMALL, meshes=("ico1.off",))
    out = tmp_path / "out"
    # The client's SHELLCONTRACT_CLI is the real executable (sweep_env); the worker's, the fake.
    r = run_sweep(cli, [str(path), "-o", str(out), "--scheduler", address])
    assert r.returncode == 0, r.stderr
    assert [row["status"] for row in results(out)] == ["ok", "ok"]
    calls = (tmp_path / "calls.txt").read_text().splitlines()
    assert sum(c.startswith("run ") for c in calls) == 2, calls


# The jobs that run at once on one machine share its cores: the usual cluster, as many
# single-threaded workers as cores, counted by host (a worker's own nthreads, 1, says nothing of
# its neighbours). Before, no --threads: each job started a thread per core, N jobs N x N threads.
def test_jobs_on_one_machines_workers_share_its_cores(cli, mesh_dir, tmp_path, cluster):
    address, start = cluster
    env = sweep_env(cli)
    env["SHELLCONTRACT_CLI"] = str(fake_cli(tmp_path, cli))
    start(env)
    start(env)  # two single-threaded workers on 127.0.0.1
    path = write_sweep(tmp_path, mesh_dir, "s.json", SMALL, meshes=("ico1.off",))
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--scheduler", address])
    assert r.returncode == 0, r.stderr
    runs = [c.split() for c in (tmp_path / "calls.txt").read_text().splitlines()
            if c.startswith("run ")]
    assert len(runs) == 2, runs
    share = str(max(1, sweep_host.usable_cores() // 2))
    for args in runs:
        assert args.count("--threads") == 1 and args[args.index("--threads") + 1] == share, args


def test_the_share_counts_the_workers_of_each_host():
    workers = {"tcp://10.0.0.1:1": {"host": "10.0.0.1", "nthreads": 1},
               "tcp://10.0.0.1:2": {"host": "10.0.0.1", "nthreads": 1},
               "tcp://10.0.0.2:1": {"host": "10.0.0.2", "nthreads": 4}}
    assert sweep_host.cluster_share(workers, 10) == (
        {"tcp://10.0.0.1:1": 2, "tcp://10.0.0.1:2": 2, "tcp://10.0.0.2:1": 4}, 10)
    slots, jobs = sweep_host.cluster_share(workers, 3)  # no more at once than the sweep's jobs
    assert slots["tcp://10.0.0.2:1"] == 3 and slots["tcp://10.0.0.1:1"] == 2
    assert sweep_host.worker_job_threads((slots, jobs)) is None  # not in a worker's task


def test_a_worker_of_another_version_is_refused_before_anything_runs(cli, mesh_dir, tmp_path,
                                                                      cluster):
    address, start = cluster
    env = sweep_env(cli)
    env["SHELLCONTRACT_CLI"] = str(fake_cli(tmp_path, cli, version="shellcontract 0.0.1"))
    start(env)
    path = write_sweep(tmp_path, mesh_dir, "s.json", SMALL, meshes=("ico1.off",))
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--scheduler", address])
    assert r.returncode == 1, r.stderr
    assert "refused, nothing run" in r.stderr and "is version shellcontract 0.0.1" in r.stderr
    assert not (tmp_path / "out").exists()  # before: DIR was claimed, its jobs "pending"
    assert "tcp://127.0.0.1:" in r.stderr  # the worker is named
    assert not any(c.startswith("run ") for c in (tmp_path / "calls.txt").read_text().splitlines())


def test_a_worker_that_cannot_import_the_package_is_refused_not_waited_for(cli, mesh_dir,
                                                                          tmp_path, cluster):
    address, start = cluster
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    start(env)
    path = write_sweep(tmp_path, mesh_dir, "s.json", SMALL, meshes=("ico1.off",))
    try:
        r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--scheduler", address],
                      timeout=90)
    except subprocess.TimeoutExpired:
        pytest.fail("the sweep waited for a worker that cannot import the package")
    assert r.returncode == 1, r.stderr
    assert "cannot import the shellcontract package" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr
    assert not (tmp_path / "out").exists()


def test_worker_cli_falls_back_to_the_clients_path_and_checks_the_version(cli, monkeypatch,
                                                                           tmp_path):
    version = subprocess.run([cli, "--version"], capture_output=True, text=True).stdout.strip()
    monkeypatch.setattr(sweep_cli, "find_cli", lambda given=None: None)  # none of its own
    assert sweep_cli.worker_cli(cli, version) == cli
    with pytest.raises(sweep_cli.WorkerError, match="no shellcontract executable"):
        sweep_cli.worker_cli(str(tmp_path / "missing"), version)
    with pytest.raises(sweep_cli.WorkerError, match="the sweep's is other 1.0"):
        sweep_cli.worker_cli(cli, "other 1.0")


def test_ctrl_c_stops_the_jobs_on_the_workers_which_save(cli, mesh_dir, tmp_path, cluster):
    address, start = cluster
    start(sweep_env(cli), nthreads=2)
    spec = dict(ENDLESS, grid={"pressure": [2, 3]})
    path = write_sweep(tmp_path, mesh_dir, "endless.json", spec, meshes=("ico3.off",))
    out = tmp_path / "out"
    checkpoints = out / ".work" / "checkpoints"
    proc = subprocess.Popen([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out),
                             "--scheduler", address, "--checkpoint-every", "5"],
                            env=sweep_env(cli), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            text=True)
    try:
        wait_until(lambda: checkpoints.is_dir() and len(list(checkpoints.glob("*.ckpt"))) == 2)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=90)
        assert proc.returncode == 130, err
        assert "saved their checkpoints and resume from them" in err, err
        # No run goes on behind the sweep's back on the worker; both jobs pending, with their
        # checkpoints, nothing half-done.
        wait_until(lambda: not processes_naming(str(tmp_path / "meshes")), timeout=10)
        assert [r["status"] for r in results(out)] == ["pending", "pending"]
        assert {p.stem for p in checkpoints.glob("*.ckpt")} == {r["job"] for r in results(out)}
        assert not [p for p in (out / ".work").iterdir() if p.name != "checkpoints"]
    finally:
        if proc.poll() is None:
            proc.kill()
    # The worker still runs other sweeps' jobs (the stop was this sweep's alone).
    small = write_sweep(tmp_path, mesh_dir, "s.json", SMALL, meshes=("ico1.off",))
    r = run_sweep(cli, [str(small), "-o", str(tmp_path / "out2"), "--scheduler", address])
    assert r.returncode == 0, r.stderr
    assert json.loads((tmp_path / "out2" / "results.json").read_text())[0]["status"] == "ok"


def test_two_sweeps_with_one_job_on_one_cluster_each_get_their_files(cli, mesh_dir, tmp_path,
                                                                     cluster):
    # Before: the task's key was the job's id, which is the run's, not the folder's: the second
    # sweep joined the first's task, its results.csv said "ok" for files that were only in the
    # first sweep's folder, and a Ctrl-C of one interrupted the other. The dashboard line named a
    # link that answered 404 when the scheduler could not serve the dashboard (no bokeh).
    address, start = cluster
    start(sweep_env(cli), nthreads=2)
    spec = {"meshes": ["meshes/ico3.off"], "options": {"frames": 300}}
    path = write_sweep(tmp_path, mesh_dir, "s.json", spec, meshes=("ico3.off",))
    procs = [subprocess.Popen([sys.executable, "-m", "shellcontract.sweep", str(path), "-o",
                               str(tmp_path / name), "--scheduler", address],
                              env=sweep_env(cli), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                              text=True) for name in ("a", "b")]
    errs = [p.communicate(timeout=240)[1] for p in procs]
    for p, err in zip(procs, errs):
        assert p.returncode == 0, err
    for name in ("a", "b"):
        rows = results(tmp_path / name)
        assert [r["status"] for r in rows] == ["ok"], rows
        assert (tmp_path / name / rows[0]["output"]).is_file(), rows
    if not sweep_job_has_bokeh():
        assert all("Dask dashboard: not available" in err for err in errs), errs


def sweep_job_has_bokeh():
    import importlib.util
    return importlib.util.find_spec("bokeh") is not None


def test_a_cluster_without_workers_is_said_again_while_the_jobs_wait(cli, mesh_dir, tmp_path,
                                                                      cluster):
    # Before: "the cluster has no workers yet" once, at the start, then nothing for as long as
    # none joined. Now again every `note_every` seconds (shortened here), and the jobs run once a
    # worker joins.
    address, start = cluster
    path = write_sweep(tmp_path, mesh_dir, "s.json", SMALL, meshes=("ico1.off",))
    err_path = tmp_path / "sweep.err"
    with open(err_path, "w") as err_file:
        proc = subprocess.Popen(sweep_command(note_every=0.5)
                                + [str(path), "-o", str(tmp_path / "out"), "--scheduler", address],
                                env=sweep_env(cli), stdout=subprocess.DEVNULL, stderr=err_file,
                                text=True)
        try:
            note = "still no worker on {}: 2 jobs wait (start one with `dask worker {}`".format(
                address, address)
            wait_until(lambda: err_path.read_text().count(note) >= 2, timeout=120)
            start(sweep_env(cli))
            assert proc.wait(timeout=120) == 0, err_path.read_text()
        finally:
            if proc.poll() is None:
                proc.kill()
    assert [r["status"] for r in results(tmp_path / "out")] == ["ok", "ok"]


def test_the_lock_wait_goes_with_each_job_to_its_worker(cli, mesh_dir, tmp_path, cluster):
    # A worker of its own process and environment: the client's lock_wait reaches it only with
    # the job. 0: its attempt leaves the job at the first refusal, one run (with the default it
    # would try again every half second for 15 s).
    address, start = cluster
    path, out, job, checkpoint = one_job_to_run_again(cli, mesh_dir, tmp_path)
    start(sweep_env(cli))
    fake = logging_cli(tmp_path, cli)
    fd = hold_tool_lock(str(checkpoint))
    try:
        r = subprocess.run(sweep_command(lock_wait=0)
                           + [str(path), "-o", str(out), "--scheduler", address, "--cli", str(fake)],
                           env=sweep_env(cli), capture_output=True, text=True, timeout=240)
    finally:
        os.close(fd)
    assert r.returncode == 3, r.stderr
    assert [row["status"] for row in results(out)] == ["running elsewhere", "ok"], r.stderr
    assert [line.endswith("-> 1") for line in runs_of(tmp_path, job)] == [True]
