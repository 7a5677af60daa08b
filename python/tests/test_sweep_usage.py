"""The sweep's command line: bad usage exits 1 (the tool's 'bad usage'; 2 is its 'unusable
input'), with argparse's message and no traceback; --job-timeout and --checkpoint-every are
refused outside what the waits and `shellcontract run` can take, instead of every job crashing or
being 'bad usage' later."""
import pytest

from test_sweep import run_sweep, write_sweep

SPEC = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4}}


@pytest.mark.parametrize("args,expected", [
    ([], "the following arguments are required"),
    (["--no-such-flag"], "unrecognized arguments: --no-such-flag"),
    (["--shard", "3/2"], "expected 0 <= I < N"),
    (["--shard", "x"], "expected I/N"),
    (["--workers", "0"], "expected an integer >= 1"),
    (["--job-timeout", "inf"], "expected a number of seconds > 0 and <= 1e+09, got 'inf'"),
    (["--job-timeout", "1e10"], "got '1e10'"),
    (["--job-timeout", "nan"], "got 'nan'"),
    (["--job-timeout", "0"], "got '0'"),
    (["--job-timeout", "soon"], "got 'soon'"),
    (["--checkpoint-every", "0"], "expected an integer >= 1 and <= 2147483647"),
    (["--checkpoint-every", "99999999999"], "got '99999999999'"),
    # The tool's number grammar, not Python's int() and float() (before: all of these ran), and
    # each option once, as the C++ commands take them (before: the last one won).
    (["--workers", "257"], "expected an integer >= 1 and <= 256, got '257'"),
    (["--workers", "99999999999999999999"], "got '99999999999999999999'"),
    (["--workers", " 3"], "got ' 3'"),
    (["--job-timeout", "1_000"], "got '1_000'"),
    (["--job-timeout", "3 "], "got '3 '"),
    (["--checkpoint-every", "1_0"], "got '1_0'"),
    (["--checkpoint-every", "\u0663"], "got '\u0663'"),
    (["--shard", " 0/2"], "expected I/N, e.g. 0/4, got ' 0/2'"),
    (["--workers", "2", "--workers", "3"], "option '--workers' cannot be given more than once"),
    (["--dry-run"], "option '--dry-run' cannot be given more than once"),
    (["-o", "elsewhere"], "option '--output' cannot be given more than once"),
    # An option is named in full, as the C++ commands read theirs (before: --work 2 was --workers 2).
    (["--work", "2"], "unrecognized arguments: --work 2"),
    # --workers sizes the embedded cluster, which these two do not start (before: ignored without
    # a word).
    (["--workers", "2", "--shard", "0/2"], "argument --workers: not with --shard"),
    (["--shard", "1/2", "--workers", "1"], "argument --workers: not with --shard"),
    (["--workers", "2", "--scheduler", "tcp://127.0.0.1:8786"],
     "argument --workers: not with --scheduler"),
    (["--job", "3"], "unrecognized arguments: --job 3"),
], ids=lambda v: " ".join(v) if isinstance(v, list) else None)
def test_bad_usage_exits_1_with_a_message(cli, mesh_dir, tmp_path, args, expected):
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    base = [str(path), "-o", str(tmp_path / "out"), "--dry-run"] if args else []
    r = run_sweep(cli, base + args)
    assert r.returncode == 1, (r.returncode, r.stderr)
    assert "shellcontract sweep: error: " in r.stderr and expected in r.stderr, r.stderr
    assert "Traceback" not in r.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("address,expected", [
    ("tcp://127.0.0.1:99999", "the port must be an integer in [1, 65535], got '99999'"),
    ("tcp://127.0.0.1:0", "the port must be an integer in [1, 65535], got '0'"),
    ("tcp://127.0.0.1:8_786", "the port must be an integer in [1, 65535], got '8_786'"),
    ("tcp://127.0.0.1: 8786", "it has a blank"),
])
def test_a_scheduler_address_that_dask_lets_through_is_refused(cli, mesh_dir, tmp_path, address,
                                                               expected):
    """Before: each passed --dry-run (Dask's parse_host_port reads the port with int())."""
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--dry-run", "--scheduler",
                        address])
    assert r.returncode == 1, (r.returncode, r.stderr)
    assert "is not an address tcp://HOST:PORT ({}".format(expected) in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()


def test_the_tools_number_forms_are_still_taken(cli, mesh_dir, tmp_path):
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--dry-run", "--workers", "+3",
                        "--job-timeout", "1e3", "--checkpoint-every", "010"])
    assert r.returncode == 0, r.stderr
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--dry-run", "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--dry-run",
                        "--scheduler", "tcp://[::1]:65535"])
    assert r.returncode == 0, r.stderr


@pytest.mark.parametrize("text", ["3", "+3", "-0", "010", "3.0", ".5", "5.", "+.5", "1e3", "1E+3",
                                  "1e-320", "1e-400", "1e400", " 3", "3 ", "1_000", "0x10", "inf",
                                  "nan", "Infinity", "\u0663", "+-3", "", "e5", "1e", ".", "3,5"])
def test_the_sweeps_numbers_are_read_as_the_library_reads_them(text):
    """number_text (the sweep's options, regions()'s numbers given as text) takes a text exactly
    when the library's option parser does (c01: a finite number >= 0; frames: an integer)."""
    from shellcontract import _core, number_text

    def library_takes(**option):
        try:
            _core.resolve_options(**option)
            return True
        except ValueError:
            return False
    assert (number_text.decimal(text) is not None) == library_takes(c01=text)
    assert (number_text.integer(text) is not None) == library_takes(frames=text)


def test_the_largest_job_timeout_is_taken(cli, mesh_dir, tmp_path):
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--shard", "0/1",
                        "--job-timeout", "1e9"])
    assert r.returncode == 0, r.stderr
    assert "1 done, 0 failed, 0 left" in r.stderr


def test_help_exits_0(cli):
    r = run_sweep(cli, ["--help"])
    assert r.returncode == 0 and "SWEEP.json" in r.stdout


def test_the_jobs_arguments_write_numbers_as_the_tool_does(cli, mesh_dir, tmp_path):
    """--dry-run lists `run`'s arguments as the tool writes numbers (--help, the summary, the
    results' cells): the shortest text that reads back, 1e+06 and 0:1. Before: Python's repr,
    1000000.0 and 0:1.0, and a keyframe text split over words."""
    import shlex
    from shellcontract import _core
    from shellcontract.sweep_results import _cell
    args = list(_core.resolve_options(pressure=1e6, delta=1e-5, young=1000000.0, thickness=0.002,
                                      frames=10, target_volume=[(0, 1.0), (60, 0.5)],
                                      fiber=[1.0, 0, 0], collisions=False)["args"])
    assert args == ["--pressure", "1e+06", "--target-volume", "0:1, 60:0.5", "--frames", "10",
                    "--young", "1e+06", "--thickness", "0.002", "--fiber", "1,0,0",
                    "--collisions", "off", "--delta", "1e-05"]
    spec = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4, "delta": 1e-5},
            "grid": {"pressure": [1e6, 2.0]}, "runs": [{"target_volume": [[0, 1.0], [60, 0.5]]}]}
    path = write_sweep(tmp_path, mesh_dir, "s.json", spec, meshes=("ico1.off",))
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--dry-run"])
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert len(lines) == 2, r.stdout
    for line, pressure in zip(lines, (1e6, 2.0)):
        words = shlex.split(line)[2:]
        assert words[words.index("--pressure") + 1] == _cell(pressure)  # 1e+06, 2
        assert words[words.index("--target-volume") + 1] == "0:1, 60:0.5"
        assert words[words.index("--delta") + 1] == "1e-05"
    assert not (tmp_path / "out").exists()



def test_another_executable_a_huge_grid_and_an_empty_folder_are_refused(cli, mesh_dir, tmp_path):
    """Before: --cli /bin/true ran every job as 'ok' without a result (and a rerun skipped them);
    a grid of 10^8 points ended in a MemoryError; -o "" took the current folder."""
    import shutil
    path = write_sweep(tmp_path, mesh_dir, "s.json", {"meshes": ["meshes/ico1.off"], "options": {"frames": 2}})
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--shard", "0/1", "--cli", shutil.which("true")])
    assert r.returncode == 1 and "is not the shellcontract executable" in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()
    tens = [0.5 + i / 20 for i in range(10)]
    huge = write_sweep(tmp_path, mesh_dir, "huge.json", {
        "meshes": ["meshes/ico1.off"],
        "grid": {name: tens for name in ("pressure", "air_balance", "poisson", "target_ramp", "young", "delta")}})
    r = run_sweep(cli, [str(huge), "-o", str(tmp_path / "out2"), "--dry-run"])
    assert r.returncode == 1 and "make 1000000 jobs; at most 100000" in r.stderr, r.stderr
    r = run_sweep(cli, [str(path), "-o", "", "--dry-run"])
    assert r.returncode == 1 and "-o: empty" in r.stderr, r.stderr
    # Before: --dry-run said yes to a folder under a file; the real run then failed.
    (tmp_path / "afile").write_text("x")
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "afile" / "sub"), "--dry-run"])
    assert r.returncode == 1 and "is a file, not a folder" in r.stderr, r.stderr
    # Before: a traceback from the Dask client, after DIR was claimed.
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out3"), "--scheduler", "bogus"])
    assert r.returncode == 1 and "--scheduler 'bogus' is not an address" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "out3").exists()


def test_a_sweep_whose_stderr_reader_goes_away_runs_every_job(cli, mesh_dir, tmp_path):
    """Before: `sweep ... 2>&1 | head -1` ended at the next progress line with 'Broken pipe',
    exit 1 (documented as 'nothing run'), the jobs left pending."""
    import csv
    import subprocess
    import sys
    from test_sweep import sweep_env
    path = write_sweep(tmp_path, mesh_dir, "s.json", {"meshes": ["meshes/ico1.off"],
                                                       "grid": {"frames": [2, 3, 4]}})
    out = tmp_path / "out"
    p = subprocess.Popen([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out),
                          "--shard", "0/1"], env=sweep_env(cli), stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE)
    p.stderr.close()  # the reader is gone before the first line
    assert p.wait(timeout=120) == 0
    with open(out / "results.csv") as f:
        assert [row["status"] for row in csv.DictReader(f)] == ["ok", "ok", "ok"]


def test_silent_merges_are_refused_and_a_dry_run_lists_its_shard(cli, mesh_dir, tmp_path):
    """Before: a key given twice kept its last value, a grid over threads (or runs that differ
    only in threads) collapsed into one job, and "frames": [5] ran 5 frames, all with exit 0;
    --dry-run --shard listed every job."""
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    path.write_text('{"meshes": ["meshes/ico1.off"], "options": {"frames": 4, "frames": 6}}')
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--dry-run"])
    assert r.returncode == 1 and "the key 'frames' is given twice" in r.stderr, r.stderr
    for spec, expected in [
            ({"meshes": ["meshes/ico1.off"], "grid": {"threads": [1, 2]}},
             "grid option 'threads': it does not change a run's result"),
            ({"meshes": ["meshes/ico1.off"], "options": {"frames": [5]}},
             "frames: got [5]; it takes one value"),
            # Runs that differ only in threads: one id, so the second was dropped silently.
            ({"meshes": ["meshes/ico1.off"], "runs": [{"threads": 1}, {"threads": 2}]},
             "differs from job 0 (ico1.off, threads=1) only in 'threads'")]:
        path = write_sweep(tmp_path, mesh_dir, "s.json", spec, meshes=("ico1.off",))
        r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--dry-run"])
        assert r.returncode == 1 and expected in r.stderr, r.stderr
        assert "Traceback" not in r.stderr
    assert not (tmp_path / "out").exists()
    # A single thread count is an option like any other.
    path = write_sweep(tmp_path, mesh_dir, "s.json", {"meshes": ["meshes/ico1.off"],
                                                      "grid": {"threads": [1], "pressure": [1, 2, 3]}},
                       meshes=("ico1.off",))
    listed = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--dry-run"])
    assert listed.returncode == 0, listed.stderr
    every = listed.stdout.splitlines()
    assert len(every) == 3
    shards = [run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--dry-run", "--shard",
                              "{}/2".format(i)]).stdout.splitlines() for i in range(2)]
    assert shards == [every[0::2], every[1::2]], shards


def test_ctrl_c_while_connecting_to_a_scheduler_ends_with_130_and_no_folder(cli, mesh_dir, tmp_path):
    """The client connects to --scheduler (retrying up to 30 s) before DIR is claimed; Ctrl-C
    there ends the sweep as interrupted (exit 130), not with a traceback."""
    import signal
    import subprocess
    import sys
    import time
    from test_sweep import free_port, sweep_env
    pytest.importorskip("distributed")
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    nobody = "tcp://127.0.0.1:{}".format(free_port())  # nothing listens: the client retries
    p = subprocess.Popen([sys.executable, "-m", "shellcontract.sweep", str(path), "-o",
                          str(tmp_path / "out"), "--scheduler", nobody], env=sweep_env(cli),
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(4)  # past the imports, into the connection's retries
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 130, err
    assert "interrupted before anything ran" in err and "Traceback" not in err, err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("name", ["SIGTERM", "SIGHUP", "SIGUSR1"])
def test_a_stop_signal_is_ctrl_c_only_while_the_sweep_runs(cli, mesh_dir, tmp_path, monkeypatch,
                                                           capsys, name):
    """main() called in a program: SIGTERM, SIGHUP and SIGUSR1 (the CLI's stop signals) raise
    KeyboardInterrupt during the sweep (the jobs save, exit 130), and the program's own handler,
    or an ignored signal, is as it was after. An interrupt before the jobs run (here while asking
    the executable its version) is 130 with a message, not a traceback and an end by SIGINT.
    Before, SIGHUP and SIGUSR1 kept their default, which ends the sweep by the signal."""
    import signal
    from shellcontract import sweep, sweep_process
    sig = getattr(signal, name)
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    seen = []

    def version(cli):
        seen.append(signal.getsignal(sig))
        raise KeyboardInterrupt

    monkeypatch.setattr(sweep, "cli_version", version)
    own = lambda signum, frame: None  # noqa: E731
    for before in (own, signal.SIG_IGN, signal.SIG_DFL):
        signal.signal(sig, before)
        try:
            assert sweep.main([str(path), "-o", str(tmp_path / "out"), "--cli", cli]) == 130
            assert signal.getsignal(sig) == before
            assert "shellcontract sweep: interrupted" in capsys.readouterr().err
        finally:
            signal.signal(sig, signal.SIG_DFL)
    assert [type(h) for h in seen] == [sweep_process.StopRequest, type(signal.SIG_IGN),
                                       sweep_process.StopRequest]
    assert seen[0] is not seen[2]  # one per sweep: a stop is each sweep's own
    assert not (tmp_path / "out").exists()


def _fake_cli(folder, version):
    folder.mkdir()
    exe = folder / "shellcontract"
    exe.write_text("#!/bin/sh\necho 'shellcontract {}'\n".format(version))
    exe.chmod(0o755)
    return exe


def test_a_shellcontract_of_another_version_on_path_is_passed_over(tmp_path, monkeypatch):
    # An installed package whose own CLI is missing, and a `shellcontract` of another version
    # first on PATH (a distribution's beside a newer install): its jobs would run on the other
    # version, recorded as done. The package's layout names its CLI and version (_layout.py).
    from shellcontract import sweep_cli

    class Layout:
        CLI_FROM_PACKAGE = str(tmp_path / "missing" / "shellcontract")
        VERSION = "0.2.0"

    monkeypatch.setattr(sweep_cli, "_layout", lambda: Layout)
    monkeypatch.delenv("SHELLCONTRACT_CLI", raising=False)
    old = _fake_cli(tmp_path / "old", "0.1.9")
    monkeypatch.setenv("PATH", str(old.parent))
    assert sweep_cli.find_cli() is None
    assert "0.1.9" in sweep_cli.PASSED_OVER and "0.2.0" in sweep_cli.PASSED_OVER
    same = _fake_cli(tmp_path / "same", "0.2.0")
    monkeypatch.setenv("PATH", str(same.parent))
    assert sweep_cli.find_cli() == str(same)


def test_the_built_package_finds_its_own_cli(monkeypatch, cli):
    # The build tree's _layout.py names <build>/shellcontract: found without PATH or
    # SHELLCONTRACT_CLI (the installed tree's names <prefix>/bin/shellcontract the same way).
    import os

    from shellcontract import sweep_cli
    monkeypatch.delenv("SHELLCONTRACT_CLI", raising=False)
    monkeypatch.setenv("PATH", "/nonexistent")
    layout = sweep_cli._layout()
    if layout is None:
        pytest.skip("the package runs from the source tree (no _layout.py)")
    assert sweep_cli.find_cli() == os.path.abspath(
        os.path.join(os.path.dirname(sweep_cli.__file__), layout.CLI_FROM_PACKAGE))
    assert os.path.isfile(sweep_cli.find_cli())
