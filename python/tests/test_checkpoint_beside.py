"""contract(checkpoint=...) keeps the run's log and volume history beside the checkpoint, in
FILE.log and FILE.history, as the CLI does: each save appends what is new to them, so that a
checkpoint does not grow with the frames run (format 5). Before, every save held the whole log and
the whole history (format 3), so the saves of a long run cost the square of its frames. Such a
checkpoint resumes to the uninterrupted run's result."""
import struct

import numpy as np

import shellcontract

MAGIC = b"SHELLCONTRACT-CHECKPOINT\n"


def format_of(path):
    return struct.unpack_from("<I", path.read_bytes(), len(MAGIC))[0]


def test_saves_append_the_log_and_history_beside_and_resume(tmp_path, mesh_dir):
    v, f = shellcontract.read_mesh(mesh_dir / "ico1.off")
    sizes = {}
    for stop in (20, 80):
        path = tmp_path / f"c{stop}.ckpt"
        r = shellcontract.contract(v, f, frames=90, checkpoint=path, checkpoint_every=10,
                                   callback=lambda fr, vv, m, stop=stop: fr < stop)
        assert r.status == "cancelled"
        assert format_of(path) == 5
        sizes[stop] = path.stat().st_size
        log = (tmp_path / f"c{stop}.ckpt.log").read_text()
        assert log.count("\n") == stop + 1, log  # the header and a row a frame
        assert (tmp_path / f"c{stop}.ckpt.history").stat().st_size == 8 * (stop + 1)
    # 60 more frames: not a byte more in the checkpoint itself.
    assert sizes[80] == sizes[20]
    whole = shellcontract.contract(v, f, frames=90)
    resumed = shellcontract.contract(v, f, resume=tmp_path / "c80.ckpt")
    np.testing.assert_array_equal(resumed.vertices, whole.vertices)
    assert resumed.summary["frames_run"] == whole.summary["frames_run"]
