"""contract(resume=...) on a checkpoint edited by hand and resealed: the checksum at its end is
FNV-1a over the bytes before it, which anyone can recompute, so the fields are checked as input.
Each forgery is a ValueError naming the file and the field. Before: a NaN position and a frame
past the run's end were resumed (the CLI ended in std::terminate and in "1000000 frames")."""
import struct

import pytest

import shellcontract

MAGIC = b"SHELLCONTRACT-CHECKPOINT\n"


def fnv1a(data):
    h = 1469598103934665603
    for byte in data:
        h = ((h ^ byte) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return h


def reseal(body):
    return body + struct.pack("<Q", fnv1a(body))


def field_offsets(data):
    """Offsets of the frame and of the first position (src/sim/checkpoint.cpp's order)."""
    at = len(MAGIC)
    (fmt,) = struct.unpack_from("<I", data, at)
    at += 4

    def skip_text(at):
        (n,) = struct.unpack_from("<Q", data, at)
        return at + 8 + n

    at = skip_text(skip_text(at)) + 8  # version, input, the input's hash
    if fmt >= 2:  # format 2 added the inputs (format 3 the interval between saves, at the end)
        (n,) = struct.unpack_from("<Q", data, at)
        at += 8
        for _ in range(n):
            at = skip_text(skip_text(at)) + 1 + 8
    for _ in range(2):  # the options given, then resolved
        (n,) = struct.unpack_from("<Q", data, at)
        at += 8
        for _ in range(2 * n):
            at = skip_text(at)
    frame = at
    at += 8 + 8 + 1 + 16  # frame, V/V0, stop reached, the positions' rows and columns
    return frame, at


@pytest.fixture
def saved(tmp_path, ico2):
    v, f = ico2
    path = tmp_path / "c.ckpt"
    r = shellcontract.contract(v, f, callback=lambda fr, vv, m: fr < 4, checkpoint=path, checkpoint_every=4,
                               frames=10)
    assert r.status == "cancelled"
    return path


def forged(saved, offset, packed):
    body = bytearray(saved.read_bytes()[:-8])
    body[offset:offset + len(packed)] = packed
    path = saved.parent / "forged.ckpt"
    path.write_bytes(reseal(bytes(body)))
    return path


def test_the_resealed_unedited_checkpoint_resumes(saved, ico2):
    path = forged(saved, 0, MAGIC)
    assert shellcontract.contract(*ico2, resume=path).status == "ok"


def test_a_nan_position_is_a_value_error_naming_the_file_and_field(saved, ico2):
    _, x = field_offsets(saved.read_bytes())
    path = forged(saved, x, struct.pack("<d", float("nan")))
    with pytest.raises(ValueError, match=r"checkpoint .*forged\.ckpt: the positions: vertex 0 .*not finite"):
        shellcontract.contract(*ico2, resume=path)


def test_a_frame_past_the_run_is_a_value_error(saved, ico2):
    frame, _ = field_offsets(saved.read_bytes())
    assert struct.unpack_from("<q", saved.read_bytes(), frame)[0] == 4
    path = forged(saved, frame, struct.pack("<q", 1000000))
    with pytest.raises(ValueError, match=r"forged\.ckpt: the frame: 1000000 is not before the run's end \(10 frames\)"):
        shellcontract.contract(*ico2, resume=path)
