"""The sweep under broken streams and a short environment: a stderr that cannot be written (a full
disk under its log) loses the messages, not the jobs; what it prints on stdout (--help, --dry-run)
fails as every command's stdout does, named as stdout's; the terminal's bar fits the terminal;
`-o -dir` is a folder's name; Dask's worker folders do not outlive a sweep that ran out of
descriptors; an interpreter in SHELLCONTRACT_PYTHON that is not Python is said. Each failed before
(review13 M1, L1, L4, L5, L6)."""
import csv
import io
import os
import resource
import subprocess
import sys

import pytest

from shellcontract import sweep_progress
from test_sweep import run_sweep, sweep_env, write_sweep

SPEC = {"meshes": ["meshes/ico1.off"], "grid": {"frames": [2, 3]}}


def statuses(out):
    with open(out / "results.csv") as f:
        return [row["status"] for row in csv.DictReader(f)]


@pytest.mark.parametrize("where", [["--shard", "0/1"], ["--workers", "1"]],
                         ids=["shard", "embedded"])
def test_a_stderr_that_cannot_be_written_loses_the_messages_not_the_jobs(cli, mesh_dir, tmp_path,
                                                                         where):
    """Before: the first progress line's ENOSPC was taken for the results folder's error: exit 1,
    every job pending, no word."""
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    out = tmp_path / "out"
    with open("/dev/full", "w") as full:
        p = subprocess.run([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out)]
                           + where, env=sweep_env(cli), stdout=subprocess.DEVNULL, stderr=full,
                           timeout=240)
    assert p.returncode == 0
    assert statuses(out) == ["ok", "ok"]


def _sweep_shell(cli, line, cwd):
    """`python3 -m shellcontract.sweep` with the redirections of a shell line ending in `$S ARGS`."""
    env = sweep_env(cli)
    env["S"] = "{} -m shellcontract.sweep".format(sys.executable)
    return subprocess.run(["/bin/bash", "-c", line], env=env, cwd=cwd, capture_output=True,
                          text=True, timeout=120)


@pytest.mark.parametrize("redirect,reason", [(">/dev/full", "No space left on device"),
                                             (">&-", "closed")], ids=["full", "closed"])
@pytest.mark.parametrize("args", ["s.json -o out --dry-run", "--help"], ids=["dry-run", "help"])
def test_stdout_that_cannot_be_written_is_said_as_stdout_exit_1(cli, mesh_dir, tmp_path, redirect,
                                                               reason, args):
    """Before: the dry run's full stdout was named as the results folder's ("DIR: No space left
    on device"), a closed one was exit 0 with nothing said, --help to a full one a traceback."""
    write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    r = _sweep_shell(cli, "$S {} {}".format(args, redirect), tmp_path)
    assert r.returncode == 1, r.stderr
    assert "cannot write to standard output" in r.stderr and reason in r.stderr, r.stderr
    assert "Traceback" not in r.stderr and str(tmp_path / "out") not in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()


def test_a_dry_run_whose_reader_goes_away_says_broken_pipe(cli, mesh_dir, tmp_path):
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    p = subprocess.Popen([sys.executable, "-m", "shellcontract.sweep", str(path), "-o",
                          str(tmp_path / "out"), "--dry-run"], env=sweep_env(cli),
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    p.stdout.close()  # the reader is gone before the list
    err = p.stderr.read()
    assert p.wait(timeout=120) == 1
    assert "cannot write to standard output: Broken pipe" in err, err


@pytest.mark.parametrize("columns", [20, 45, 60, 200])
def test_the_bar_fits_the_terminal(monkeypatch, columns):
    """Before: about 75 columns whatever the terminal's width; a narrower one wrapped the line
    and left a row behind at every redraw."""
    monkeypatch.setenv("COLUMNS", str(columns))
    stream = io.StringIO()
    progress = sweep_progress.Progress(1234, stream=stream, tty=True)
    progress.finished_here = 1  # an ETA in the line
    for status in ["ok"] * 5 + ["crashed"] * 3:
        progress.job_finished({"status": status}, "job")
    drawn = [part for part in stream.getvalue().split("\r\033[K") if part and "\n" not in part]
    assert drawn
    assert all(len(line) < columns for line in drawn), drawn
    if columns >= 80:
        assert all(line.startswith("[") for line in drawn), drawn


@pytest.mark.parametrize("option", ["-o", "--output"])
def test_an_output_folder_whose_name_starts_with_a_dash(cli, mesh_dir, tmp_path, option):
    """Before: argparse took `-dir` for an option: "expected one argument"."""
    write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    r = run_sweep(cli, ["s.json", option, "-dir", "--dry-run"], cwd=tmp_path)
    assert r.returncode == 0 and len(r.stdout.splitlines()) == 2, r.stderr
    r = run_sweep(cli, ["s.json", option, "-dir", "--shard", "0/1"], cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert statuses(tmp_path / "-dir") == ["ok", "ok"]


def test_no_dask_worker_folder_outlives_a_sweep_short_of_descriptors(cli, mesh_dir, tmp_path):
    """Before: near `ulimit -n 16` Dask could not remove its worker's folder ("Failed to remove",
    or a worker that failed to start without its lock), which stayed in the temporary folder; a
    cluster that failed to start was a traceback. Whatever the sweep's outcome at each of these
    limits (where it fails depends on the machine), nothing is left and nothing is a traceback."""
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    for limit in range(10, 17):
        tmp = tmp_path / "tmp{}".format(limit)
        tmp.mkdir()
        env = sweep_env(cli)
        env["TMPDIR"] = str(tmp)
        r = subprocess.run(
            [sys.executable, "-m", "shellcontract.sweep", str(path), "-o",
             str(tmp_path / "out{}".format(limit)), "--workers", "1"], env=env,
            capture_output=True, text=True, timeout=240,
            preexec_fn=lambda n=limit: resource.setrlimit(resource.RLIMIT_NOFILE, (n, n)))
        # (The interpreter's own "Exception ignored" at exit, of an event loop that Dask could
        # not finish making, is not the sweep's.)
        # Dask's own log lines (ERROR, with their tracebacks) may come before; an uncaught error
        # would come last.
        said = r.stderr.split("Exception ignored in")[0].strip().splitlines()
        assert said and said[-1].startswith("shellcontract sweep: "), (limit, r.stderr)
        left = [os.path.relpath(os.path.join(d, n), tmp) for d, dirs, files in os.walk(tmp)
                for n in dirs if n.startswith(("worker-", "shellcontract-sweep-dask-"))]
        assert left == [], (limit, r.stderr)


def test_the_scratch_folder_of_a_killed_sweep_is_removed_by_the_next(cli, mesh_dir, tmp_path):
    """A sweep killed with SIGKILL cannot remove its workers' scratch folder: the next sweep
    removes it (its lock is free); one whose sweep runs (its lock held), and one without a lock,
    stay. Fails before: nothing removed such folders (Dask's own in dask-worker-space were)."""
    import fcntl
    from shellcontract import sweep_dask
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    tmp = tmp_path / "tmp"
    for name in ("killed", "running", "unlocked"):
        worker = tmp / (sweep_dask.SCRATCH_PREFIX + name) / "dask-worker-space" / "worker-x"
        worker.mkdir(parents=True)
        (worker / "f").write_text("x")
        if name != "unlocked":
            (worker.parents[1] / sweep_dask.SCRATCH_LOCK).write_text("")
    held = os.open(tmp / (sweep_dask.SCRATCH_PREFIX + "running") / sweep_dask.SCRATCH_LOCK,
                   os.O_RDWR)
    try:
        fcntl.flock(held, fcntl.LOCK_EX)
        env = sweep_env(cli)
        env["TMPDIR"] = str(tmp)
        r = subprocess.run([sys.executable, "-m", "shellcontract.sweep", str(path), "-o",
                            str(tmp_path / "out"), "--workers", "1"], env=env,
                           capture_output=True, text=True, timeout=240)
        assert r.returncode == 0, r.stderr
    finally:
        os.close(held)
    assert sorted(os.listdir(tmp)) == [sweep_dask.SCRATCH_PREFIX + "running",
                                       sweep_dask.SCRATCH_PREFIX + "unlocked"]


@pytest.mark.parametrize("interpreter", ["/bin/false", "/bin/true"])
def test_an_interpreter_that_is_not_python_is_said(cli, mesh_dir, tmp_path, interpreter):
    """Before: /bin/false ended the sweep with exit 1 and no word, /bin/true with exit 0 and
    nothing run."""
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    env = dict(os.environ, SHELLCONTRACT_PYTHON=interpreter)
    r = subprocess.run([cli, "sweep", str(path), "-o", str(tmp_path / "out")], env=env,
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 1
    assert "SHELLCONTRACT_PYTHON=" + interpreter in r.stderr, r.stderr
    assert "is not a Python interpreter" in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()
