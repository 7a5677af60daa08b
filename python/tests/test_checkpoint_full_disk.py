"""contract(checkpoint=...) when a save cannot be written (a full disk; here a file size limit,
which gives EFBIG where a full disk gives ENOSPC): the run goes on and returns its result, with a
UserWarning and the same text in summary["warnings"], as the CLI warns and goes on. Before, the
first failed save raised ValueError at that frame and the whole run was lost."""
import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import shellcontract

# Run in a child: RLIMIT_FSIZE would limit this process's own files too. CPython ignores SIGXFSZ,
# so a write past the limit fails with EFBIG instead of ending the process.
CHILD = textwrap.dedent("""
    import json, os, resource, sys, warnings
    import shellcontract
    mesh, folder = sys.argv[1], sys.argv[2]
    v, f = shellcontract.read_mesh(mesh)
    # The first save's size, then a limit a little above it: the checkpoint carries the log of
    # the frames so far, so the later saves outgrow it.
    first = os.path.join(folder, "first.ckpt")
    shellcontract.contract(v, f, frames=120, checkpoint=first, checkpoint_every=5,
                           callback=lambda fr, vv, m: fr < 5)
    limit = os.path.getsize(first) + 2048
    os.remove(first)
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
    path = os.path.join(folder, "c.ckpt")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            r = shellcontract.contract(v, f, frames=120, checkpoint=path, checkpoint_every=5)
        except Exception as e:  # the behaviour before the fix
            print(json.dumps({"raised": type(e).__name__ + ": " + str(e)}))
            sys.exit(0)
    print(json.dumps({"status": r.status, "frames_run": r.summary["frames_run"],
                      "warned": [str(w.message) for w in caught if w.category is UserWarning],
                      "summary_warnings": r.summary.get("warnings", []),
                      "vertices": r.vertices.tolist()}))
""")


def test_a_failed_save_warns_and_the_run_goes_on(tmp_path, mesh_dir):
    mesh = str(mesh_dir / "ico1.off")
    child = subprocess.run([sys.executable, "-c", CHILD, mesh, str(tmp_path)], capture_output=True,
                           text=True, env=dict(os.environ, PYTHONDONTWRITEBYTECODE="1"))
    assert child.returncode == 0, child.stderr
    got = json.loads(child.stdout.strip().splitlines()[-1])
    assert "raised" not in got, got["raised"]
    v, f = shellcontract.read_mesh(mesh)
    whole = shellcontract.contract(v, f, frames=120)
    assert got["status"] == whole.status and got["frames_run"] == whole.summary["frames_run"]
    assert len(got["warned"]) == 1, got["warned"]
    warning = got["warned"][0]
    assert warning.startswith("checkpoint not written "), warning
    assert "too large" in warning, warning
    assert warning in got["summary_warnings"]
    # What it says is left is there: an older whole checkpoint, which resumes to the result.
    assert "the checkpoint of frame " in warning and str(tmp_path / "c.ckpt") in warning, warning
    np.testing.assert_array_equal(np.array(got["vertices"]), whole.vertices)
    resumed = shellcontract.contract(v, f, resume=str(tmp_path / "c.ckpt"))
    np.testing.assert_array_equal(resumed.vertices, whole.vertices)
