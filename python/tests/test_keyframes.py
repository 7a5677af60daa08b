"""Keyframed target volume and pressure, and per-vertex region weights, from Python
(docs/design/keyframes.md)."""
import numpy as np
import pytest

import shellcontract


def tetra_volume(vertices, faces):
    """|V| of a closed mesh by the divergence theorem, computed here (not the module's number)."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return abs(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def test_target_follows_keys_down_and_back_up(ico2):
    vertices, faces = ico2
    v0 = tetra_volume(vertices, faces)
    seen = {}

    def keep(frame, v, metrics):
        seen[frame] = tetra_volume(v, faces) / v0

    result = shellcontract.contract(vertices, faces, frames=70, callback=keep, validate="end",
                                    target_volume="0:1, 25:0.6, 35:0.6, 60:0.95, 70:0.95")
    assert result.status == "ok", result.summary["failure"]
    assert result.summary["new_intersections"] == 0
    for frame in range(25, 36):
        assert seen[frame] == pytest.approx(0.6, abs=0.005), frame
    for frame in range(60, 71):
        assert seen[frame] == pytest.approx(0.95, abs=0.005), frame
    # The summary records the schedule, in a form that parses back to it.
    assert result.summary["options"]["target_volume"] == "0:1, 25:0.6, 35:0.6, 60:0.95, 70:0.95"


def test_pairs_and_arrays_are_the_same_schedule_as_text(ico2):
    vertices, faces = ico2
    text = shellcontract.contract(vertices, faces, frames=20, target_volume="0:1, 15:0.7")
    pairs = shellcontract.contract(vertices, faces, frames=20, target_volume=[(0, 1), (15, 0.7)])
    array = shellcontract.contract(vertices, faces, frames=20,
                                   target_volume=np.array([[0, 1.0], [15, 0.7]]))
    np.testing.assert_array_equal(text.vertices, pairs.vertices)
    np.testing.assert_array_equal(text.vertices, array.vertices)
    assert pairs.summary["options"]["target_volume"] == "0:1, 15:0.7"
    # A float array's whole frames (15.0) are frames.
    assert text.log["volume_ratio"][14] == pytest.approx(0.7, abs=0.005)


def test_single_number_is_unchanged(ico2):
    vertices, faces = ico2
    single = shellcontract.contract(vertices, faces, frames=20, target_volume=0.7)
    assert single.summary["options"]["target_volume"] == "0.7"


@pytest.mark.parametrize("keys, parts", [
    ("0:1, 60:0.5, 50:0.8", ["key 3", "50:0.8"]),
    ("0:1, 60:3", ["key 2", "(0, 2]"]),
    ("0:1, junk", ["key 2"]),
    ([(0, 1), (10, 0.5, 2)], ["pairs"]),
])
def test_bad_keys_are_refused_naming_the_key(ico2, keys, parts):
    vertices, faces = ico2
    with pytest.raises(ValueError) as e:
        shellcontract.contract(vertices, faces, frames=5, target_volume=keys)
    for p in parts:
        assert p in str(e.value)


def test_pressure_keys_reverse_the_motion(ico2):
    vertices, faces = ico2
    v0 = tetra_volume(vertices, faces)
    r = shellcontract.contract(vertices, faces, frames=120, air_balance=0,
                               pressure=[(0, 4), (40, 4), (60, -4)])
    ratios = r.log["volume_ratio"]
    assert ratios[39] < 0.99
    assert ratios[119] > ratios[59] + 0.01
    assert tetra_volume(r.vertices, faces) / v0 == pytest.approx(ratios[119], abs=1e-9)


def weights_near(vertices, axis=0, above=0.6):
    """1 on the vertices beyond `above` along an axis (a cap of the sphere), 0 elsewhere."""
    span = vertices[:, axis].max() - vertices[:, axis].min()
    cut = vertices[:, axis].min() + above * span
    return (vertices[:, axis] > cut).astype(np.float64)


def test_weights_make_regions_and_scale_their_sink(mesh_dir):
    vertices, faces = shellcontract.read_mesh(mesh_dir / "ico3.off")
    w = weights_near(vertices)
    full = shellcontract.contract(vertices, faces, frames=60, pressure=0, region_weights=w)
    half = shellcontract.contract(vertices, faces, frames=60, pressure=0, region_weights=0.5 * w)
    none = shellcontract.contract(vertices, faces, frames=60, pressure=0,
                                  region_weights=np.zeros(len(vertices)))
    assert full.summary["regions"] == 1
    assert none.summary["regions"] == 0
    sink_full = full.summary["region_inward_displacement"]
    sink_half = half.summary["region_inward_displacement"]
    # The weight is the strength: half the weight sinks the cap in, less far.
    assert sink_full > 0.0 and sink_half > 0.0
    assert sink_half < 0.8 * sink_full
    # The weights are the regions: recorded under region_weights, `regions` not given (a rerun
    # refuses `regions` beside them; docs/cli.md, the summary's options).
    assert full.summary["options"]["regions"] == ""
    assert full.summary["options"]["region_weights"] == "<weights given as an array>"


def test_bad_weights_are_refused(ico2):
    vertices, faces = ico2
    with pytest.raises(ValueError, match="weights for"):
        shellcontract.contract(vertices, faces, frames=2, region_weights=np.ones(5))
    w = np.zeros(len(vertices))
    w[7] = 1.5
    with pytest.raises(ValueError, match=r"region_weights\[7\] = 1.5"):
        shellcontract.contract(vertices, faces, frames=2, region_weights=w)
    with pytest.raises(ValueError, match="exclude"):
        shellcontract.contract(vertices, faces, frames=2, regions="auto",
                               region_weights=np.zeros(len(vertices)))
