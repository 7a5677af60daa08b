"""A sweep never loses a job's checkpoint to the machine's condition: a checkpoint the tool had no
descriptor to open (exit 2, "checkpoint not read"), a run the system refused a resource before it
had a result (exit 3 without a summary: "out of resources"), an output not written after a run
that failed (exit 3, 4 or 5: "output not written") are not final, and a sweep that an error stops
after its jobs started exits 3 with its jobs stopped, not 1 ("nothing run"). The limits are real
(setrlimit, `ulimit`) on the real tool; docs/design/sweeps.md, "Jobs"."""
import json
import resource
import subprocess
import sys

import pytest

from test_sweep import results, run_sweep, sweep_env, wait_until, write_sweep
from test_sweep_engine import ENDLESS, processes_naming
from test_sweep_workers import cluster  # noqa: F401 (a fixture)

SHORT = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4}, "grid": {"pressure": [2, 3]}}


def run_with_open_files(cli, limit, args):
    """`cli args` with at most `limit` descriptors (0, 1 and 2 open at the start)."""
    def low():
        resource.setrlimit(resource.RLIMIT_NOFILE, (limit, limit))
    return subprocess.run([cli] + [str(a) for a in args], capture_output=True, text=True,
                          preexec_fn=low, timeout=120)


def checkpoint_limits(cli, mesh_dir, tmp_path):
    """[(limit, result)] of `run --resume` of a real checkpoint (with its .log and .history
    beside) under each limit of open files at which the tool could not open the checkpoint."""
    ck = tmp_path / "c.ckpt"
    r = subprocess.run([cli, "run", str(mesh_dir / "ico1.off"), "-o", str(tmp_path / "a.off"),
                        "-n", "4", "--checkpoint", str(ck), "--checkpoint-every", "1", "-q"],
                       capture_output=True, text=True)
    assert r.returncode == 0 and ck.with_name("c.ckpt.log").is_file(), r.stderr
    found = []
    for limit in range(3, 12):
        r = run_with_open_files(cli, limit, ["run", "--resume", ck, "-o", tmp_path / "b.off", "-q"])
        if str(ck) + ": cannot open file: Too many open files" in r.stderr:
            found.append((limit, r))
    return found


def test_a_checkpoint_without_a_descriptor_is_a_checkpoint_not_read(cli, mesh_dir, tmp_path):
    # Before: exit 3 (the reader's ResourceFileError), which a sweep took for the job's final
    # "failed": it removed the checkpoint and the hours it held.
    found = checkpoint_limits(cli, mesh_dir, tmp_path)
    assert found, "no limit ran out of descriptors at the checkpoint"
    for limit, r in found:
        assert r.returncode == 2, (limit, r.stderr)
        assert "shellcontract run: checkpoint " + str(tmp_path / "c.ckpt") in r.stderr, r.stderr


WRAPPER = """#!{python}
# The tool, with its limit of open files set so that only FREE_FDS more descriptors than it
# inherits can be opened, when it resumes a checkpoint.
import os, resource, sys
if "--resume" in sys.argv:
    free, fd = [], 0
    while len(free) <= int(os.environ["FREE_FDS"]):
        try:
            if not os.get_inheritable(fd):  # this interpreter's own: closed at the exec
                free.append(fd)
        except OSError:
            free.append(fd)
        fd += 1
    hard = resource.getrlimit(resource.RLIMIT_NOFILE)[1]
    resource.setrlimit(resource.RLIMIT_NOFILE, (free[-1], hard))
os.execv({cli!r}, [{cli!r}] + sys.argv[1:])
"""


def resumed_job(cli, mesh_dir, tmp_path):
    """A sweep of two jobs run to their end, the first's record removed and a checkpoint put in
    its place: (sweep file, DIR, the first job's id, its checkpoint)."""
    path = write_sweep(tmp_path, mesh_dir, "c.json", SHORT, meshes=("ico1.off",))
    out = tmp_path / "out"
    assert run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"]).returncode == 0
    job = results(out)[0]["job"]
    (out / "jobs" / job / "job.json").unlink()
    checkpoint = out / ".work" / "checkpoints" / (job + ".ckpt")
    checkpoint.write_bytes(b"a checkpoint")
    return path, out, job, checkpoint


def test_a_sweep_keeps_a_checkpoint_the_tool_had_no_descriptor_for(cli, mesh_dir, tmp_path):
    found = checkpoint_limits(cli, mesh_dir, tmp_path)
    assert found
    path, out, job, checkpoint = resumed_job(cli, mesh_dir, tmp_path)
    wrapper = tmp_path / "limited_cli.py"
    wrapper.write_text(WRAPPER.format(python=sys.executable, cli=cli))
    wrapper.chmod(0o755)
    # As many descriptors as the tool had at the checkpoint's open above, beyond 0, 1 and 2.
    env = dict(sweep_env(cli), FREE_FDS=str(found[-1][0] - 3))
    r = subprocess.run([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out),
                        "--shard", "0/1", "--cli", str(wrapper)], env=env, capture_output=True,
                       text=True, timeout=240)
    # Before: "failed", final, the checkpoint removed, exit 0.
    kept_and_finished_later(cli, r, path, out, job, checkpoint, "checkpoint not read", 2,
                            "Too many open files")


def kept_and_finished_later(cli, r, path, out, job, checkpoint, status, exit_code, words):
    """The sweep `r` recorded the resumed job as `status` (not final: the sweep exits 3), kept its
    checkpoint and the run's exit code and message; the next sweep, with the resource back,
    finishes every job (resuming from the checkpoint, whose contents the tool refuses: the job
    runs from its first frame)."""
    assert [row["status"] for row in results(out)] == [status, "ok"], r.stderr
    assert r.returncode == 3, r.stderr
    assert checkpoint.read_bytes() == b"a checkpoint"
    record = json.loads((out / "jobs" / job / "job.json").read_text())
    assert record["exit_code"] == exit_code and words in record["message"], record
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0 and [row["status"] for row in results(out)] == ["ok", "ok"], r.stderr


def test_a_run_the_system_refused_a_resource_is_not_final(cli, mesh_dir, tmp_path):
    # A stack limit below what the tool maps at its start: exit 3, "out of memory at start", no
    # summary. Before: the job's final "failed", its checkpoint removed, exit 0.
    path, out, job, checkpoint = resumed_job(cli, mesh_dir, tmp_path)
    fake = tmp_path / "small_stack.sh"
    fake.write_text("#!/bin/bash\ncase \"$*\" in *--resume*) ulimit -s 512;; esac\n"
                    "exec '{}' \"$@\"\n".format(cli))
    fake.chmod(0o755)
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1", "--cli", str(fake)])
    kept_and_finished_later(cli, r, path, out, job, checkpoint, "out of resources", 3,
                            "the stack limit")


def test_an_output_not_written_after_a_failed_run_runs_again(cli, mesh_dir, tmp_path):
    # A target not reached (exit 5) whose -o exceeds a file size limit (the summary does not):
    # `run` exits with the run's 5, not 1. Before: the job's final "target not reached", without
    # its mesh.
    fake = tmp_path / "fake_cli.sh"
    fake.write_text("#!/bin/bash\n"
                    "case \"$*\" in *'--pressure 3'*) trap '' XFSZ; ulimit -f 16;; esac\n"
                    "exec '{}' \"$@\"\n".format(cli))
    fake.chmod(0o755)
    spec = {"meshes": ["meshes/ico3.off"], "options": {"frames": 4, "stop_volume_ratio": 0.1},
            "grid": {"pressure": [2, 3]}}
    path = write_sweep(tmp_path, mesh_dir, "d.json", spec, meshes=("ico3.off",))
    out = tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1", "--cli", str(fake)])
    assert [row["status"] for row in results(out)] == ["target not reached",
                                                       "output not written"], r.stderr
    assert r.returncode == 3, r.stderr
    record = json.loads((out / "jobs" / results(out)[1]["job"] / "job.json").read_text())
    assert record["exit_code"] == 5 and "-o: failed" in record["message"], record
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0 and "1 done already" in r.stderr, r.stderr
    assert [row["status"] for row in results(out)] == ["target not reached"] * 2


@pytest.mark.parametrize("rc,summary,lines,status", [
    # A save that failed is a note of the summary, not an output: the run's result is whole.
    (5, {"status": "target not reached", "failure": "V/V0 0.9",
         "outputs": {"--checkpoint": "2 of 3 saves failed", "-o": "written"}}, [],
     "target not reached"),
    (4, {"status": "new self-intersections", "outputs": {"-o": "failed: disk full"}}, [],
     "output not written"),
    # Neither the summary nor an output written: the tool says so.
    (1, None, ["shellcontract run: not every output could be written (the run itself ended: ok, "
               "frame 4)"], "output not written"),
    # A file the tool could not make for want of a descriptor (its checkpoint's lock).
    (1, None, ["shellcontract run: --checkpoint 'c.ckpt': cannot make its lock file "
               "'.c.ckpt.lock' (Too many open files)"], "out of resources"),
    (3, None, ["shellcontract run: pthread_create has failed: Resource temporarily unavailable "
               "(while preparing the run or taking its result); nothing was written"],
     "out of resources"),
    # Memory that ran out during the frames: the run ends itself, with its summary; final.
    (3, {"status": "failed", "failure": "out of memory at step 3", "outputs": {"-o": "written"}},
     ["shellcontract run: simulation failed: out of memory at step 3"], "failed"),
    (3, None, ["shellcontract run: simulation failed: NaN"], "failed"),
    (2, None, ["shellcontract run: m.off: cannot read file: Too many open files"], "bad input"),
])
def test_the_outcome_of_a_run(rc, summary, lines, status):
    from shellcontract import sweep_outcome
    assert sweep_outcome.classify(rc, False, summary, "last lines", lines)[0] == status
    assert (status in sweep_outcome.FINAL_STATUSES) == (
        status not in ("output not written", "out of resources"))


# A sweep whose results tables cannot be written once a job has finished (a full disk).
FAILING_TABLES = """import errno, sys
from shellcontract import sweep, sweep_results
def failing(self, job, record):
    raise OSError(errno.ENOSPC, "No space left on device", self.out_dir + "/results.csv")
sweep_results.Writer.record = failing
sys.exit(sweep.main(sys.argv[1:]))
"""


def test_tables_not_written_after_a_job_ran_is_not_nothing_run(cli, mesh_dir, tmp_path):
    # Before: exit 1, "bad usage or a refused sweep file, output folder or cluster (nothing run)".
    path = write_sweep(tmp_path, mesh_dir, "c.json", SHORT, meshes=("ico1.off",))
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-c", FAILING_TABLES, str(path), "-o", str(out),
                        "--shard", "0/1"], env=sweep_env(cli), capture_output=True, text=True,
                       timeout=240)
    assert r.returncode == 3, r.stderr
    assert "No space left on device" in r.stderr and "run the same command again" in r.stderr
    assert len(list((out / "jobs").glob("*/job.json"))) == 1
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0 and "1 done already" in r.stderr, r.stderr


def test_an_error_on_an_existing_cluster_stops_its_jobs(cli, mesh_dir, tmp_path,
                                                      cluster):  # noqa: F811
    # Before: the sweep exited 1 and left the endless job running on the worker.
    address, start = cluster
    start(sweep_env(cli), nthreads=2)
    spec = {"meshes": ["meshes/ico3.off"], "runs": [{"frames": 2}, ENDLESS["options"]]}
    path = write_sweep(tmp_path, mesh_dir, "e.json", spec, meshes=("ico3.off",))
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-c", FAILING_TABLES, str(path), "-o", str(out),
                        "--scheduler", address], env=sweep_env(cli), capture_output=True,
                       text=True, timeout=240)
    # No run goes on behind the sweep's back on the worker.
    wait_until(lambda: not processes_naming(str(tmp_path / "meshes")), timeout=10)
    assert r.returncode == 3, r.stderr
    assert "stopped after its jobs started" in r.stderr, r.stderr


SHORT_WHILE_CHECKED = """
import errno, sys
from shellcontract import sweep, sweep_file
def short(path):
    raise {error}
sweep_file._core.check_run_input = short
sys.exit(sweep.main(sys.argv[1:]))
"""


@pytest.mark.parametrize("error,code,words", [
    ("MemoryError('out of memory')", 3, "the system refused a resource while a mesh was checked"),
    ("OSError(errno.EMFILE, 'Too many open files')", 3, "the system refused a resource"),
    ("OSError(errno.ENOMEM, 'Cannot allocate memory')", 3, "the system refused a resource"),
    ("OSError(errno.EACCES, 'Permission denied')", 1, "refused, nothing run"),
])
def test_a_mesh_the_machine_could_not_read_is_not_a_refused_sweep_file(cli, mesh_dir, tmp_path,
                                                                      error, code, words):
    # Before: memory or descriptors running short while the meshes were checked was exit 1,
    # "refused, nothing run", sending the user to edit a correct file (`run` of the mesh: 3).
    path = write_sweep(tmp_path, mesh_dir, "m.json", SHORT, meshes=("ico1.off",))
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-c", SHORT_WHILE_CHECKED.format(error=error), str(path),
                        "-o", str(out)], env=sweep_env(cli), capture_output=True, text=True,
                       timeout=240)
    assert r.returncode == code, r.stderr
    assert words in r.stderr and "ico1.off" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr and not out.exists()
