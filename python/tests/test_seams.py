"""A mesh split along a UV seam (what Blender's glTF importer hands the add-on: one vertex per
texture coordinate, copies at the same position) runs welded: contract() returns the given
vertices, each copy at its welded vertex's position, and the run is the one of the mesh without
the copies, bit for bit."""
import numpy as np
import pytest

import shellcontract


def seam_split(v, f):
    """v, f with a seam around the middle: the upper faces use copies (appended after the
    vertices) of the vertices they share with the lower faces."""
    upper = v[f].mean(axis=1)[:, 2] > 0
    shared = np.intersect1d(np.unique(f[upper]), np.unique(f[~upper]))
    copy = {int(i): len(v) + k for k, i in enumerate(shared)}
    split = f.copy()
    for row in np.nonzero(upper)[0]:
        split[row] = [copy.get(int(i), int(i)) for i in f[row]]
    return np.vstack([v, v[shared]]), split, shared


def test_a_seam_split_mesh_runs_as_the_mesh_without_its_copies(ico2):
    v, f = ico2
    sv, sf, shared = seam_split(v, f)
    assert len(shared) > 0
    frames = []
    split = shellcontract.contract(sv, sf, frames=6, target_volume=0.8,
                                   callback=lambda frame, x, m: frames.append(x.shape))
    whole = shellcontract.contract(v, f, frames=6, target_volume=0.8)
    assert split.vertices.shape == sv.shape
    assert frames == [sv.shape] * 6
    assert np.array_equal(split.faces, sf)
    # The welded mesh is ico2 itself (its vertices come first): the same run, to the bit.
    assert np.array_equal(split.vertices[:len(v)], whole.vertices)
    assert np.array_equal(split.vertices[len(v):], whole.vertices[shared])
    assert split.summary["welded_vertices"] == len(shared)
    assert whole.summary["welded_vertices"] == 0
    assert shellcontract.check(sv, sf)["welded_vertices"] == len(shared)


def test_region_weights_are_one_per_given_vertex(ico2):
    v, f = ico2
    sv, sf, shared = seam_split(v, f)
    w = np.clip(v[:, 0] * 2.0, 0.0, 1.0)  # a region on one side, across the seam
    split = shellcontract.contract(sv, sf, frames=4, region_weights=np.concatenate([w, w[shared]]))
    whole = shellcontract.contract(v, f, frames=4, region_weights=w)
    assert split.summary["regions"] == whole.summary["regions"] > 0
    assert np.array_equal(split.vertices[:len(v)], whole.vertices)
    with pytest.raises(ValueError, match="{} weights for {} vertices".format(len(v), len(sv))):
        shellcontract.contract(sv, sf, frames=1, region_weights=w)


def test_read_and_write_keep_a_split_files_vertices(ico2, tmp_path):
    v, f = ico2
    sv, sf, _ = seam_split(v, f)
    rows = "".join("{!r} {!r} {!r} {}\n".format(*p, i % 7) for i, p in enumerate(sv.tolist()))
    ply = ("ply\nformat ascii 1.0\nelement vertex {}\nproperty double x\nproperty double y\n"
           "property double z\nproperty int tag\nelement face {}\nproperty list uchar int vertex_indices\n"
           "end_header\n{}{}").format(len(sv), len(sf), rows, "".join("3 {} {} {}\n".format(*t) for t in sf))
    src = tmp_path / "split.ply"
    src.write_text(ply)
    rv, rf = shellcontract.read_mesh(src)
    assert np.array_equal(rv, sv) and np.array_equal(rf, sf)
    r = shellcontract.contract(rv, rf, frames=3)
    out = tmp_path / "out.ply"
    shellcontract.write_mesh(out, r.vertices, r.faces, like=src)
    back, _ = shellcontract.read_mesh(out)
    assert np.array_equal(back, r.vertices)
    assert out.read_text().split("end_header\n")[0] == ply.split("end_header\n")[0]


def test_a_split_mesh_that_welding_does_not_close_is_refused_with_a_hint(ico2):
    v, f = ico2
    sv, sf, _ = seam_split(v, f)
    with pytest.raises(ValueError, match="open boundary.*after welding, open boundary"):
        shellcontract.contract(sv, sf[1:], frames=1)


def test_a_hole_left_after_welding_is_named_by_the_faces_around_it(ico2):
    # The seam-split mesh with one face away from the seam removed: as given it is open along
    # the seam and at the hole, welded at the hole only. MeshError.faces (what the Blender
    # add-on names) are the hole's neighbours, found here on ico2 itself, not the seam's faces.
    v, f = ico2
    sv, sf, shared = seam_split(v, f)
    hole = next(i for i, t in enumerate(f) if not np.isin(t, shared).any())
    edges = {frozenset(e) for e in ((f[hole][0], f[hole][1]), (f[hole][1], f[hole][2]),
                                     (f[hole][2], f[hole][0]))}
    rest = np.delete(np.arange(len(f)), hole)
    around = [k for k, i in enumerate(rest)
              if any(frozenset((f[i][j], f[i][(j + 1) % 3])) in edges for j in range(3))]
    assert len(around) == 3
    with pytest.raises(shellcontract.MeshError, match="after welding, open boundary: ") as e:
        shellcontract.contract(sv, np.delete(sf, hole, axis=0), frames=1)
    assert e.value.faces == around
