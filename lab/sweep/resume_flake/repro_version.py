"""The test's flow (test_ctrl_c_stops_cleanly_and_a_rerun_resumes_the_interrupted_job[SIGINT]),
with one change: between the interrupted sweep and the rerun, the tool's `--version` changes (as
when `make`/`ninja` relinks build/shellcontract, e.g. building test_cli after a commit or an edit).
A wrapper stands in for the CLI: it execs the real one and appends SUFFIX to --version's text."""
import json, os, shutil, signal, subprocess, sys, time, pathlib
CLI = "/work/main/build/shellcontract"
root = pathlib.Path(sys.argv[1]); shutil.rmtree(root, ignore_errors=True); root.mkdir(parents=True)
change = len(sys.argv) > 2 and sys.argv[2] == "change"
(root / "meshes").mkdir(); shutil.copy("/work/main/meshes/ico3.off", root / "meshes")
spec = {"meshes": ["meshes/ico3.off"], "options": {"pressure": 2, "frames": 1500, "threads": 1},
        "grid": {"air_balance": [0.9, 0.8]}}
path = root / "long.json"; path.write_text(json.dumps(spec))
suffix = root / "suffix"; suffix.write_text("")
fake = root / "cli.sh"
fake.write_text('#!/bin/sh\nif [ "$1" = --version ]; then echo "$(\'%s\' --version)$(cat \'%s\')"; exit 0; fi\n'
                'exec \'%s\' "$@"\n' % (CLI, suffix, CLI))
fake.chmod(0o755)
env = dict(os.environ, PYTHONPATH="/work/main/build/python", SHELLCONTRACT_CLI=str(fake))
out = root / "out"
def done_jobs(): return list((out / "jobs").glob("*/job.json")) if (out / "jobs").is_dir() else []
proc = subprocess.Popen([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out),
                         "--shard", "0/1", "--checkpoint-every", "5"], env=env,
                        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
def second_saved():
    done = {p.parent.name for p in done_jobs()}
    saved = {p.stem for p in (out / ".work" / "checkpoints").glob("*.ckpt")}
    return len(done) == 1 and saved - done
t0 = time.monotonic()
while not second_saved():
    assert time.monotonic() - t0 < 120; time.sleep(0.05)
(out / "results.csv").unlink()
proc.send_signal(signal.SIGINT)
_, err = proc.communicate(timeout=60)
print("first sweep rc", proc.returncode, "| done_jobs", len(done_jobs()),
      "| checkpoints", sorted(p.name for p in (out / ".work" / "checkpoints").iterdir()))
if change:
    suffix.write_text(" rebuilt")  # the binary relinked between the two sweeps
again = subprocess.run([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out), "--shard", "0/1"],
                       env=env, capture_output=True, text=True, timeout=240)
records = [json.loads(p.read_text()) for p in done_jobs()]
print("rerun rc", again.returncode, "| stderr:", again.stderr.strip().splitlines()[0])
print("records", len(records), "| resumed", [r["resumed"] for r in records],
      "| sum(resumed) =", sum(r["resumed"] for r in records), "(the test wants 1)")
print("checkpoints left", sorted(p.name for p in (out / ".work" / "checkpoints").iterdir()))
