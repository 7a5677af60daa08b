"""One reading of an integer argument at every door of the package (whole_number,
python/src/option_values.hpp): contract()'s and the sweep's integer options, regions()'s
min_faces and checkpoint_every take an int (numpy's too) or a float whose value is whole, of any
size, and a str of the CLI's integer text."""
import os
import re

import numpy as np
import pytest

import shellcontract
from shellcontract import _core
from test_sweep import run_sweep


@pytest.fixture(scope="module")
def ico1(mesh_dir):
    return shellcontract.read_mesh(mesh_dir / "ico1.off")


def _integer_options():
    """The table's integer options, found by their refusal of 1.5, with their ranges."""
    found = {}
    for option in shellcontract.options():
        try:
            _core.resolve_options(**{option.name: "1.5"})
        except ValueError as e:
            m = re.search(r"is not an integer in \[(\d+), (\d+)\]", str(e))
            if m:
                found[option.name] = (int(m.group(1)), int(m.group(2)))
    return found


def test_every_integer_option_takes_a_whole_float_of_any_size():
    """Before: a float reached the table as shortest_text, 1e+05 for 100000.0, which the integer
    parser refused: frames=1e6 and iterations=1e5 (their upper bounds) were ValueErrors where
    3.0 ran."""
    options = _integer_options()
    assert {"frames", "iterations", "threads", "target_ramp", "collision_rounds"} <= set(options)
    for name, (lo, hi) in options.items():
        for n in {lo, hi, 100000 if lo <= 100000 <= hi else hi}:
            want = _core.resolve_options(**{name: n})["args"]
            for whole in (float(n), np.float64(n), np.array(float(n))):
                assert _core.resolve_options(**{name: whole})["args"] == want, (name, whole)
        # Beyond the range, refused quoting the integer (before: '1e+15').
        with pytest.raises(ValueError, match="'1000000000000000' is not an integer in"):
            _core.resolve_options(**{name: 1e15})
        for bad in (2.5, float("nan"), float("inf")):
            with pytest.raises(ValueError, match="is not an integer in"):
                _core.resolve_options(**{name: bad})


def test_a_number_option_still_quotes_a_round_float_as_the_tool_writes_it():
    with pytest.raises(ValueError, match="'2e\\+06' is not a number"):
        _core.resolve_options(pressure=2e6)
    assert _core.resolve_options(young=1e6)["args"] == ["--young", "1e+06"]


def test_a_sweep_file_takes_a_round_whole_float_for_an_integer_option(cli, mesh_dir, tmp_path):
    """Before: "frames": 1e5 (a JSON number Python reads as 100000.0) refused the whole sweep:
    "--frames: '1e+05' is not an integer in [0, 1000000]"; 50000.0 passed."""
    (tmp_path / "ico1.off").write_bytes((mesh_dir / "ico1.off").read_bytes())
    path = tmp_path / "s.json"
    path.write_text('{"meshes": ["ico1.off"], "options": {"iterations": 1e5},'
                    ' "grid": {"frames": [50000.0, 1e5, 1E6]}}')
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--dry-run"])
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert len(lines) == 3, r.stdout
    for line, frames in zip(lines, ("50000", "100000", "1000000")):
        assert "--frames {} ".format(frames) in line + " ", line
        assert "--iterations 100000" in line, line
    assert not (tmp_path / "out").exists()


def _saves(ico1, path, every):
    """The frames after which the checkpoint had been written anew (seen from the callback)."""
    seen, last = [], None
    def callback(frame, vertices, metrics):
        nonlocal last
        try:
            stat = os.stat(path)
            now = (stat.st_ino, stat.st_mtime_ns)
        except FileNotFoundError:
            now = None
        if now != last:
            seen.append(frame)
            last = now
    shellcontract.contract(*ico1, frames=7, checkpoint=str(path), checkpoint_every=every,
                           callback=callback)
    return seen


@pytest.mark.parametrize("every", [2.0, np.float64(2), np.float32(2), np.array(2.0), np.int64(2),
                                   "2", "+2", "02"])
def test_checkpoint_every_takes_what_frames_takes(ico1, tmp_path, every):
    """Before: 2.0 and "2" were TypeErrors ("expected an integer >= 1"), where frames=2.0 and
    frames="2" run."""
    assert _saves(ico1, tmp_path / "a.ckpt", 2) != _saves(ico1, tmp_path / "b.ckpt", 3)
    assert _saves(ico1, tmp_path / "c.ckpt", every) == _saves(ico1, tmp_path / "d.ckpt", 2)


@pytest.mark.parametrize("every, error", [
    (2.5, ValueError), (float("nan"), ValueError), (float("inf"), ValueError), (0.0, ValueError),
    (2.0 ** 40, ValueError), ("2.0", ValueError), (" 2", ValueError), ("", ValueError),
    ("1_0", ValueError), ("0", ValueError), (True, TypeError), (np.bool_(True), TypeError),
    ([2], TypeError), (np.array([2]), TypeError), (2 + 0j, TypeError)])
def test_checkpoint_every_refuses_what_frames_refuses(ico1, tmp_path, every, error):
    with pytest.raises(error, match="checkpoint_every: expected an integer >= 1, with checkpoint=FILE "
                                    "or resume=FILE, got"):
        shellcontract.contract(*ico1, frames=2, checkpoint=str(tmp_path / "c.ckpt"),
                               checkpoint_every=every)
    assert not (tmp_path / "c.ckpt").exists()
