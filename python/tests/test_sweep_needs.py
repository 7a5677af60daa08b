"""A file that a sweep's mesh needs (an OBJ's material library, its images, a PLY's texture, a
glTF's buffer) is never one of the sweep's outputs, as for every command's outputs
(docs/design/output-safety.md, "Files the input needs"): a results table named like the mesh's
.mtl is refused before any job runs, whether the library exists (it would be destroyed) or not
(the table would give the mesh a library it did not have), and so is such a file in a folder the
sweep removes. Before, the sweep checked only the mesh file itself."""
import json
import os
import struct

import pytest

import shellcontract
from shellcontract import sweep_needs

from test_sweep import results, run_sweep
from test_sweep_output import refused

pytest.importorskip("distributed")


def obj_mesh(mesh_dir, path, head):
    """ico1 as an OBJ file whose first lines are `head`."""
    v, f = shellcontract.read_mesh(mesh_dir / "ico1.off")
    plain = path.with_name("plain-" + path.name)
    shellcontract.write_mesh(plain, v, f)
    path.write_text(head + plain.read_text())
    plain.unlink()
    return path


def sweep_of(tmp_path, mesh):
    path = tmp_path / "s.json"
    path.write_text(json.dumps({"meshes": [str(mesh)], "options": {"frames": 2}}))
    return path


def assert_refused(cli, path, out, *texts):
    for dry_run in ([], ["--dry-run"]):
        r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"] + dry_run)
        refused(r, "refused, nothing run", *texts)


@pytest.mark.parametrize("table", ["results.csv", "results.json"])
def test_a_table_that_an_objs_missing_library_names_is_refused_in_a_new_folder(
        cli, mesh_dir, tmp_path, table):
    mesh = obj_mesh(mesh_dir, tmp_path / "m.obj", "mtllib out/{}\n".format(table))
    out = tmp_path / "out"
    assert_refused(cli, sweep_of(tmp_path, mesh), out, "{}: is the material library that '{}' "
                   "reads (mtllib, line 1); the mesh needs this file".format(out / table, mesh))
    assert not out.exists()


def test_an_objs_library_in_the_place_of_a_table_is_kept(cli, mesh_dir, tmp_path):
    mesh = obj_mesh(mesh_dir, tmp_path / "m.obj", "")
    path, out = sweep_of(tmp_path, mesh), tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    job = results(out)[0]["job"]
    # The user's materials kept in the results folder, also under a table's name, and the mesh
    # (a new job: other bytes) reading them from there, by a name with a space on a continued
    # line.
    mats, table = out / "my mats", out / "results.json"
    mats.write_text("newmtl m\nKd 1 0 0\n")
    table.unlink()
    os.link(mats, table)  # another name of the library: a hard link
    obj_mesh(mesh_dir, mesh, "# materials\nmtllib \\\n  out/my mats\n")
    assert_refused(cli, path, out, "{}: is the material library that '{}' reads (mtllib, line 2)"
                   .format(table, mesh))
    assert mats.read_text() == "newmtl m\nKd 1 0 0\n" and os.path.samefile(table, mats)
    assert [j.name for j in (out / "jobs").iterdir()] == [job]


def test_a_file_a_mesh_needs_in_a_folder_the_sweep_removes_is_refused(cli, mesh_dir, tmp_path):
    mesh = obj_mesh(mesh_dir, tmp_path / "m.obj", "")
    path, out = sweep_of(tmp_path, mesh), tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    library = out / ".work" / "m.mtl"
    library.write_text("newmtl m\nmap_Kd -s 1 1 1 -bm 0.5 tex ture.png\n")
    obj_mesh(mesh_dir, mesh, "mtllib out/.work/m.mtl\n")
    assert_refused(cli, path, out, "{} (the material library that '{}' reads (mtllib, line 1)), is "
                   "in {}, which the sweep replaces or removes".format(library, mesh,
                                                                      out / ".work"))
    assert library.read_text() == "newmtl m\nmap_Kd -s 1 1 1 -bm 0.5 tex ture.png\n"


def test_the_files_listed_are_the_librarys(tmp_path):
    """The same readings as src/mesh/input_dependencies.cpp's (its tests: tests/mesh)."""
    (tmp_path / "a b.mtl").write_text("newmtl m\nmap_Kd -o 0 0 -clamp on t one.png # c\n"
                                      "map_aat on\nbump b.png\nKd 1 1 1\n")
    obj = tmp_path / "m.obj"
    obj.write_bytes(b"\xef\xbb\xbfmtllib a b.mtl missing.mtl # comment\nv 0 0 0\n"
                    b"  mtllib \\\r\nsecond.mtl\r\nmtllib a b.mtl\n")
    got = sweep_needs.needed_files(str(obj))
    assert [(os.path.relpath(p, tmp_path), what.split(" (")[-1]) for p, what in got] == [
        ("a b.mtl", "mtllib, line 1)"), ("t one.png", "map_Kd, line 2)"),
        ("b.png", "bump, line 4)"), ("missing.mtl", "mtllib, line 1)"),
        ("second.mtl", "mtllib, line 3)")]
    ply = tmp_path / "p.ply"
    ply.write_bytes(b"ply\nformat ascii 1.0\ncomment TextureFile tex/a.png\ncomment TextureFiles x"
                    b"\nelement vertex 0\nend_header\ncomment TextureFile no.png\n")
    assert [p for p, _ in sweep_needs.needed_files(str(ply))] == [str(tmp_path / "tex/a.png")]
    # A glTF the reader loads (the library lists a refused one's images only as far as it read:
    # the run refuses the file before writing anything): a tetrahedron in an external buffer.
    (tmp_path / "g b.bin").write_bytes(
        struct.pack("<12f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1)
        + struct.pack("<12H", 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3))
    gltf = tmp_path / "g.gltf"
    gltf.write_text(json.dumps({
        "asset": {"version": "2.0"},
        "buffers": [{"uri": "g%20b.bin", "byteLength": 72}],
        "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48,
                                                           "byteLength": 24}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 1]},
                      {"bufferView": 1, "componentType": 5123, "count": 12, "type": "SCALAR"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}],
        "images": [{"uri": "t.png?v=1"}, {"uri": "data:image/png;base64,AA=="}]}))
    assert [p for p, _ in sweep_needs.needed_files(str(gltf))] == [
        str(tmp_path / "g b.bin"), str(tmp_path / "t.png?v=1"), str(tmp_path / "t.png")]
    off = tmp_path / "m.off"
    off.write_text("OFF\n# mtllib x.mtl\n0 0 0\n")
    assert sweep_needs.needed_files(str(off)) == []
    assert sweep_needs.needed_files(str(tmp_path / "none.obj")) == []
