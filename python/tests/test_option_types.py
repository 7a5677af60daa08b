"""Which Python types the options take: contract() and regions() by one rule (an int or a float,
numpy's too; a whole float for an integer; a str of the CLI's number text; a bool, numpy's too,
only for on/off options), and keyframes as (frame, value) pairs, never a list of numbers (the
sweep file's values go through the same check)."""
import json

import numpy as np
import pytest

import shellcontract
from test_sweep import run_sweep


@pytest.fixture(scope="module")
def bumpy(mesh_dir):
    return shellcontract.read_mesh(mesh_dir / "bumpy_sphere.off")


def _faces(found):
    return [list(r) for r in found]


def test_regions_takes_a_whole_float_and_number_text_as_contract_does(bumpy):
    """Before: contract(frames=3.0) and contract(mu="3") ran, regions(min_faces=3.0) and
    regions(contrast="0.5") were TypeErrors."""
    plain = _faces(shellcontract.regions(*bumpy, min_faces=3, contrast=0.5))
    assert plain  # the options are used: bumpy_sphere has regions with them
    for min_faces in (3.0, np.float64(3.0), np.float32(3.0), "3", np.int64(3)):
        for contrast in (0.5, "0.5", "+.5", "5e-1", np.float32(0.5)):
            got = shellcontract.regions(*bumpy, min_faces=min_faces, contrast=contrast)
            assert _faces(got) == plain, (min_faces, contrast)
    vertices, faces = bumpy
    assert (shellcontract.contract(vertices, faces, frames=3.0, mu="1").summary["frames_run"]
            == shellcontract.contract(vertices, faces, frames=3, mu=1).summary["frames_run"] == 3)


@pytest.mark.parametrize("options,fragment", [
    ({"min_faces": 3.5}, "min_faces: expected an integer from 1 to 2147483647, got 3.5"),
    ({"min_faces": float("nan")}, "min_faces: expected an integer"),
    ({"min_faces": "3.0"}, "min_faces: '3.0' is not an integer"),
    ({"min-faces": " 3"}, "min-faces: ' 3' is not an integer"),
    ({"contrast": "0,5"}, "contrast: '0,5' is not a number"),
    ({"contrast": "0x1"}, "contrast: '0x1' is not a number"),
    ({"fit_tolerance": "inf"}, "fit_tolerance: 'inf' is not a number"),
])
def test_regions_refuses_what_contract_refuses_with_a_value_error(bumpy, options, fragment):
    with pytest.raises(ValueError) as e:
        shellcontract.regions(*bumpy, **options)
    assert fragment in str(e.value)


@pytest.mark.parametrize("text", ["0.5", "+0.5", ".5", "5e-1", "1e-320", "1e-400", " 0.5", "0.5 ",
                                  "0x1", "0,5", "1_0", "nan", "inf", "", "\u0665"])
def test_regions_and_contract_take_the_same_number_texts(bumpy, text):
    """contrast and c01 have one range (a finite number >= 0): a text is a number to both or to
    neither."""
    def takes(call):
        try:
            call()
            return True
        except ValueError:
            return False
    regions_takes = takes(lambda: shellcontract.regions(*bumpy, contrast=text))
    contract_takes = takes(lambda: shellcontract._core.resolve_options(c01=text))
    assert regions_takes == contract_takes, (text, regions_takes, contract_takes)


@pytest.mark.parametrize("value", [True, np.bool_(True), np.bool_(False), np.array(True)])
def test_a_bool_for_a_number_is_a_type_error_of_any_kind(bumpy, value):
    """Before: np.bool_(True) for frames was a ValueError "'on' is not an integer", and for
    regions()'s contrast or min_faces was taken as 1."""
    vertices, faces = bumpy
    for name in ("frames", "threads", "damping"):
        with pytest.raises(TypeError, match=name + ": got the bool"):
            shellcontract.contract(vertices, faces, **{name: value})
    for name in ("contrast", "min_faces"):
        with pytest.raises(TypeError, match="regions\\(\\) option " + name):
            shellcontract.regions(vertices, faces, **{name: value})
    # The on/off options take them.
    off = shellcontract.contract(vertices, faces, frames=1, collisions=np.bool_(False))
    assert off.summary["options"]["collisions"] == "off"


@pytest.mark.parametrize("keys,named", [
    ([(0, 4), (True, 0)], "key 2 = (True, 0): its frame is a bool"),
    ([(0, 4), (2, np.bool_(False))], "key 2 = (2, False): its value is a bool"),
    ([(True, 1)], "key 1 = (True, 1): its frame is a bool"),
])
def test_a_bool_in_a_keyframe_is_a_type_error_naming_the_key(bumpy, keys, named):
    """Before: the key was reported as 'on:0'."""
    with pytest.raises(TypeError) as e:
        shellcontract.contract(*bumpy, frames=2, pressure=keys)
    assert named in str(e.value)


@pytest.mark.parametrize("name,value", [
    ("pressure", [1]), ("pressure", [1, 2]), ("pressure", (4.0,)), ("pressure", []),
    ("target_volume", np.array([0.5])), ("target_volume", [0.5, 0.7]),
    ("pressure", [(0, 4), 5]),
])
def test_a_list_of_numbers_for_a_keyframe_option_is_refused(bumpy, name, value):
    """Before: pressure=[1] ran as pressure=1 and target_volume=np.array([0.5]) as 0.5, while
    pressure=[1, 2] was "'1,2' is not a number"."""
    with pytest.raises(TypeError) as e:
        shellcontract.contract(*bumpy, frames=2, **{name: value})
    assert "{}: got ".format(name) in str(e.value)
    assert "keyframes: a list of (frame, value) pairs" in str(e.value)


def test_keyframes_still_come_as_pairs_arrays_text_or_one_number(bumpy):
    vertices, faces = bumpy
    runs = [shellcontract.contract(vertices, faces, frames=3, pressure=p)
            for p in ([(0, 4), (2, 1)], [[0, 4], [2, 1]], np.array([[0, 4.0], [2, 1]]),
                      "0:4, 2:1", ((0, 4), (2, 1)))]
    assert all(r.summary["options"]["pressure"] == "0:4, 2:1" for r in runs)
    assert all((r.vertices == runs[0].vertices).all() for r in runs)
    for one in (4, 4.0, np.float64(4), np.array(4.0), "4"):
        assert shellcontract.contract(vertices, faces, frames=1, pressure=one).summary[
            "options"]["pressure"] == "4"


def test_help_says_how_to_give_keyframes():
    doc = shellcontract.contract.__doc__
    assert "pressure" in doc and "target_volume" in doc
    for form in ("(frame, value) pairs", "N by 2", '"0:1, 60:0.5"'):
        assert form in doc, form


def test_a_sweep_file_refuses_a_list_of_numbers_for_keyframes(cli, mesh_dir, tmp_path):
    """docs/design/sweeps.md: a list for an option of one value is refused. Before,
    "pressure": [0.5] was listed and run as --pressure 0.5."""
    (tmp_path / "ico1.off").write_bytes((mesh_dir / "ico1.off").read_bytes())
    for value, code in (([0.5], 1), ([[0, 4], [2, 0]], 0)):
        path = tmp_path / "s.json"
        path.write_text(json.dumps({"meshes": ["ico1.off"],
                                    "options": {"frames": 2, "pressure": value}}))
        r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--dry-run"])
        assert r.returncode == code, r.stderr
        if code:
            assert "pressure: got [0.5]; it takes one value, or keyframes" in r.stderr, r.stderr
        else:
            assert "--pressure '0:4, 2:0'" in r.stdout, r.stdout
    assert not (tmp_path / "out").exists()
