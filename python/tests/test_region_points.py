"""region_at in regions() and contract(): one parser (the forms and errors are the same in both,
by Python's indices), and one warning for a point far from the surface."""
import warnings

import numpy as np
import pytest

import shellcontract

NAN = float("nan")


@pytest.fixture(scope="module")
def bumpy(mesh_dir):
    return shellcontract.read_mesh(mesh_dir / "bumpy_sphere.off")


def as_lists(regions):
    return [list(r) for r in regions]


@pytest.mark.parametrize("one_point", [(0.3, 0, 0), [0.3, 0, 0], "0.3,0,0", np.array([0.3, 0.0, 0.0]),
                                       [(0.3, 0, 0)], np.array([[0.3, 0.0, 0.0]])])
def test_regions_takes_the_region_at_forms_contract_takes(bumpy, one_point):
    """Before: (x, y, z) and 'X,Y,Z' raised pybind11's "Unable to cast Python instance"."""
    got = shellcontract.regions(*bumpy, region_at=one_point)
    assert len(got) == 1
    assert as_lists(got) == as_lists(shellcontract.regions(*bumpy, region_at=[(0.3, 0.0, 0.0)]))
    assert shellcontract.contract(*bumpy, region_at=one_point, frames=1).summary["regions"] == 1


@pytest.mark.parametrize("points", ["0.3,0,0;-0.3,0,0", [(0.3, 0, 0), (-0.3, 0, 0)],
                                    np.array([[0.3, 0, 0, 9], [-0.3, 0, 0, 9]])[:, :3]])
def test_regions_takes_several_points_in_every_form(bumpy, points):
    got = shellcontract.regions(*bumpy, region_at=points)
    assert as_lists(got) == as_lists(shellcontract.regions(*bumpy, region_at=[(0.3, 0, 0), (-0.3, 0, 0)]))
    assert len(got) == 2


@pytest.mark.parametrize("value,error,fragment", [
    (None, TypeError, "region_at: expected a point"),
    (b"0.3,0,0", TypeError, "got bytes"),
    (5, TypeError, "got int"),
    ([], ValueError, "region_at: expected at least one point"),
    (np.zeros((0, 3)), ValueError, "region_at: expected at least one point"),
    ([(1, 2)], ValueError, r"got \[\(1, 2\)\]"),
    ("", ValueError, "region_at: '' is not a point"),
    ("1,2", ValueError, "region_at: '1,2' is not a point"),
])
def test_region_at_errors_are_the_same_in_regions_and_contract(bumpy, value, error, fragment):
    """Before: regions() gave "'NoneType' object is not iterable" for None and ran the automatic
    search for [] (where contract() said "'' is not a point")."""
    with pytest.raises(error, match=fragment):
        shellcontract.regions(*bumpy, region_at=value)
    with pytest.raises(error, match=fragment):
        shellcontract.contract(*bumpy, region_at=value, frames=1)


@pytest.mark.parametrize("value,fragment", [
    ([(NAN, 0, 0)], r"region_at\[0\] = \(nan, 0.0, 0.0\) is not a point of three finite numbers"),
    ([(1, 0, 0), (0, float("inf"), 0)], r"region_at\[1\] = \(0.0, inf, 0.0\)"),
    ((NAN, 0, 0), r"region_at = \(nan, 0.0, 0.0\)"),
])
def test_a_point_that_is_not_finite_is_named_by_python_index(bumpy, value, fragment):
    """Before: regions() said "region point 1 is not finite" (numbered from 1)."""
    with pytest.raises(ValueError, match=fragment):
        shellcontract.regions(*bumpy, region_at=value)
    with pytest.raises(ValueError, match=fragment):
        shellcontract.contract(*bumpy, region_at=value, frames=1)


@pytest.mark.parametrize("value", [[(1, 0, 0)], (1, 0, 0), np.array([[1.0, 0.0, 0.0]]), "1,0,0"])
def test_the_sweeps_option_check_takes_the_region_at_forms_of_contract(value):
    """The sweep checks its jobs' options with resolve_options. Before: a list of points there was
    read as keyframes ("keyframes are (frame, value) pairs")."""
    args = list(shellcontract._core.resolve_options(region_at=value)["args"])
    i = args.index("--region-at")
    assert [float(c) for c in args[i + 1].split(",")] == [1.0, 0.0, 0.0]


def test_the_sweeps_results_write_several_points_as_the_cli_text():
    """results.csv's cell for region_at=[[x, y, z], ...]: before, all coordinates in one
    comma list, so the points could not be told apart. The numbers as the tool writes them, the
    same text as its resolved option."""
    from shellcontract import _core
    from shellcontract.sweep_results import _cell
    points = [[0.5, 1.0, -2.0], [3.0, 0.0, 1.0]]
    assert _cell(points) == "0.5,1,-2;3,0,1"
    assert _cell(points) == _core.resolve_options(region_at=points)["resolved"]["region_at"]
    assert _cell([0.0, 0.0, 1.0]) == "0,0,1"  # one point (or a fibre direction): one list


def test_a_region_at_point_far_from_the_surface_is_a_warning(bumpy):
    """Before: a point far from the surface (a fitted sphere's centre, a point in Blender's Z-up
    world, (0, 0, 3)) was taken at its nearest surface point with no word."""
    vertices, faces = bumpy
    with pytest.warns(UserWarning, match=r"the 1st region_at point \(0, 0, 3\) is [0-9.]+ from the surface"):
        shellcontract.regions(vertices, faces, region_at=(0, 0, 3))
    summary = shellcontract.contract(vertices, faces, region_at=(0, 0, 3), frames=1).summary
    assert any(w.startswith("the 1st region_at point (0, 0, 3) is ") for w in summary["warnings"])
    # A vertex, and a point a percent of the bounding box's diagonal from it: no warning.
    diagonal = np.linalg.norm(vertices.max(axis=0) - vertices.min(axis=0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for point in (vertices[7], vertices[7] + 0.01 * diagonal * np.array([0.6, 0.0, 0.8])):
            assert len(shellcontract.regions(vertices, faces, region_at=point)) == 1
            summary = shellcontract.contract(vertices, faces, region_at=point, frames=1).summary
            assert not any("region_at point" in w for w in summary.get("warnings", []))
