"""The helpers of lab/scripts/paper_figures.py: the rasterizer's depth test, the up-axis rule and the
fibre-strain measure (numpy only; no CLI run)."""
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "scripts"))
import mesh_measures  # noqa: E402
import render_mesh  # noqa: E402


def two_overlapping_triangles(near_first):
    """Two triangles covering the centre pixel of a 20x20 image, at depths 1 (near, red) and
    -1 (far, blue), in either order of drawing."""
    near = [[2, 2, 1.0], [18, 2, 1.0], [10, 18, 1.0]]
    far = [[1, 1, -1.0], [19, 1, -1.0], [10, 19, -1.0]]
    P = np.array(near + far if near_first else far + near)
    F = np.array([[0, 1, 2], [3, 4, 5]])
    rgb = np.array([[1.0, 0, 0], [0, 0, 1.0]] if near_first else [[0, 0, 1.0], [1.0, 0, 0]])
    return P, F, rgb


def test_near_triangle_hides_far_one_whatever_the_order():
    for near_first in (True, False):
        P, F, rgb = two_overlapping_triangles(near_first)
        img, covered = render_mesh.rasterize(P, F, rgb, 20, 20)
        assert covered[10, 10]
        assert np.allclose(img[10, 10], [1, 0, 0]), near_first
        # Where only the far triangle reaches (its wider rim), it shows.
        assert np.allclose(img[1, 10], [0, 0, 1])


def pyramid(up_axis):
    """A square pyramid standing on its base (outward normals), apex along +up_axis."""
    V = np.array([[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1], [0, 2, 0]], float)
    F = np.array([[0, 1, 2], [0, 2, 3], [0, 4, 1], [1, 4, 2], [2, 4, 3], [3, 4, 0]])
    if up_axis == "z":  # rotate y -> z (x, y, z) -> (x, -z, y): still a right-handed turn
        V = np.column_stack([V[:, 0], -V[:, 2], V[:, 1]])
    assert mesh_measures.volume(V, F) > 0
    return V, F


def test_up_axis_is_the_axis_the_mesh_stands_on():
    for axis in ("y", "z"):
        V, F = pyramid(axis)
        assert np.allclose(render_mesh.detect_up(V, F), render_mesh.AXES[axis]), axis


def test_fibre_strains_of_a_uniform_shrink():
    V, F = pyramid("y")
    along, across = mesh_measures.fibre_strains(V, 0.9 * V, F, [2, 3, 4, 5])
    assert abs(along + 0.1) < 1e-12 and abs(across + 0.1) < 1e-12


def test_jitter_counts_the_frames_where_the_volume_goes_up():
    assert mesh_measures.jitter_frames([1.0, 0.9, 0.95, 0.94, 0.96]) == 2
    assert mesh_measures.reversals([1.0, 0.9, 0.95, 0.94, 0.96]) == 3
    # A shell at rest wobbling in the ninth digit does not jitter.
    assert mesh_measures.jitter_frames([0.9, 0.9 + 1e-9, 0.9, 0.9 + 2e-9]) == 0


def test_view_toward_looks_from_the_given_direction():
    for up in ("y", "z", "-x"):
        u = render_mesh.parse_axis(up)
        d = np.array([0.3, -0.5, 0.8])
        d -= 0.4 * (d @ u) * u  # keep the elevation under the 60 degree clip
        d /= np.linalg.norm(d)
        toward = render_mesh.camera_basis(u, *render_mesh.view_toward(d, u))[2]
        assert np.allclose(toward, d), up


def test_cli_arguments_become_the_sweeps_options():
    import figure_sweep
    opts = figure_sweep.to_options(["--k-b", "0.1", "--measure-regions", "--pressure", "-2",
                                    "--regions", "/tmp/r.txt"])
    # A negative number is the value of --pressure, not a flag; a flag with no value a switch.
    assert opts == {"k_b": "0.1", "measure_regions": True, "pressure": "-2",
                    "regions": "/tmp/r.txt"}


def test_the_papers_model_is_added_only_where_a_figure_does_not_set_it():
    import figure_sweep
    args = figure_sweep.paper_args(["--pressure", 0, "--aniso", "arap"])
    opts = figure_sweep.to_options(args)
    assert opts["pressure"] == "0"  # the figure's own value is kept
    assert opts["solver"] == "pbd" and opts["bending"] == "isometric"
    assert opts["order"] == "sequential"
    assert opts["air_balance"] == "0"
    # A local-contraction run gets the paper's region pressure.
    assert opts["inward"] == "force" and opts["region_shrink"] == "0.3"
    assert "inward" not in figure_sweep.to_options(figure_sweep.paper_args(["--frames", 5]))
