"""contract(checkpoint=..., resume=...): a run stopped and continued from its checkpoint gives the
uninterrupted run's result bit for bit, its log included; the CLI and Python resume each other's
checkpoints; a checkpoint of other options or another mesh is refused, saying which."""
import subprocess

import numpy as np
import pytest

import shellcontract

TIMING = {"step_ms", "solve_ms", "ccd_ms"}
OPTIONS = dict(frames=50, target_volume=0.3, target_ramp=20)


def stop_at(frame):
    return lambda f, v, m: f < frame  # False at `frame`: the run stops there


def assert_same_result(a, b):
    np.testing.assert_array_equal(a.vertices, b.vertices)
    assert a.summary["frames_run"] == b.summary["frames_run"]
    assert a.summary["final_volume_ratio"] == b.summary["final_volume_ratio"]
    for column in a.log:
        if column not in TIMING:
            np.testing.assert_array_equal(a.log[column], b.log[column], err_msg=column)


def test_stopped_and_resumed_equals_the_whole_run(tmp_path, mesh_dir):
    v, f = shellcontract.read_mesh(mesh_dir / "ico2.off")
    whole = shellcontract.contract(v, f, **OPTIONS)
    path = tmp_path / "run.ckpt"
    stopped = shellcontract.contract(v, f, callback=stop_at(20), checkpoint=str(path),
                                     checkpoint_every=10, **OPTIONS)
    assert stopped.status == "cancelled" and stopped.summary["frames_run"] == 20
    # The options come from the checkpoint; another thread count is allowed.
    resumed = shellcontract.contract(v, f, resume=str(path), threads=1)
    assert resumed.status == whole.status
    assert len(resumed.log["frame"]) == 50
    assert_same_result(whole, resumed)
    assert not np.array_equal(stopped.vertices, whole.vertices)  # the stop was really mid-run


def test_python_resumes_the_cli_checkpoint(cli, tmp_path, mesh_dir):
    mesh = mesh_dir / "ico2.off"
    ckpt = tmp_path / "cli.ckpt"
    whole_out = tmp_path / "whole.off"
    args = ["--frames", "50", "--target-volume", "0.3", "--target-ramp", "20"]
    subprocess.run([cli, "run", str(mesh), "-o", str(whole_out), "-q"] + args, check=True)
    # A CLI run saving every 7 frames, of which the one at frame 49 is the last before its end.
    subprocess.run([cli, "run", str(mesh), "-o", str(tmp_path / "x.off"), "-q", "--checkpoint",
                    str(ckpt), "--checkpoint-every", "7"] + args, check=True)
    v, f = shellcontract.read_mesh(mesh)
    resumed = shellcontract.contract(v, f, resume=str(ckpt))
    assert resumed.summary["frames_run"] == 50
    out = tmp_path / "resumed.off"
    shellcontract.write_mesh(out, resumed.vertices, resumed.faces)
    assert out.read_bytes() == whole_out.read_bytes()


def test_refuses_other_options_and_another_mesh(tmp_path, mesh_dir):
    v, f = shellcontract.read_mesh(mesh_dir / "ico2.off")
    path = tmp_path / "run.ckpt"
    shellcontract.contract(v, f, callback=stop_at(5), checkpoint=str(path), checkpoint_every=5,
                           frames=20)
    # By Python's name (the library names it by field; the CLI says --pressure).
    with pytest.raises(ValueError, match=r"other options: pressure 3 \(the checkpoint's: 4\)"):
        shellcontract.contract(v, f, resume=str(path), pressure=3)
    v1, f1 = shellcontract.read_mesh(mesh_dir / "ico1.off")
    # Before: "the vertices and faces given is not the mesh <arrays> it was written for (or that
    # file has changed)": a placeholder for a name, and a file where there was none.
    with pytest.raises(ValueError, match="another input") as refused:
        shellcontract.contract(v1, f1, resume=str(path))
    assert "<arrays>" not in str(refused.value) and "file" not in str(refused.value)
    assert "the vertices and faces given are not" in str(refused.value)
