"""The fits of lab/regions/rest_over_time.py: a known similarity and a known affine map of a
random point set are recovered exactly (to rounding), and a motion that neither explains is left
whole (no mesh or run needed)."""
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "regions"))
import rest_over_time  # noqa: E402


def rotation(axis, angle):
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * kx + (1 - np.cos(angle)) * kx @ kx


def test_a_similarity_is_recovered_with_its_scale():
    rng = np.random.default_rng(1)
    p = rng.normal(size=(200, 3))
    q = 0.985 * p @ rotation([1, 2, 3], 0.3).T + np.array([0.1, -0.2, 0.05])
    fitted, scale = rest_over_time.similarity_fit(p, q)
    assert abs(scale - 0.985) < 1e-12
    assert np.abs(fitted - q).max() < 1e-12


def test_an_affine_map_is_recovered_and_a_similarity_leaves_its_shear():
    rng = np.random.default_rng(2)
    p = rng.normal(size=(200, 3))
    a = np.array([[1.0, 0.2, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.9]])
    q = p @ a.T + np.array([0.3, 0.0, -0.1])
    assert np.abs(rest_over_time.affine_fit(p, q) - q).max() < 1e-12
    fitted, _ = rest_over_time.similarity_fit(p, q)
    assert np.abs(fitted - q).max() > 1e-2


def test_a_local_bump_is_left_by_both_fits():
    # Half the points moved along a field that is not affine: neither fit takes it out.
    rng = np.random.default_rng(3)
    p = rng.normal(size=(400, 3))
    q = p.copy()
    q[:, 2] += 0.1 * np.sin(3 * p[:, 0])
    affine = np.linalg.norm(rest_over_time.affine_fit(p, q) - q, axis=1).mean()
    raw = np.linalg.norm(q - p, axis=1).mean()
    assert affine > 0.5 * raw
