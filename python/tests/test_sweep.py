"""python3 -m shellcontract.sweep with real processes: the embedded Dask cluster, a real `dask
scheduler` with two `dask worker`s one of which is killed mid-sweep, a sweep killed and run
again, shards, and sweep files that are refused. Every result is compared byte for byte with the
same job run as a plain `shellcontract run` (the serial run the issue names as the reference)."""
import csv
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time

import pytest

from shellcontract import sweep_file

from proc_holders import lock_holders

pytest.importorskip("distributed")

TIMING_COLUMNS = {"step_ms", "solve_ms", "ccd_ms"}
RESULT_COLUMNS = ["status", "exit_code", "final_volume_ratio", "frames_run", "wall_seconds",
                  "resumed", "peak_memory_mb", "new_intersections", "output"]


def sweep_env(cli):
    env = dict(os.environ)
    import shellcontract
    package_parent = os.path.dirname(os.path.dirname(os.path.abspath(shellcontract.__file__)))
    env["PYTHONPATH"] = package_parent + os.pathsep + env.get("PYTHONPATH", "")
    env["SHELLCONTRACT_CLI"] = cli
    return env


def run_sweep(cli, args, timeout=240, **kw):
    return subprocess.run([sys.executable, "-m", "shellcontract.sweep"] + args, env=sweep_env(cli),
                          capture_output=True, text=True, timeout=timeout, **kw)


def write_sweep(tmp_path, mesh_dir, name, spec, meshes=("ico1.off", "octahedron.off")):
    folder = tmp_path / "meshes"
    folder.mkdir(exist_ok=True)
    for m in meshes:
        if not (folder / m).exists():
            shutil.copy(mesh_dir / m, folder / m)
    path = tmp_path / name
    path.write_text(json.dumps(spec))
    return path


_SERIAL = {}  # job id -> (mesh bytes, log): a job's id names its mesh bytes and options


def serial_reference(cli, sweep_path, tmp_path):
    """Each job of the file run as a plain `shellcontract run`: job id -> (mesh bytes, log)."""
    version = subprocess.run([cli, "--version"], capture_output=True, text=True).stdout.strip()
    jobs = sweep_file.expand(str(sweep_path), sweep_file.load(str(sweep_path)), version)
    ref = tmp_path / "serial"
    ref.mkdir(exist_ok=True)
    out = {}
    for job in jobs:
        if job.id in _SERIAL:
            out[job.id] = _SERIAL[job.id]
            continue
        mesh_out = ref / (job.id + os.path.splitext(job.mesh)[1])
        log = ref / (job.id + ".csv")
        r = subprocess.run([cli, "run", job.mesh, "-o", str(mesh_out), "--log", str(log), "-q"]
                           + job.args, capture_output=True, text=True)
        assert r.returncode in (0, 5), r.stderr
        out[job.id] = _SERIAL[job.id] = (mesh_out.read_bytes(), log_rows(log))
    return out


def log_rows(path):
    with open(path) as f:
        return [{k: v for k, v in row.items() if k not in TIMING_COLUMNS} for row in csv.DictReader(f)]


def results(out_dir):
    with open(os.path.join(out_dir, "results.csv")) as f:
        return list(csv.DictReader(f))


def assert_equals_serial(out_dir, reference):
    rows = results(out_dir)
    assert sorted(r["job"] for r in rows) == sorted(reference)
    for row in rows:
        assert row["status"] in ("ok", "target not reached"), row
        mesh_bytes, log = reference[row["job"]]
        with open(os.path.join(out_dir, row["output"]), "rb") as f:
            assert f.read() == mesh_bytes, "job {}: the mesh differs from the serial run".format(row["job"])
        assert log_rows(os.path.join(out_dir, "jobs", row["job"], "log.csv")) == log, row["job"]


SMALL = {"meshes": ["meshes/*.off"], "options": {"collisions": True},
         "grid": {"pressure": [2, 4.5], "frames": [6, 9]}}


def test_embedded_cluster_equals_serial_runs(cli, mesh_dir, tmp_path):
    path = write_sweep(tmp_path, mesh_dir, "small.json", SMALL)
    out = tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--workers", "2"])
    assert r.returncode == 0, r.stderr
    assert "Dask dashboard" in r.stderr or "dashboard" in r.stderr.lower()
    rows = results(out)
    assert len(rows) == 8
    assert list(rows[0]) == ["job", "mesh", "pressure", "frames"] + RESULT_COLUMNS
    assert {(r["pressure"], r["frames"]) for r in rows} == {("2", "6"), ("2", "9"), ("4.5", "6"), ("4.5", "9")}
    assert json.loads((out / "results.json").read_text())[0].keys() == rows[0].keys()
    assert_equals_serial(out, serial_reference(cli, path, tmp_path))
    # Again: every job is skipped (no job folder is rewritten).
    before = {p: os.stat(p).st_ino for p in (out / "jobs").glob("*/job.json")}
    again = run_sweep(cli, [str(path), "-o", str(out), "--workers", "1"])
    assert again.returncode == 0, again.stderr
    assert "8 done already" in again.stderr
    assert {p: os.stat(p).st_ino for p in (out / "jobs").glob("*/job.json")} == before
    # One option of the file changed for one grid value: only the jobs it touches run.
    changed = dict(SMALL, grid={"pressure": [2, 3], "frames": [6, 9]})
    path = write_sweep(tmp_path, mesh_dir, "small.json", changed)
    third = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert third.returncode == 0, third.stderr
    assert "4 done already" in third.stderr


def test_shards_together_equal_the_whole(cli, mesh_dir, tmp_path):
    path = write_sweep(tmp_path, mesh_dir, "small.json", SMALL)
    out = tmp_path / "out"
    seen = set()
    for i in range(3):
        r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "{}/3".format(i)])
        assert r.returncode == 0, r.stderr
        done = {p.name for p in (out / "jobs").iterdir()}
        assert len(done - seen) in (2, 3), "shard {} ran {} jobs".format(i, len(done - seen))
        seen = done
    assert len(seen) == 8
    assert_equals_serial(out, serial_reference(cli, path, tmp_path))


# Jobs of about a second each, for the tests that must find a sweep mid-way (three of them on two
# workers in test_real_scheduler_with_a_worker_killed_mid_sweep).
KILLED = {"meshes": ["meshes/ico3.off"], "options": {"pressure": 2, "frames": 1500, "threads": 1},
          "grid": {"air_balance": [0.9, 0.8, 0.7]}}


def wait_until(predicate, timeout=120):
    start = time.monotonic()
    while not predicate():
        if time.monotonic() - start > timeout:
            raise AssertionError("timed out waiting")
        time.sleep(0.05)


def done_jobs(out):
    return list((out / "jobs").glob("*/job.json")) if (out / "jobs").is_dir() else []


def test_sweep_killed_and_run_again_redoes_no_finished_job(cli, mesh_dir, tmp_path):
    # Four jobs of about a second on two workers: when two have finished the other two are
    # running, so the kill finds the sweep mid-way on any machine (jobs of a tenth of a second
    # could all end between two polls).
    path = write_sweep(tmp_path, mesh_dir, "long.json", dict(KILLED, grid={"air_balance": [0.9, 0.8, 0.7, 0.6]}),
                       meshes=("ico3.off",))
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out),
                             "--workers", "2", "--checkpoint-every", "5"], env=sweep_env(cli),
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)
    wait_until(lambda: len(done_jobs(out)) >= 2)
    os.killpg(proc.pid, signal.SIGKILL)  # the sweep and its worker processes, no goodbye
    proc.wait()
    finished = {p.parent.name: (os.stat(p).st_ino, p.read_text()) for p in done_jobs(out)}
    assert 2 <= len(finished) < 4, "make the jobs longer: the sweep ended before the kill"
    # The killed sweep's runs got SIGTERM (the parent-death signal): they save and end. A job
    # that the kill caught as it started ends before running (sweep_job._death_signal_prefix;
    # before, it ran to its end orphaned and the rerun found its attempt locked). What the rerun
    # depends on is waited for, the locks: a job's process not yet exec'd shows the sweep's
    # command line, and an ending one loses its command line before its descriptors.
    wait_until(lambda: not runs_reading(tmp_path / "meshes") and not lock_holders(out / ".work")
               and not lock_holders(out / ".work" / "checkpoints"), timeout=60)
    left = [p.name for p in (out / ".work").iterdir() if p.name != "checkpoints"]
    held = lock_holders(out / ".work")  # said if an attempt is left: who held its lock
    again = run_sweep(cli, [str(path), "-o", str(out), "--workers", "2"])
    assert again.returncode == 0, again.stderr
    for job, (inode, text) in finished.items():
        p = out / "jobs" / job / "job.json"
        assert os.stat(p).st_ino == inode and p.read_text() == text, "job {} was redone".format(job)
    assert_equals_serial(out, serial_reference(cli, path, tmp_path))
    # The killed sweep's working folders are gone (the rerun removed them: nobody held them).
    if left:
        assert "that a killed sweep left" in again.stderr, again.stderr
    assert [p.name for p in (out / ".work").iterdir()] == ["checkpoints"], (left, held)
    # Every job finished: its checkpoint is removed, and the log the CLI kept beside it.
    assert [p.name for p in (out / ".work" / "checkpoints").iterdir()] == []


def test_a_finished_jobs_leftover_checkpoint_is_removed_by_the_next_sweep(cli, mesh_dir, tmp_path):
    # A sweep killed after publishing a job and before removing its checkpoint (the window
    # test_sweep_killed_and_run_again_redoes_no_finished_job can hit) leaves FILE, FILE.log and
    # FILE.history in .work/checkpoints/: the next sweep finds the job done and removes them.
    spec = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4}, "grid": {"pressure": [2, 3]}}
    path = write_sweep(tmp_path, mesh_dir, "c.json", spec, meshes=("ico1.off",))
    out = tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    jobs = [row["job"] for row in results(out)]
    left = [out / ".work" / "checkpoints" / (jobs[0] + ".ckpt" + tail) for tail in ("", ".log", ".history")]
    for p in left:
        p.write_bytes(b"left by a killed sweep")
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0 and "2 done already" in r.stderr, r.stderr
    assert [p.name for p in (out / ".work" / "checkpoints").iterdir()] == []


def test_a_checkpoint_the_tool_refuses_is_removed_and_the_job_runs_from_its_first_frame(cli, mesh_dir, tmp_path):
    # Before: the job became a final "bad input" (exit 2), its checkpoint removed, and every later
    # sweep skipped it ("done already") though nothing was wrong with its mesh or options.
    spec = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4}, "grid": {"pressure": [2, 3]}}
    path = write_sweep(tmp_path, mesh_dir, "c.json", spec, meshes=("ico1.off",))
    out = tmp_path / "out"
    assert run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"]).returncode == 0
    ids = [row["job"] for row in results(out)]
    # The first job again, from a checkpoint the tool refuses.
    shutil.rmtree(out / "jobs" / ids[0])
    checkpoints = out / ".work" / "checkpoints"
    (checkpoints / (ids[0] + ".ckpt")).write_bytes(b"not a checkpoint")
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    assert [row["status"] for row in results(out)] == ["ok", "ok"]
    record = json.loads((out / "jobs" / ids[0] / "job.json").read_text())
    assert record["resumed"] is False
    assert "checkpoint was refused (shellcontract run: checkpoint" in (out / "jobs" / ids[0] / "messages.txt").read_text()
    assert list(checkpoints.iterdir()) == []


def runs_reading(folder):
    """Pids of the processes whose command line names `folder` (the jobs' runs of a test)."""
    pids = []
    for name in os.listdir("/proc"):
        try:
            with open("/proc/{}/cmdline".format(name), "rb") as f:
                if str(folder).encode() in f.read():
                    pids.append(int(name))
        except (OSError, ValueError):
            pass
    return pids


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_scheduler(dask, tmp_path, env, logs):
    """A `dask scheduler` on ports the system picks (0), and its address from the file it
    writes: a port taken from free_port() can be taken again before the scheduler binds it (the
    dashboard's, or another process's), which failed a test with "Address already in use"."""
    info = tmp_path / "scheduler.json"
    proc = subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", "0",
                             "--dashboard-address", "127.0.0.1:0", "--scheduler-file", str(info)],
                            env=env, stdout=logs, stderr=logs)

    def address():
        assert proc.poll() is None, "the scheduler ended: " + (tmp_path / "dask.log").read_text()
        try:
            return json.loads(info.read_text()).get("address")
        except (OSError, ValueError):
            return None  # not written yet, or written half
    wait_until(address, timeout=60)
    return proc, address()


def test_real_scheduler_with_a_worker_killed_mid_sweep(cli, mesh_dir, tmp_path):
    dask = shutil.which("dask")
    if dask is None:
        pytest.skip("the dask command (python3-distributed) is not installed")
    # Jobs of about a second (KILLED): jobs of a tenth of a second end so soon that under a loaded
    # machine two of them are seldom running with a checkpoint at the same poll, and the wait
    # below timed out after the sweep had ended.
    path = write_sweep(tmp_path, mesh_dir, "long.json", KILLED, meshes=("ico3.off",))
    out = tmp_path / "out"
    env = sweep_env(cli)
    logs = open(tmp_path / "dask.log", "w")
    scheduler, address = start_scheduler(dask, tmp_path, env, logs)
    procs = [scheduler]
    try:
        for _ in range(2):
            procs.append(subprocess.Popen(
                [dask, "worker", address, "--nworkers", "1", "--nthreads", "1", "--no-nanny",
                 "--host", "127.0.0.1", "--no-dashboard"], env=env, stdout=logs, stderr=logs))
        sweep = subprocess.Popen([sys.executable, "-m", "shellcontract.sweep", str(path), "-o",
                                  str(out), "--scheduler", address, "--checkpoint-every", "5"],
                                 env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        # Mid-sweep, with both workers inside a job: a job's checkpoint exists only while it runs
        # (a finished job removes it), so two checkpoints mean each worker holds a job that has
        # saved one, and the worker killed below is certainly mid-job.
        def two_running():
            assert sweep.poll() is None, "the sweep ended before two jobs ran at once"
            return ((out / ".work" / "checkpoints").is_dir()
                    and len(list((out / ".work" / "checkpoints").glob("*.ckpt"))) >= 2)
        wait_until(two_running)
        procs[1].kill()  # SIGKILL: the worker and its running job are gone at once
        procs[1].wait()
        _, err = sweep.communicate(timeout=240)
        assert sweep.returncode == 0, err
        assert len(results(out)) == 3
        assert_equals_serial(out, serial_reference(cli, path, tmp_path))
        records = [json.loads(p.read_text()) for p in done_jobs(out)]
        # The lost worker's job went on from its checkpoint elsewhere (its run got SIGTERM when
        # the worker died, saved, and the new attempt resumed it).
        assert any(r["resumed"] for r in records), [r["job"] for r in records]
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


@pytest.mark.parametrize("spec,expected", [
    ({"meshes": ["meshes/*.off"], "grid": {"presure": [1, 2]}}, "unknown option 'presure'"),
    ({"meshes": ["meshes/ico1.off"], "options": {"presure": 1}},
     "job 0 (mesh meshes/ico1.off, options {\"presure\": 1}): unknown option 'presure' (options are "
     "the Python names of shellcontract.options()); valid options: pressure, "),
    ({"meshes": ["meshes/*.off"], "grid": {"pressure": [1, 2]}, "runs": [{"pressure": 3}]},
     "runs[0]: option 'pressure' is also in 'grid'"),
    ({"meshes": ["meshes/*.off"], "grid": {"damping": [0.1, 1.5]}}, "--damping: '1.5'"),
    ({"meshes": ["meshes/*.off", "meshes/missing.off"]}, "missing.off"),
    ({"meshes": ["meshes/*.stl"]}, "matches no file"),
    ({"meshes": ["meshes/*.off"], "options": {"frames": 5}, "grid": {"frames": [1]}},
     "both in 'options' and in 'grid'"),
    ({"meshes": ["meshes/*.off"], "gird": {}}, "unknown key 'gird'"),
    ({"meshes": ["meshes/*.off"], "runs": [{"frames": 5}, {"target_volume": 0.5, "stop_volume_ratio": 0.4}]},
     "job 1 (mesh meshes/ico1.off"),
])
def test_bad_sweep_files_are_refused_naming_the_job_and_nothing_runs(cli, mesh_dir, tmp_path, spec,
                                                                     expected):
    path = write_sweep(tmp_path, mesh_dir, "bad.json", spec)
    out = tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 1, r.stderr
    assert "refused, nothing run" in r.stderr and expected in r.stderr, r.stderr
    assert "contract()" not in r.stderr  # the sweep's options, not a Python call's arguments
    assert not out.exists()


def test_a_cli_that_is_no_executable_is_refused_not_replaced(cli, mesh_dir, tmp_path):
    # Before: --cli /nonexistent (or a file that is not executable) was passed over for the
    # next candidate ($SHELLCONTRACT_CLI here) and the sweep ran, exit 0.
    path = write_sweep(tmp_path, mesh_dir, "s.json", {"meshes": ["meshes/ico1.off"], "options": {"frames": 2}})
    text = tmp_path / "not_executable"
    text.write_text("#!/bin/sh\n")
    for given in (tmp_path / "missing", text):
        out = tmp_path / "out"
        r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1", "--cli", str(given)])
        assert r.returncode == 1, r.stderr
        assert "--cli {}: not an executable file".format(given) in r.stderr, r.stderr
        assert not out.exists()


def test_unreadable_mesh_and_bad_json_are_refused(cli, mesh_dir, tmp_path):
    folder = tmp_path / "meshes"
    folder.mkdir()
    (folder / "broken.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")
    path = tmp_path / "s.json"
    path.write_text(json.dumps({"meshes": ["meshes/broken.off"]}))
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--shard", "0/1"])
    assert r.returncode == 1 and "broken.off" in r.stderr, r.stderr
    path.write_text("{\"meshes\": [")
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--shard", "0/1"])
    assert r.returncode == 1 and "not valid JSON" in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()


def test_a_failing_job_is_recorded_and_the_others_go_on(cli, mesh_dir, tmp_path):
    # A target that the frames cannot reach (exit 5, result written) and a job timeout.
    spec = {"meshes": ["meshes/ico2.off"], "runs": [{"frames": 4},
                                                     {"frames": 4, "stop_volume_ratio": 0.1},
                                                     {"frames": 1000000, "threads": 1}]}
    path = write_sweep(tmp_path, mesh_dir, "f.json", spec, meshes=("ico2.off",))
    out = tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1", "--job-timeout", "3"])
    assert r.returncode == 3, r.stderr  # a job timed out: not every job has its outcome
    status = [row["status"] for row in results(out)]
    assert status == ["ok", "target not reached", "timeout"], status
    rows = results(out)
    assert rows[1]["exit_code"] == "5" and rows[1]["output"]
    record = json.loads((out / "jobs" / rows[2]["job"] / "job.json").read_text())
    assert "job-timeout" in record["message"]
    # The timed-out job stopped with SIGTERM and saved its state: a rerun resumes it.
    assert (out / ".work" / "checkpoints" / (rows[2]["job"] + ".ckpt")).is_file()


def test_cli_front_runs_the_sweep_module(cli, mesh_dir, tmp_path):
    path = write_sweep(tmp_path, mesh_dir, "small.json", SMALL)
    r = subprocess.run([cli, "sweep", str(path), "-o", str(tmp_path / "out"), "--dry-run"],
                       capture_output=True, text=True, env=sweep_env(cli), timeout=120)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert len(lines) == 8 and all("--pressure" in line and "--frames" in line for line in lines)
    assert not (tmp_path / "out").exists()  # a dry run writes nothing


def test_cli_front_says_where_it_looked_for_a_missing_package(cli, mesh_dir, tmp_path):
    # The executable alone, with no package beside it (neither <dir>/python, as in the build
    # tree, nor the install's lib/python3.X/dist-packages) and none on PYTHONPATH.
    lone = tmp_path / "bin"
    lone.mkdir()
    shutil.copy(cli, lone / "shellcontract")
    path = write_sweep(tmp_path, mesh_dir, "small.json", SMALL)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "SHELLCONTRACT_CLI")}
    # Started from the folder holding the built package: the current folder is not looked in.
    import shellcontract
    cwd = os.path.dirname(os.path.dirname(os.path.abspath(shellcontract.__file__)))
    r = subprocess.run([str(lone / "shellcontract"), "sweep", str(path), "-o", str(tmp_path / "o"),
                        "--dry-run"], capture_output=True, text=True, env=env, timeout=120, cwd=cwd)
    assert r.returncode == 1, r.stderr
    assert "cannot import the Python package shellcontract" in r.stderr, r.stderr
    assert "looked for it in {}".format(lone / "python") in r.stderr, r.stderr
    # The install folder: lib/python3.X/dist-packages of the interpreter the module is built for,
    # the one running these tests.
    site = "python{}.{}".format(*sys.version_info[:2])
    assert str(tmp_path / "lib" / site / "dist-packages") in r.stderr, r.stderr
    assert "Traceback" not in r.stderr


def test_progress_is_a_bar_on_a_terminal_and_lines_otherwise():
    import io
    from shellcontract.sweep_progress import Progress
    ok = {"status": "ok"}
    failed = {"status": "failed", "message": "blow-up at step 3"}
    tty = io.StringIO()
    p = Progress(3, stream=tty, tty=True)
    p.job_finished(ok, "job 0")
    p.job_finished(failed, "job 1")
    text = tty.getvalue()
    assert "\r" in text and "[" + "#" * 10 in text  # redrawn in place, a third then two
    assert "1 done, 1 failed, 1 left, ETA" in text
    assert "job 1: failed (blow-up at step 3)\n" in text
    plain = io.StringIO()
    p = Progress(3, stream=plain, tty=False)
    p.job_finished(ok, "job 0")
    p.job_finished(failed, "job 1")
    assert "\r" not in plain.getvalue()
    assert plain.getvalue().splitlines()[1].startswith("job 1: failed (blow-up at step 3) -- 1 done, 1 failed, 1 left")


# Two jobs long enough (about a second each) that the test sees the second one running with a
# checkpoint before it ends: jobs of a tenth of a second end sooner than the test's
# polling can rely on under load.
INTERRUPTED = {"meshes": ["meshes/ico3.off"], "options": {"pressure": 2, "frames": 1500, "threads": 1},
               "grid": {"air_balance": [0.9, 0.8]}}


# SIGTERM (Slurm's scancel, kill) is Ctrl-C's twin: before, it ended the sweep by the signal,
# leaving its working folders and the tables as they were. So are SIGHUP (the terminal closed)
# and SIGUSR1 (Slurm's warning, `sbatch --signal`), as for the CLI: before, each still did.
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGUSR1],
                         ids=["SIGINT", "SIGTERM", "SIGHUP", "SIGUSR1"])
def test_ctrl_c_stops_cleanly_and_a_rerun_resumes_the_interrupted_job(cli, mesh_dir, tmp_path, sig):
    path = write_sweep(tmp_path, mesh_dir, "long.json", INTERRUPTED, meshes=("ico3.off",))
    out = tmp_path / "out"
    # A job's id holds the tool's version: a tool rebuilt meanwhile (a build in this tree while the
    # tests run) makes the rerun's jobs new ones, none resumed (lab/sweep/resume_flake.md).
    version = subprocess.run([cli, "--version"], capture_output=True, text=True).stdout
    proc = subprocess.Popen([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out),
                             "--shard", "0/1", "--checkpoint-every", "5"], env=sweep_env(cli),
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    # The second job is running and has saved a checkpoint (so the first one's row is written).
    def second_saved():
        done = {p.parent.name for p in done_jobs(out)}
        saved = {p.stem for p in (out / ".work" / "checkpoints").glob("*.ckpt")}
        return len(done) == 1 and saved - done
    wait_until(second_saved)
    # Removed while no job ends (the second runs 1500 frames): the stop writes the tables anew.
    (out / "results.csv").unlink()
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "run the same command again" in err
    # Nothing half-done in DIR: one finished job folder, the rest pending, no temporary files,
    # no working folder but the checkpoints.
    assert len(done_jobs(out)) == 1
    assert [r["status"] for r in results(out)].count("pending") == 1
    assert not [p for p in out.iterdir() if p.name.startswith(".results") or ".tmp-" in p.name]
    assert [p.name for p in (out / ".work").iterdir()] == ["checkpoints"]
    again = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert again.returncode == 0, again.stderr
    assert subprocess.run([cli, "--version"], capture_output=True, text=True).stdout == version, \
        "the tool was rebuilt during the test: its jobs are new ones"
    assert "1 done already" in again.stderr, again.stderr
    records = [json.loads(p.read_text()) for p in done_jobs(out)]
    assert sum(r["resumed"] for r in records) == 1  # the interrupted one, from its checkpoint
    # The table says which row's wall_seconds is a last attempt's, not a whole run's.
    assert sorted(row["resumed"] for row in results(out)) == ["off", "on"]
    assert_equals_serial(out, serial_reference(cli, path, tmp_path))


def test_crashed_and_killed_jobs_are_recorded_and_rerun_later(cli, mesh_dir, tmp_path):
    # A stand-in for the tool that dies by a signal for some jobs (a crash; SIGKILL is what the
    # kernel's OOM killer sends) and is the real one otherwise.
    fake = tmp_path / "fake_cli.sh"
    fake.write_text("#!/bin/sh\n"
                    "case \"$*\" in *'--pressure 3'*) kill -SEGV $$;; *'--pressure 5'*) kill -KILL $$;; esac\n"
                    "exec '{}' \"$@\"\n".format(cli))
    fake.chmod(0o755)
    spec = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4}, "grid": {"pressure": [2, 3, 5]}}
    path = write_sweep(tmp_path, mesh_dir, "c.json", spec, meshes=("ico1.off",))
    out = tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1", "--cli", str(fake)])
    assert r.returncode == 3, r.stderr
    assert [row["status"] for row in results(out)] == ["ok", "crashed", "killed"]
    assert "SIGSEGV" in json.loads((out / "jobs" / results(out)[1]["job"] / "job.json").read_text())["message"]
    # With the real tool the crashed and killed jobs run again; the finished one does not.
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0 and "1 done already" in r.stderr, r.stderr
    assert [row["status"] for row in results(out)] == ["ok", "ok", "ok"]


def test_a_job_whose_output_could_not_be_written_runs_again(cli, mesh_dir, tmp_path):
    # A stand-in for a full disk: the job at pressure 3 runs under a file-size limit (RLIMIT_FSIZE,
    # with SIGXFSZ ignored so that the write fails with EFBIG) that the mesh exceeds and the
    # summary does not. Its run ends, but -o fails: exit 1. That is the machine's condition, not
    # the job's, so it must not be a final 'bad usage': the next sweep, with room, runs it again.
    fake = tmp_path / "fake_cli.sh"
    fake.write_text("#!/bin/bash\n"
                    "case \"$*\" in *'--pressure 3'*) trap '' XFSZ; ulimit -f 16;; esac\n"
                    "exec '{}' \"$@\"\n".format(cli))
    fake.chmod(0o755)
    spec = {"meshes": ["meshes/ico3.off"], "options": {"frames": 4}, "grid": {"pressure": [2, 3]}}
    path = write_sweep(tmp_path, mesh_dir, "d.json", spec, meshes=("ico3.off",))
    out = tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1", "--cli", str(fake)])
    assert r.returncode == 3, r.stderr  # a job without a final outcome, as a crash
    assert [row["status"] for row in results(out)] == ["ok", "output not written"], r.stderr
    record = json.loads((out / "jobs" / results(out)[1]["job"] / "job.json").read_text())
    assert "-o: failed" in record["message"] and "too large" in record["message"], record
    assert not [p for p in out.rglob("*") if ".tmp" in p.name]
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0 and "1 done already" in r.stderr, r.stderr
    assert [row["status"] for row in results(out)] == ["ok", "ok"]

