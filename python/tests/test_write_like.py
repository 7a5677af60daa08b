"""write_mesh(..., like=INPUT) keeps a textured OBJ whole: every line but v and vn
as read, the given positions bitwise. (One `vn` per vertex: a line shared by several vertices is
split when they no longer share a normal, docs/design/attributes.md, "Normals".)"""
import numpy as np
import pytest

import shellcontract

OBJ = ("# a tetrahedron with texture coordinates and a material\nmtllib t.mtl\no tet\n"
       "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\n"
       "vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nusemtl red\ns 1\n"
       "f 1/1/1 3/3/3 2/2/2\nf 1/1/1 2/2/2 4/3/4\nf 1/1/1 4/3/4 3/2/3\nf 2/2/2 3/3/3 4/1/4\n")


def test_write_like_keeps_everything_but_positions(tmp_path):
    src = tmp_path / "tet.obj"
    src.write_text(OBJ)
    v, f = shellcontract.read_mesh(src)
    moved = v * 0.5 + np.array([0.125, -0.25, 1.0 / 3.0])
    out = tmp_path / "out.obj"
    shellcontract.write_mesh(out, moved, f, like=src)
    a, b = OBJ.splitlines(), out.read_text().splitlines()
    assert len(a) == len(b)
    rows = [line for line in b if line.startswith("v ")]
    assert np.array_equal(np.array([[float(t) for t in r.split()[1:4]] for r in rows]), moved)
    for x, y in zip(a, b):
        if not x.startswith(("v ", "vn ")):
            assert x == y


def test_write_like_refuses_other_faces(tmp_path):
    src = tmp_path / "tet.obj"
    src.write_text(OBJ)
    v, f = shellcontract.read_mesh(src)
    with pytest.raises(ValueError, match="not those read_mesh gives"):
        shellcontract.write_mesh(tmp_path / "out.obj", v, f[:, [0, 2, 1]], like=src)
    with pytest.raises(ValueError, match="written to a file of its format \\(.obj\\), not "):
        shellcontract.write_mesh(tmp_path / "out.off", v, f, like=src)


@pytest.mark.parametrize("name", ["ico1.off", "ico1.stl"])
def test_write_like_of_a_format_without_a_document_names_the_formats_that_have_one(tmp_path, mesh_dir, name):
    """Before: "only an OBJ or PLY file", where a .glb or .gltf like is written too."""
    like = tmp_path / name
    shellcontract.write_mesh(like, *shellcontract.read_mesh(mesh_dir / "ico1.off"))
    v, f = shellcontract.read_mesh(like)
    with pytest.raises(ValueError, match="only an OBJ, PLY, .glb or .gltf file") as e:
        shellcontract.write_mesh(tmp_path / ("out" + like.suffix), v, f, like=like)
    assert "OBJ or PLY file" not in str(e.value)
    assert not (tmp_path / ("out" + like.suffix)).exists()


def test_the_docstring_names_the_formats_like_takes():
    doc = shellcontract.write_mesh.__doc__
    assert "like: the OBJ, PLY, .glb or .gltf file" in " ".join(doc.split())


PLY_HEAD = "ply\nformat ascii 1.0\nelement vertex 4\n"
PLY_BODY = ("element face 4\nproperty list uchar int vertex_indices\nend_header\n"
            "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")


def test_a_bad_like_file_gets_the_readers_message(tmp_path):
    # The file is read and checked before it is kept as a document, so a malformed one is
    # refused as read_mesh refuses it, by the PLY reader: here a body shorter than the header
    # declares, which the document alone would call "the body ends early".
    good = tmp_path / "tet.ply"
    good.write_text(PLY_HEAD + "property float x\nproperty float y\nproperty float z\n" + PLY_BODY)
    v, f = shellcontract.read_mesh(good)
    bad = tmp_path / "bad.ply"
    bad.write_text(PLY_HEAD + "property float x\nproperty float y\nproperty float z\n" + PLY_BODY.split("0 0 1")[0])
    with pytest.raises(ValueError) as read_error:
        shellcontract.read_mesh(bad)
    with pytest.raises(ValueError) as write_error:
        shellcontract.write_mesh(tmp_path / "out.ply", v, f, like=bad)
    assert "truncated file" in str(read_error.value)
    assert str(write_error.value) == str(read_error.value)
    assert not (tmp_path / "out.ply").exists()


def test_write_like_elsewhere_names_the_same_material_library(tmp_path):
    (tmp_path / "in").mkdir()
    (tmp_path / "out").mkdir()
    src = tmp_path / "in" / "tet.obj"
    src.write_text(OBJ)
    (tmp_path / "in" / "t.mtl").write_text("newmtl red\nKd 1 0 0\n")
    v, f = shellcontract.read_mesh(src)
    out = tmp_path / "out" / "r.obj"
    shellcontract.write_mesh(out, v, f, like=src)
    name = next(l for l in out.read_text().splitlines() if l.startswith("mtllib ")).split(" ", 1)[1]
    assert (out.parent / name).samefile(tmp_path / "in" / "t.mtl")
    (tmp_path / "in" / "t.mtl").unlink()
    with pytest.warns(UserWarning, match=r"line 2: material library 't.mtl' not found"):
        shellcontract.write_mesh(out, v, f, like=src)
    assert "mtllib t.mtl" in out.read_text().splitlines()


def test_write_like_a_glb_writes_its_positions(cli, mesh_dir, tmp_path):
    """A .glb input (here the CLI's --gltf of a run) is written back through its glTF document:
    the positions read back are the given ones to float32 rounding (glTF stores floats), and the
    faces are read_mesh's. Before glTF inputs, read_mesh refused the file (unknown extension)."""
    import subprocess
    glb = tmp_path / "run.glb"
    subprocess.run([cli, "run", str(mesh_dir / "ico2.off"), "-o", str(tmp_path / "run.off"),
                    "--gltf", str(glb), "-n", "3", "-q"], check=True)
    v, f = shellcontract.read_mesh(glb)
    moved = v * 0.75 + np.array([0.5, -0.25, 0.125])
    out = tmp_path / "out.glb"
    shellcontract.write_mesh(out, moved, f, like=glb)
    back, faces = shellcontract.read_mesh(out)
    assert np.array_equal(faces, f)
    assert np.abs(back - moved).max() <= 2.0 ** -23 * np.abs(moved).max()


def _glb_json(path):
    import json
    import struct
    b = path.read_bytes()
    (n,) = struct.unpack("<I", b[12:16])
    return json.loads(b[20:20 + n]), b[20 + n:]


def test_write_like_a_glb_keeps_its_json(cli, mesh_dir, tmp_path):
    """The glTF document's JSON is the input's but for what new positions change (buffers,
    POSITION's min and max): an empty scene, an empty node and an infinite camera stay as they
    were. Before: tinygltf's writer made the empty objects null, which read_mesh then refused
    ("`scenes' does not contain an JSON object"), and gave the camera "zfar": 0."""
    import json
    import struct
    import subprocess
    run = tmp_path / "run.glb"
    subprocess.run([cli, "run", str(mesh_dir / "ico2.off"), "-o", str(tmp_path / "run.off"),
                    "--gltf", str(run), "-n", "3", "-q"], check=True)
    doc, rest = _glb_json(run)
    doc["scenes"] = [{}, {"nodes": [0, 2]}]
    doc["scene"] = 1
    doc["nodes"] += [{}, {"camera": 0}]
    doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 1, "znear": 0.1}}]
    doc["extras"] = {"empty": {}}
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    glb = tmp_path / "doc.glb"
    glb.write_bytes(b"glTF" + struct.pack("<IIII", 2, 20 + len(text) + len(rest), len(text),
                                          0x4E4F534A) + text + rest)
    v, f = shellcontract.read_mesh(glb)
    out = tmp_path / "out.glb"
    shellcontract.write_mesh(out, v * 0.5, f, like=glb)
    written, _ = _glb_json(out)
    for key in doc:
        if key not in ("buffers", "accessors"):
            assert written[key] == doc[key], key
    assert written["scenes"][0] == {} and written["nodes"][1] == {}
    assert "zfar" not in written["cameras"][0]["perspective"]
    back, faces = shellcontract.read_mesh(out)
    assert np.array_equal(faces, f)
    assert np.abs(back - v * 0.5).max() <= 2.0 ** -23 * np.abs(v).max()


@pytest.mark.parametrize("binary", [False, True])
def test_write_like_refuses_positions_its_floats_cannot_hold(tmp_path, binary):
    # A PLY that stores x, y, z as float32 cannot hold 1e300 (written as inf: a file no reader
    # takes) nor a mesh of extent 1e-300 (every coordinate zero: one point). Before, both were
    # written without a word.
    src = tmp_path / "tet.ply"
    head = PLY_HEAD + "property float x\nproperty float y\nproperty float z\n"
    if binary:
        import struct
        body = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1)
        for tri in ((0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)):
            body += struct.pack("<B3i", 3, *tri)
        src.write_bytes((head.replace("ascii", "binary_little_endian") + PLY_BODY.split("0 0 0")[0]).encode() + body)
    else:
        src.write_text(head + PLY_BODY)
    v, f = shellcontract.read_mesh(src)
    out = tmp_path / "out.ply"
    with pytest.raises(ValueError, match=r"vertex 1's x is 1e\+300, beyond the largest 32-bit float"):
        shellcontract.write_mesh(out, v * 1e300, f, like=src)
    with pytest.raises(ValueError, match=r"below the smallest normal 32-bit float"):
        shellcontract.write_mesh(out, v * 1e-300, f, like=src)
    assert not out.exists()
    # What floats hold is written: a large mesh, a small one, and a tiny coordinate beside them.
    for scale in (1e38, 1e-37):
        shellcontract.write_mesh(out, v * scale, f, like=src)
        back, _ = shellcontract.read_mesh(out)
        assert np.allclose(back, v * scale, rtol=1e-6, atol=0)
    w = v.copy()
    w[1, 1] = 1e-300
    shellcontract.write_mesh(out, w, f, like=src)


TOUCHING = ("OFF\n8 8 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 0 0\n-1 0 0\n0 -1 0\n0 0 -1\n"
            "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 4 5 6\n3 4 7 5\n3 4 6 7\n3 5 7 6\n")


def test_write_mesh_refuses_an_stl_that_reads_back_as_another_mesh(tmp_path):
    # Two closed tetrahedra touching at the origin through two vertices: an STL keeps no vertex
    # identity, so read back the two would be one, a non-manifold vertex (read_mesh refuses it).
    # Before, the STL was written against the promise that what is written can be read back.
    src = tmp_path / "touch.off"
    src.write_text(TOUCHING)
    v, f = shellcontract.read_mesh(src)
    with pytest.raises(ValueError, match=r"an STL keeps no vertex identity, and vertices 0 and 4 would both be "
                                         r"stored at \(0, 0, 0\)"):
        shellcontract.write_mesh(tmp_path / "t.stl", v, f)
    assert not (tmp_path / "t.stl").exists()
    shellcontract.write_mesh(tmp_path / "t.off", v, f)
    back, _ = shellcontract.read_mesh(tmp_path / "t.off")
    assert np.array_equal(back, v)


def test_write_like_writes_integer_coordinates_as_double(tmp_path):
    # A PLY with int16 coordinates (legal, rare): positions are not integers, so x, y, z become
    # double in the written file. Before, they were rounded to the nearest integer (a unit-size
    # mesh flattened), and one beyond the type refused.
    src = tmp_path / "tet.ply"
    src.write_text(PLY_HEAD + "property short x\nproperty short y\nproperty short z\n" + PLY_BODY)
    v, f = shellcontract.read_mesh(src)
    for w in (v * 0.3 + 0.01, v * 40000):
        shellcontract.write_mesh(tmp_path / "out.ply", w, f, like=src)
        assert "property double x\nproperty double y\nproperty double z\n" in (tmp_path / "out.ply").read_text()
        back, _ = shellcontract.read_mesh(tmp_path / "out.ply")
        assert np.array_equal(back, w)
