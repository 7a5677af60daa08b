"""The test's flow with the sweep's SIGINT timed at a chosen moment of the interrupted job's
process (the second job): while its N-th checkpoint save holds its temporary (tests/tools/held_cli:
the temporary created, not yet written or renamed, for HOLD ms), or DELAY seconds after the test's
second_saved() (the plain test's moment plus a delay). Then the rerun, as the test does.
  repro_timing.py ROOT save N [HOLD]   |   repro_timing.py ROOT delay SECONDS"""
import json, os, shutil, signal, subprocess, sys, time, pathlib
CLI = "/work/main/build/shellcontract"; HELD = "/work/main/build/tests/held_cli"
root = pathlib.Path(sys.argv[1]); mode = sys.argv[2]; arg = float(sys.argv[3])
hold = sys.argv[4] if len(sys.argv) > 4 else "300"
shutil.rmtree(root, ignore_errors=True); root.mkdir(parents=True)
(root / "meshes").mkdir(); shutil.copy("/work/main/meshes/ico3.off", root / "meshes")
spec = {"meshes": ["meshes/ico3.off"], "options": {"pressure": 2, "frames": 1500, "threads": 1},
        "grid": {"air_balance": [0.9, 0.8]}}
path = root / "long.json"; path.write_text(json.dumps(spec))
fake = root / "cli.sh"
fake.write_text('#!/bin/sh\ncase "$*" in *"--air-balance 0.8"*) if [ -e \'%s\' ]; then exec \'%s\' %s "$@"; fi;; esac\n'
                'exec \'%s\' "$@"\n' % (root / "hold_on", HELD, hold, CLI))
fake.chmod(0o755)
if mode == "save":
    (root / "hold_on").write_text("")
env = dict(os.environ, PYTHONPATH="/work/main/build/python", SHELLCONTRACT_CLI=str(fake))
out = root / "out"
ids = [l.split()[0] for l in subprocess.run([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out),
        "--dry-run"], env=env, capture_output=True, text=True).stdout.splitlines()]
def done_jobs(): return list((out / "jobs").glob("*/job.json")) if (out / "jobs").is_dir() else []
proc = subprocess.Popen([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out),
                         "--shard", "0/1", "--checkpoint-every", "5"], env=env,
                        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
def second_saved():
    done = {p.parent.name for p in done_jobs()}
    saved = {p.stem for p in (out / ".work" / "checkpoints").glob("*.ckpt")}
    return len(done) == 1 and saved - done
def nth_temporary():
    for m in (out / ".work").glob(ids[1] + ".*/messages.txt"):
        try:
            if m.read_text().count("temporary created") >= arg + 6:  # 6 probes of the outputs first
                return True
        except OSError:
            pass
    return False
t0 = time.monotonic()
cond = nth_temporary if mode == "save" else second_saved
while not cond():
    assert time.monotonic() - t0 < 120 and proc.poll() is None, proc.stderr.read() if proc.poll() is not None else "timeout"
    time.sleep(0.005)
if mode == "delay":
    time.sleep(arg)
ck = out / ".work" / "checkpoints"
before = sorted(p.name for p in ck.iterdir())
proc.send_signal(signal.SIGINT)
_, err = proc.communicate(timeout=60)
after = sorted(p.name for p in ck.iterdir())
msgs = ""
print("first sweep rc", proc.returncode, "| done_jobs", len(done_jobs()), "| ckpt files at signal", before, "after", after)
again = subprocess.run([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out), "--shard", "0/1"],
                       env=env, capture_output=True, text=True, timeout=300)
records = [json.loads(p.read_text()) for p in done_jobs()]
r2 = [r for r in records if r["job"] == ids[1]]
print("rerun rc", again.returncode, "| records", len(records), "| sum(resumed) =", sum(r["resumed"] for r in records),
      "| job2", [(r["status"], r["resumed"], r.get("frames_run")) for r in r2])
