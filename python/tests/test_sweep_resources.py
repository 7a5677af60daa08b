"""A sweep keeps a job's checkpoint that the tool had no descriptor to open: `run --resume` exits
2, "checkpoint FILE: cannot open file: Too many open files", a checkpoint not read, and the sweep
records "checkpoint not read" and resumes from it later. The limits are real (setrlimit) on the
real tool; docs/design/sweeps.md, "Jobs"."""
import json
import resource
import subprocess
import sys

from test_sweep import results, run_sweep, sweep_env, write_sweep

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
    assert [row["status"] for row in results(out)] == ["checkpoint not read", "ok"], r.stderr
    assert r.returncode == 3, r.stderr
    assert checkpoint.read_bytes() == b"a checkpoint"
    record = json.loads((out / "jobs" / job / "job.json").read_text())
    assert record["exit_code"] == 2 and "Too many open files" in record["message"], record
    # With descriptors, the next sweep resumes from it (whose contents the tool refuses: the job
    # runs from its first frame).
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0 and [row["status"] for row in results(out)] == ["ok", "ok"], r.stderr
