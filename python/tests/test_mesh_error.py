"""shellcontract.MeshError: a mesh refused because of particular faces (or of a non-manifold
vertex: the faces around it) raises a ValueError subclass whose `faces` lists their indices into
the faces array, all of them (the message lists at most ten), so that a caller with its own face numbering (the Blender add-on) maps them
without reading the message's text."""
import numpy as np
import pytest

import shellcontract


def test_mesh_error_is_a_value_error():
    assert issubclass(shellcontract.MeshError, ValueError)
    assert shellcontract.MeshError.__name__ == "MeshError"
    assert "MeshError" in shellcontract.__all__


def test_degenerate_face_names_it(ico2):
    v, f = ico2
    f = f.copy()
    f[7, 2] = f[7, 0]
    with pytest.raises(shellcontract.MeshError, match="degenerate face: face 7 uses vertex") as e:
        shellcontract.contract(v, f, frames=1)
    assert isinstance(e.value, ValueError)
    assert e.value.faces == [7]
    assert all(type(i) is int for i in e.value.faces)


def test_non_manifold_edge_lists_every_face(ico2):
    """Eleven triangles added on face 0's first edge: 13 faces share it, the message lists ten,
    `faces` all 13 (in the message's order: by index)."""
    v, f = ico2
    a, b = int(f[0, 0]), int(f[0, 1])
    other = [i for i in range(1, len(f)) if {a, b} <= set(int(x) for x in f[i])]
    assert len(other) == 1
    extra_v = v.mean(axis=0) + 0.01 * np.arange(1, 12)[:, None] * np.array([1.0, 0.3, 0.7])
    extra_f = [[b, a, len(v) + k] for k in range(11)]
    v2 = np.vstack([v, extra_v])
    f2 = np.vstack([f, np.array(extra_f, dtype=f.dtype)])
    with pytest.raises(ValueError, match=r"non-manifold edge: .* is shared by 13 faces \(") as e:
        shellcontract.contract(v2, f2, frames=1)
    assert type(e.value) is shellcontract.MeshError
    expected = [0, other[0]] + list(range(len(f), len(f) + 11))
    assert e.value.faces == expected
    listed = str(e.value).split("faces (")[1].split(")")[0]
    assert listed == ", ".join(str(i) for i in expected[:10])


def test_open_boundary_names_the_face(ico2):
    v, f = ico2
    removed = 10
    f2 = np.delete(f, removed, axis=0)
    with pytest.raises(shellcontract.MeshError, match="open boundary") as e:
        shellcontract.check(v, f2)
    # Every face with an open edge: the removed face's three neighbours (sharing two vertices
    # with it), as indices into f2; the message names the first.
    gone = set(int(x) for x in f[removed])
    expected = [i for i, face in enumerate(f2) if len(set(int(x) for x in face) & gone) == 2]
    assert len(expected) == 3
    assert list(e.value.faces) == expected
    assert "of face {} has no neighbouring face".format(expected[0]) in str(e.value)
    assert "(3 faces in all have such edges)" in str(e.value)


def test_non_manifold_vertex_lists_the_faces_around_it():
    """Two tetrahedra that share vertex 0 only: the vertex is refused with its six faces (it was
    a plain ValueError), so that the Blender add-on names the faces of the pinch."""
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, 0, 0], [0, -1, 0], [0, 0, -1]], dtype=float)
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3], [0, 4, 5], [0, 6, 4], [0, 5, 6], [4, 6, 5]])
    with pytest.raises(shellcontract.MeshError) as e:
        shellcontract.check(v, f)
    assert str(e.value) == ("input arrays: non-manifold vertex: vertex 0: its 6 faces form several fans "
                            "(the fan through its first face has 3); the surface pinches there")
    assert e.value.faces == [0, 1, 2, 4, 5, 6]


def test_an_isolated_vertex_stays_a_plain_value_error(ico2):
    """No face touches an isolated vertex: there is no face to name, so no MeshError."""
    v, f = ico2
    v = np.vstack([v, [[5.0, 5.0, 5.0]]])
    with pytest.raises(ValueError, match="isolated vertex: vertex {} is not used by any face".format(len(v) - 1)) as e:
        shellcontract.check(v, f)
    assert not isinstance(e.value, shellcontract.MeshError)


def test_a_problem_without_faces_stays_a_plain_value_error(ico2):
    v, f = ico2
    v = v.copy()
    v[3, 1] = np.nan
    with pytest.raises(ValueError, match="non-finite coordinate") as e:
        shellcontract.contract(v, f, frames=1)
    assert not isinstance(e.value, shellcontract.MeshError)


def test_mesh_error_pickles_with_its_faces(ico2):
    """A sweep's worker hands errors back pickled: the class is found as shellcontract.MeshError
    and `faces` comes along."""
    import pickle
    v, f = ico2
    f = f.copy()
    f[3, 1] = f[3, 0]
    with pytest.raises(shellcontract.MeshError) as e:
        shellcontract.check(v, f)
    back = pickle.loads(pickle.dumps(e.value))
    assert type(back) is shellcontract.MeshError and back.faces == [3] and str(back) == str(e.value)
