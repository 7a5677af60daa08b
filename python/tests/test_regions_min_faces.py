"""regions()'s min_faces: the range the library (check_region_options) and the CLI's
--min-faces accept, said in the message, with the option named as the caller spelt it."""
import pytest

import shellcontract


@pytest.fixture(scope="module")
def bumpy(mesh_dir):
    return shellcontract.read_mesh(mesh_dir / "bumpy_sphere.off")


@pytest.mark.parametrize("min_faces", [1, 5000, 2**31 - 1])
def test_min_faces_takes_what_the_cli_takes(bumpy, min_faces):
    """Before: 5000 was refused ("an integer from 0 to 1000") although --min-faces=5000 runs."""
    got = shellcontract.regions(*bumpy, min_faces=min_faces)
    assert all(len(r) >= min_faces for r in got)


@pytest.mark.parametrize("min_faces", [0, -1, 2**31])
def test_min_faces_out_of_range_says_the_range(bumpy, min_faces):
    """Before: 0 passed the Python check ("from 0 to 1000") and failed in the library with
    "min faces must be >= 1"."""
    with pytest.raises(ValueError, match="min_faces: expected an integer from 1 to 2147483647"):
        shellcontract.regions(*bumpy, min_faces=min_faces)


@pytest.mark.parametrize("given,value,named", [
    ("min_faces", 0, "option min_faces:"), ("min-faces", 0, "option min-faces:"),
    ("fit_tolerance", -1.0, "option fit_tolerance:"), ("max_area_fraction", float("nan"), "option max_area_fraction:"),
])
def test_a_bad_value_names_the_option_as_the_caller_spelt_it(bumpy, given, value, named):
    """Before: min_faces and fit_tolerance were named min-faces and fit-tolerance."""
    with pytest.raises(ValueError, match=named):
        shellcontract.regions(*bumpy, **{given: value})


@pytest.mark.parametrize("value", [0, -1.0, float("inf"), float("nan")])
def test_max_compactness_says_it_must_be_positive_for_every_bad_value(bumpy, value):
    """A cap on a sphere measures below 1, so any bound > 0 is a threshold; 0 had another message
    ("region options: max compactness must be > 0") than -1 ("expected a finite number >= 0")."""
    with pytest.raises(ValueError, match=r"max_compactness: expected a finite number > 0"):
        shellcontract.regions(*bumpy, max_compactness=value)
    assert shellcontract.regions(*bumpy, max_compactness=0.5) is not None
