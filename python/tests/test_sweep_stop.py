"""A sweep stopped by several signals at once (a service manager's SIGTERM then SIGHUP, a batch
system's SIGUSR1 and then SIGTERM, a double Ctrl-C) stops once: its jobs save their checkpoints,
the tables are written, exit 130 (docs/design/sweeps.md, "Ctrl-C or SIGTERM")."""
import os
import signal
import subprocess
import sys
import time

import pytest

from test_sweep import results, sweep_env, wait_until, write_sweep

# Two jobs that run for minutes unless stopped, on the embedded cluster's two workers.
LONG = {"meshes": ["meshes/ico3.off"], "options": {"frames": 200000, "threads": 1},
        "grid": {"thickness": [0.002, 0.004]}}


@pytest.mark.parametrize("signals", [("SIGTERM", "SIGHUP"), ("SIGUSR1", "SIGTERM"),
                                     ("SIGINT", "SIGINT")])
def test_a_stop_in_several_signals_stops_once_and_the_jobs_save(cli, mesh_dir, tmp_path, signals):
    path = write_sweep(tmp_path, mesh_dir, "long.json", LONG, meshes=("ico3.off",))
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "shellcontract.sweep", str(path), "-o", str(out),
                             "--workers", "2", "--checkpoint-every", "1000"], env=sweep_env(cli),
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    checkpoints = out / ".work" / "checkpoints"
    try:
        # Both jobs in their frames: each has written its first checkpoint (frame 1000). A sleep
        # after their attempt folders appeared was not enough on a loaded machine: a job stopped
        # while its run is prepared has no state to save.
        wait_until(lambda: len(list(checkpoints.glob("*.ckpt"))) == 2)
        before = {p.name: p.read_bytes() for p in checkpoints.glob("*.ckpt")}
        for name in signals:
            os.kill(proc.pid, getattr(signal, name))
            time.sleep(0.001)
        # Before: the second signal, raised again inside the stop, left the sweep waiting on jobs
        # it had not told to stop (still running after 20 s, tracebacks on stderr).
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 130, err
    assert "Traceback" not in err, err
    # Each job saved its checkpoint on the way out: a later state than the one seen before.
    saved = sorted(p.name for p in checkpoints.glob("*.ckpt"))
    assert len(saved) == 2, (saved, err)
    assert all((checkpoints / name).read_bytes() != before[name] for name in saved), err
    assert [r["status"] for r in results(out)] == ["pending", "pending"], err
