"""The sweep where it runs: a sweep file in a folder whose name has glob characters, a CPU
affinity narrower than the machine (taskset, a Slurm cpuset), the jobs' thread counts, a closed
stderr, a mistyped $SHELLCONTRACT_CLI, results files made private, and TERM=dumb."""
import csv
import io
import json
import os
import re
import shutil
import stat
import subprocess
import sys

import pytest

from shellcontract import sweep_cli, sweep_dask, sweep_file, sweep_host, sweep_output
from shellcontract.sweep_progress import Progress
from test_sweep import run_sweep, sweep_env, write_sweep


def _statuses(out):
    with open(os.path.join(out, "results.csv")) as f:
        return [row["status"] for row in csv.DictReader(f)]


def _mesh(folder, name, source):
    folder.mkdir(parents=True, exist_ok=True)
    shutil.copy(source, folder / name)
    return str(folder / name)


# The sweep file's folder is taken as it is; only the pattern may be a glob. Before, the folder
# `r[12]` was a glob too: the sweep ran its sibling r1's mesh of the same name, silently.
def test_the_sweep_files_folder_is_not_a_glob(mesh_dir, tmp_path):
    meant = _mesh(tmp_path / "r[12]", "m.off", mesh_dir / "ico1.off")
    _mesh(tmp_path / "r1", "m.off", mesh_dir / "octahedron.off")
    path = str(tmp_path / "r[12]" / "s.json")
    assert sweep_file.expand_meshes(path, ["m.off"]) == [meant]
    assert sweep_file.expand_meshes(path, ["*.off"]) == [meant]
    # A folder that matches nothing as a glob: before, 'matches no file' of a mesh that is there.
    plain = _mesh(tmp_path / "run [2024]", "m.off", mesh_dir / "ico1.off")
    path = str(tmp_path / "run [2024]" / "s.json")
    assert sweep_file.expand_meshes(path, ["m.off"]) == [plain]
    assert sweep_file.expand_meshes(path, ["m.*"]) == [plain]
    assert sweep_file.expand_meshes(path, ["../r?/m.off"]) == [str(tmp_path / "r1" / "m.off")]


def test_a_pattern_that_names_an_existing_file_is_that_file(mesh_dir, tmp_path):
    # `part[1].off` (a copy's usual name) was a glob matching `part1.off` only, refused here.
    literal = _mesh(tmp_path, "part[1].off", mesh_dir / "ico1.off")
    path = str(tmp_path / "s.json")
    assert sweep_file.expand_meshes(path, ["part[1].off"]) == [literal]
    assert sweep_file.expand_meshes(path, [literal]) == [literal]
    # Where no file has that name, the glob: part[12].off matches part1.off.
    other = _mesh(tmp_path, "part1.off", mesh_dir / "octahedron.off")
    assert sweep_file.expand_meshes(path, ["part[12].off"]) == [other]
    assert sweep_file.expand_meshes(path, ["part*.off"]) == sorted([literal, other])
    with pytest.raises(sweep_file.SweepError, match=re.escape("'part[3].off' matches no file")):
        sweep_file.expand_meshes(path, ["part[3].off"])


def test_a_sweep_in_a_folder_named_with_brackets_runs_its_own_mesh(cli, mesh_dir, tmp_path):
    pytest.importorskip("distributed")
    folder = tmp_path / "run [2024]"
    _mesh(folder, "m.off", mesh_dir / "ico1.off")
    _mesh(tmp_path / "run 2", "m.off", mesh_dir / "octahedron.off")  # matches `run [2024]`
    (folder / "s.json").write_text(json.dumps({"meshes": ["m.off"], "options": {"frames": 2}}))
    r = run_sweep(cli, ["s.json", "-o", "out", "--dry-run"], cwd=str(folder))
    assert r.returncode == 0, r.stderr
    assert r.stdout.split()[1] == "m.off", r.stdout  # relative to the sweep file's folder


# The embedded cluster's workers: one per core this process may use (its affinity), not per core
# of the machine. Before, os.cpu_count(): a sweep given 1 core of 64 started 64 jobs at once.
def _embedded_workers_asked(sweep, cli, mesh_dir, tmp_path, monkeypatch, extra=(), jobs=4):
    """The worker counts a sweep of `jobs` tiny jobs asks its embedded cluster for (nothing
    runs); more jobs than workers by default, so that the workers asked are the test."""
    path = write_sweep(tmp_path, mesh_dir, "s.json", {"meshes": ["meshes/ico1.off"],
                                                      "grid": {"frames": list(range(1, jobs + 1))}},
                       meshes=("ico1.off",))
    asked = []

    def cluster(workers, local_directory=None):
        asked.append(workers)
        raise KeyboardInterrupt  # nothing to run: the number is the test

    monkeypatch.setattr(sweep_dask, "embedded_cluster", cluster)
    assert sweep.main([str(path), "-o", str(tmp_path / "out"), "--cli", cli] + list(extra)) == 130
    return asked


def test_the_default_workers_are_the_cores_this_process_may_use(cli, mesh_dir, tmp_path,
                                                                 monkeypatch):
    pytest.importorskip("distributed")
    from shellcontract import sweep
    if not hasattr(os, "sched_getaffinity"):
        pytest.skip("no CPU affinity on this system")
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {3})
    monkeypatch.setattr(os, "cpu_count", lambda: 64)
    assert _embedded_workers_asked(sweep, cli, mesh_dir, tmp_path, monkeypatch) == [1]


def test_no_more_workers_start_than_jobs_to_run(cli, mesh_dir, tmp_path, monkeypatch):
    """Before: --workers 1000 on a sweep of one job started 1000 workers, which on a small machine
    did not finish starting (the job stayed pending among Dask's tracebacks)."""
    pytest.importorskip("distributed")
    from shellcontract import sweep
    for name, workers, jobs, started in [("a", 3, 2, 2), ("b", 2, 3, 2)]:
        (tmp_path / name).mkdir()
        assert _embedded_workers_asked(sweep, cli, mesh_dir, tmp_path / name, monkeypatch,
                                       extra=["--workers", str(workers)], jobs=jobs) == [started]


def test_the_default_workers_are_at_most_the_bound(cli, mesh_dir, tmp_path, monkeypatch):
    """A machine of more cores than sweep_host.MAX_WORKERS starts that many workers, the bound
    --workers takes; the jobs at once share the cores."""
    pytest.importorskip("distributed")
    from shellcontract import sweep
    monkeypatch.setattr(sweep_host, "usable_cores", lambda: 1000)
    assert sweep_host.MAX_WORKERS == 256
    assert _embedded_workers_asked(sweep, cli, mesh_dir, tmp_path, monkeypatch, jobs=300) == [256]
    assert sweep_host.job_threads(256, 300, cores=1000) == 3


# A CPU quota (docker --cpus=2, a Kubernetes CPU limit) leaves the affinity whole: the cores
# this process may use are held to it. Before, the affinity alone: a sweep in a container given 2
# CPUs of a 64-core host started 64 jobs at once. The same reading as the tool's default thread
# count (tests/core/test_usable_cpus.cpp).
def _cgroup_tree(tmp_path, monkeypatch, proc_self_cgroup, files):
    root = tmp_path / "cgroup"
    for relative, text in files.items():
        (root / relative).parent.mkdir(parents=True, exist_ok=True)
        (root / relative).write_text(text)
    root.mkdir(exist_ok=True)
    (tmp_path / "proc_self_cgroup").write_text(proc_self_cgroup)
    monkeypatch.setattr(sweep_host, "CGROUP_ROOT", str(root))
    monkeypatch.setattr(sweep_host, "PROC_SELF_CGROUP", str(tmp_path / "proc_self_cgroup"))
    return root


def test_a_cpu_quota_holds_the_usable_cores(tmp_path, monkeypatch):
    root = _cgroup_tree(tmp_path, monkeypatch, "0::/job\n", {"job/cpu.max": "200000 100000\n"})
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set(range(64)), raising=False)
    assert sweep_host.cgroup_cpu_limit() == 2
    assert sweep_host.usable_cores() == 2
    for text, limit in (("150000 100000", 2), ("50000 100000", 1), ("max 100000", 0),
                        ("", 0), ("abc", 0), ("-5 100000", 0), ("200000 0", 0), ("1_0 1", 0),
                        ("200000 100000 7", 0), ("0x30000 100000", 0), ("200000\t100000", 0)):
        (root / "job" / "cpu.max").write_text(text + "\n")
        assert sweep_host.cgroup_cpu_limit() == limit, text
        assert sweep_host.usable_cores() == (limit or 64), text
    (root / "job" / "cpu.max").write_bytes(b"\xff\xfe\x00")
    assert sweep_host.usable_cores() == 64
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {5}, raising=False)
    (root / "job" / "cpu.max").write_text("800000 100000\n")
    assert sweep_host.usable_cores() == 1  # the affinity is the smaller


def test_the_tightest_quota_of_the_cgroup_and_its_ancestors(tmp_path, monkeypatch):
    root = _cgroup_tree(tmp_path, monkeypatch, "", {
        "user.slice/cpu.max": "300000 100000", "user.slice/session/cpu.max": "max 100000",
        "user.slice/session/job/cpu.max": "800000 100000"})
    assert sweep_host.cgroup_cpu_limit(str(root), "0::/user.slice/session/job\n") == 3
    # A container whose own cgroup is mounted as the root: its full path is not there.
    (root / "cpu.max").write_text("400000 100000")
    assert sweep_host.cgroup_cpu_limit(str(root), "0::/system.slice/docker-0123.scope\n") == 4
    # v1: the cpu controller's hierarchy, root/cpu or root/cpu,cpuacct; -1 is no quota.
    (root / "cpu,cpuacct" / "docker").mkdir(parents=True)
    (root / "cpu,cpuacct" / "docker" / "cpu.cfs_quota_us").write_text("250000\n")
    (root / "cpu,cpuacct" / "docker" / "cpu.cfs_period_us").write_text("100000\n")
    v1 = "4:cpu,cpuacct:/docker\n5:cpuacct:/docker\n"
    assert sweep_host.cgroup_cpu_limit(str(root), v1) == 3
    assert sweep_host.cgroup_cpu_limit(str(root), v1 + "0::/\n") == 3  # v2's 4 is the larger
    (root / "cpu,cpuacct" / "docker" / "cpu.cfs_quota_us").write_text("-1\n")
    assert sweep_host.cgroup_cpu_limit(str(root), v1) == 0
    assert sweep_host.cgroup_cpu_limit(str(root), "5:cpuacct:/docker\n") == 0
    # Garbage: no quota, no error; nothing outside the tree is read.
    for text in ("", "junk", "0::relative", ":::", "0:", "0::/../..", "2:cpu/../..:/", "\n\n"):
        assert sweep_host.cgroup_cpu_limit(str(root), text) == 0, text
    assert sweep_host.cgroup_cpu_limit(str(tmp_path / "absent"), "0::/job\n") == 0
    (tmp_path / "proc_self_cgroup").unlink()  # unreadable: no quota
    assert sweep_host.cgroup_cpu_limit() == 0


def test_the_default_workers_are_held_to_the_cpu_quota(cli, mesh_dir, tmp_path, monkeypatch):
    pytest.importorskip("distributed")
    from shellcontract import sweep
    _cgroup_tree(tmp_path, monkeypatch, "0::/\n", {"cpu.max": "200000 100000\n"})
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set(range(64)), raising=False)
    assert _embedded_workers_asked(sweep, cli, mesh_dir, tmp_path, monkeypatch) == [2]


def test_the_jobs_at_once_share_the_cores():
    assert sweep_host.job_threads(1, 10, cores=8) is None  # one at a time: the tool's default
    assert sweep_host.job_threads(8, 1, cores=8) is None
    assert sweep_host.job_threads(8, 10, cores=8) == 1
    assert sweep_host.job_threads(4, 10, cores=8) == 2
    assert sweep_host.job_threads(4, 2, cores=8) == 4  # two jobs left: half the cores each
    assert sweep_host.job_threads(16, 10, cores=8) == 1


def _calls_cli(tmp_path, cli):
    """A stand-in executable that notes the arguments of each call, then is the real one."""
    fake = tmp_path / "noting_cli.sh"
    fake.write_text("#!/bin/sh\necho \"$*\" >> '{}'\nexec '{}' \"$@\"\n".format(
        tmp_path / "calls.txt", cli))
    fake.chmod(0o755)
    return str(fake)


def _run_calls(tmp_path):
    lines = (tmp_path / "calls.txt").read_text().splitlines()
    return [line.split() for line in lines if line.startswith("run ")]


# Several jobs at once each ran with a thread per core: N jobs, N x N threads on N cores. Now
# each gets its share of the cores (--threads), unless its options give `threads`; the job ids
# do not change (`threads` is result-neutral), nor the results (checked byte for byte against
# the serial runs by test_sweep.py's embedded sweeps).
def test_jobs_run_at_once_get_a_share_of_the_cores(cli, mesh_dir, tmp_path):
    pytest.importorskip("distributed")
    spec = {"meshes": ["meshes/ico1.off", "meshes/octahedron.off"], "options": {"frames": 2}}
    path = write_sweep(tmp_path, mesh_dir, "s.json", spec)
    noting = _calls_cli(tmp_path, cli)
    dry = run_sweep(cli, [str(path), "-o", str(tmp_path / "dry"), "--dry-run"])
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--workers", "2", "--cli", noting])
    assert r.returncode == 0, r.stderr
    share = str(max(1, sweep_host.usable_cores() // 2))
    runs = _run_calls(tmp_path)
    assert len(runs) == 2
    for args in runs:
        assert args.count("--threads") == 1 and args[args.index("--threads") + 1] == share, args
    with open(tmp_path / "out" / "results.csv") as f:
        ids = sorted(row["job"] for row in csv.DictReader(f))
    assert ids == sorted(line.split()[0] for line in dry.stdout.splitlines())
    # A job's own `threads` is kept as it is.
    (tmp_path / "calls.txt").unlink()
    spec["options"]["threads"] = 3
    path.write_text(json.dumps(spec))
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "own"), "--workers", "2", "--cli", noting])
    assert r.returncode == 0, r.stderr
    for args in _run_calls(tmp_path):
        assert args.count("--threads") == 1 and args[args.index("--threads") + 1] == "3", args


# Fd 2 closed (`2>&-`, a daemon's child): the jobs run and the progress is dropped. Before, the
# sweep ended with exit 120 before any job, every job pending.
def test_a_sweep_without_stderr_runs_its_jobs(cli, mesh_dir, tmp_path):
    pytest.importorskip("distributed")
    path = write_sweep(tmp_path, mesh_dir, "s.json", {"meshes": ["meshes/*.off"],
                                                      "options": {"frames": 2}})
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out)],
                       env=sweep_env(cli), stdout=subprocess.PIPE, text=True, timeout=240,
                       preexec_fn=lambda: os.close(2))
    assert r.returncode == 0, r.stdout
    assert _statuses(out) == ["ok", "ok"]
    assert r.stdout == ""  # nothing of stderr's moved to stdout


# A set $SHELLCONTRACT_CLI that is not an executable file is refused as --cli is. Before, it was
# passed over for the build tree's executable: the results came from another binary, unsaid.
def test_a_shellcontract_cli_that_is_no_executable_is_refused(cli, mesh_dir, tmp_path):
    path = write_sweep(tmp_path, mesh_dir, "s.json", {"meshes": ["meshes/ico1.off"],
                                                      "options": {"frames": 2}},
                       meshes=("ico1.off",))
    out = tmp_path / "out"
    text = tmp_path / "not_executable"
    text.write_text("#!/bin/sh\n")
    for given in (tmp_path / "typo" / "shellcontract", text):
        env = sweep_env(cli)
        env["SHELLCONTRACT_CLI"] = str(given)
        r = subprocess.run([sys.executable, "-m", "shellcontract.sweep", str(path), "-o",
                            str(out), "--shard", "0/1"], env=env, capture_output=True, text=True,
                           timeout=240)
        assert r.returncode == 1, r.stderr
        assert "SHELLCONTRACT_CLI={}: not an executable file".format(given) in r.stderr, r.stderr
        assert not out.exists()


def test_a_worker_with_a_wrong_shellcontract_cli_is_named(cli, tmp_path, monkeypatch):
    # A worker of an existing cluster took the client's executable instead.
    monkeypatch.setenv("SHELLCONTRACT_CLI", str(tmp_path / "typo"))
    with pytest.raises(sweep_cli.WorkerError, match="SHELLCONTRACT_CLI=.*typo: not an executable"):
        sweep_cli.worker_cli(cli, None)
    monkeypatch.setenv("SHELLCONTRACT_CLI", "")  # empty: as if unset
    assert sweep_cli.find_cli() is not None


# The results tables keep the mode the user gave them, as the CLI's outputs do. Before, a
# rewrite made a private (0600) results.csv 0644.
def test_a_rewritten_file_keeps_its_mode(tmp_path):
    path = tmp_path / "results.csv"
    old = os.umask(0o022)
    try:
        sweep_output.write_atomic(str(path), "a\n")
        assert stat.S_IMODE(path.stat().st_mode) == 0o644  # new: 0666 less the umask
        path.chmod(0o600)
        sweep_output.write_atomic(str(path), "b\n")
        assert stat.S_IMODE(path.stat().st_mode) == 0o600 and path.read_text() == "b\n"
        path.chmod(0o640)
        sweep_output.write_atomic(str(path), "c\n")
        assert stat.S_IMODE(path.stat().st_mode) == 0o640
    finally:
        os.umask(old)
    assert [p.name for p in tmp_path.iterdir()] == ["results.csv"]


def test_private_results_stay_private_when_the_sweep_runs_again(cli, mesh_dir, tmp_path):
    path = write_sweep(tmp_path, mesh_dir, "s.json", {"meshes": ["meshes/ico1.off"],
                                                      "options": {"frames": 2}},
                       meshes=("ico1.off",))
    out = tmp_path / "out"
    assert run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"]).returncode == 0
    for name in ("results.csv", "results.json"):
        (out / name).chmod(0o600)
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0 and "0 in this run, 1 done already" in r.stderr, r.stderr
    for name in ("results.csv", "results.json"):
        assert stat.S_IMODE((out / name).stat().st_mode) == 0o600, name


class _Terminal(io.StringIO):
    def isatty(self):
        return True


# TERM=dumb declares a terminal without the erase sequence the bar is redrawn with: plain lines,
# as to a file. Before, `\r\033[K` went to it (shown raw in an Emacs buffer).
def test_a_dumb_terminal_gets_plain_lines(monkeypatch):
    ok = {"status": "ok"}
    monkeypatch.setenv("TERM", "dumb")
    dumb = _Terminal()
    p = Progress(2, stream=dumb)
    p.job_finished(ok, "job 0")
    p.close()
    assert "\033" not in dumb.getvalue() and "\r" not in dumb.getvalue()
    assert dumb.getvalue().startswith("job 0: ok -- 1 done, 0 failed, 1 left")
    monkeypatch.setenv("TERM", "xterm")
    smart = _Terminal()
    p = Progress(2, stream=smart)
    p.job_finished(ok, "job 0")
    assert "\r\033[K[" in smart.getvalue()
