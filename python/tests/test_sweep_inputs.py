"""The files a sweep's jobs read besides their meshes (a regions face list, region weights):
usable in a sweep file, relative to it, and part of each job's id by their bytes, so that an
edited file reruns its jobs (from scratch, not from a checkpoint of the old file). Each mesh is
checked before the sweep as `run` checks its input."""
import base64
import json
import os
import struct
import subprocess

import pytest

import shellcontract
from shellcontract import sweep, sweep_file
from test_sweep import results, run_sweep, write_sweep

pytest.importorskip("distributed")

ICO2_VERTICES = 162


def version(cli):
    return subprocess.run([cli, "--version"], capture_output=True, text=True).stdout.strip()


def jobs_of(cli, path):
    return sweep_file.expand(str(path), sweep_file.load(str(path)), version(cli))


def test_region_weights_in_a_sweep_file_relative_to_it(cli, mesh_dir, tmp_path):
    (tmp_path / "w.txt").write_text("".join("{}\n".format(i % 2) for i in range(ICO2_VERTICES)))
    spec = {"meshes": ["meshes/ico2.off"],
            "options": {"frames": 4, "pressure": 0, "region_weights": "w.txt"}}
    path = write_sweep(tmp_path, mesh_dir, "w.json", spec, meshes=("ico2.off",))
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    # Run from another folder: the weights file is found next to the sweep file.
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--dry-run"], cwd=str(elsewhere))
    assert r.returncode == 0, r.stderr
    assert "--region-weights " + str(tmp_path / "w.txt") in r.stdout, r.stdout
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--shard", "0/1"],
                  cwd=str(elsewhere))
    assert r.returncode == 0, r.stderr
    assert [row["status"] for row in results(tmp_path / "out")] == ["ok"]
    # A weights file that is not there is refused like a missing regions file.
    spec["options"]["region_weights"] = "missing.txt"
    path.write_text(json.dumps(spec))
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out2"), "--dry-run"])
    assert r.returncode == 1, r.stderr
    assert "region_weights file {} is not readable".format(tmp_path / "missing.txt") in r.stderr


@pytest.mark.parametrize("name,first,second", [
    ("regions", "0 1 2 3 4 5\n", "100 101 102 103 104 105\n"),
    ("region_weights", "1\n" * ICO2_VERTICES, "0.5\n" * ICO2_VERTICES),
], ids=["regions", "region_weights"])
def test_the_job_id_covers_the_bytes_of_every_input_file(cli, mesh_dir, tmp_path, name, first,
                                                         second):
    data = tmp_path / "input.txt"
    data.write_text(first)
    spec = {"meshes": ["meshes/ico2.off"], "options": {"frames": 4, name: "input.txt"}}
    path = write_sweep(tmp_path, mesh_dir, "s.json", spec, meshes=("ico2.off",))
    before = jobs_of(cli, path)[0].id
    data.write_text(second)
    assert jobs_of(cli, path)[0].id != before
    # The same bytes under another name (a moved file) are the same job.
    data.write_text(first)
    os.rename(data, tmp_path / "moved.txt")
    spec["options"][name] = "moved.txt"
    path.write_text(json.dumps(spec))
    assert jobs_of(cli, path)[0].id == before


def write_gltf_with_buffer(folder, vertices, faces):
    """ball.gltf whose positions and indices are in the external buffer ball.bin."""
    import numpy as np
    pos = np.asarray(vertices, dtype="<f4").tobytes()
    idx = np.asarray(faces, dtype="<u4").tobytes()
    (folder / "ball.bin").write_bytes(pos + idx)
    lo, hi = np.asarray(vertices).min(axis=0).tolist(), np.asarray(vertices).max(axis=0).tolist()
    document = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"uri": "ball.bin", "byteLength": len(pos) + len(idx)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
                        {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(vertices),
                       "type": "VEC3", "min": lo, "max": hi},
                      {"bufferView": 1, "componentType": 5125, "count": 3 * len(faces),
                       "type": "SCALAR"}]}
    (folder / "ball.gltf").write_text(json.dumps(document))


def test_the_job_id_covers_a_gltfs_external_buffer(cli, mesh_dir, tmp_path):
    # Before: only the .gltf's bytes were hashed, so a sweep skipped the job of a mesh whose
    # geometry (in ball.bin) was edited and kept the old result (review determinism F1).
    from shellcontract import read_mesh
    vertices, faces = read_mesh(mesh_dir / "ico2.off")
    folder = tmp_path / "assets"
    folder.mkdir()
    write_gltf_with_buffer(folder, vertices, faces)
    path = tmp_path / "s.json"
    path.write_text(json.dumps({"meshes": ["assets/ball.gltf"], "options": {"frames": 4}}))
    before = jobs_of(cli, path)[0].id
    gltf_bytes = (folder / "ball.gltf").read_bytes()
    # Vertices off the bounding box moved inward: the accessor's min and max, hence the .gltf's
    # bytes, stay; only ball.bin changes.
    inner = ((vertices > vertices.min(axis=0)) & (vertices < vertices.max(axis=0))).all(axis=1)
    assert inner.sum() > 100
    moved = vertices.copy()
    moved[inner] *= 0.95
    write_gltf_with_buffer(folder, moved, faces)
    assert (folder / "ball.gltf").read_bytes() == gltf_bytes
    edited = jobs_of(cli, path)[0].id
    assert edited != before
    # The folder moved with both files: the same job.
    os.rename(folder, tmp_path / "moved")
    path.write_text(json.dumps({"meshes": ["moved/ball.gltf"], "options": {"frames": 4}}))
    assert jobs_of(cli, path)[0].id == edited


def test_a_file_the_mesh_names_that_this_user_cannot_read_is_no_byte_of_the_job(cli, mesh_dir,
                                                                               tmp_path):
    # Before: hashing the files a mesh needs raised PermissionError out of the expansion for an
    # OBJ's unreadable material library (a traceback, exit 1), where `run` of the mesh warns and
    # runs (review diffreview6). As a user, for whom the file's mode applies.
    import shutil
    from shellcontract import read_mesh, write_mesh
    from test_file_errors import as_a_user, folder_a_user_reaches
    folder = folder_a_user_reaches(tmp_path)
    try:
        write_mesh(folder / "m.obj", *read_mesh(mesh_dir / "ico2.off"))
        (folder / "m.obj").write_text("mtllib m.mtl\n" + (folder / "m.obj").read_text())
        (folder / "m.mtl").write_text("newmtl a\nKd 1 0 0\n")
        (folder / "m.mtl").chmod(0)
        path = folder / "s.json"
        path.write_text(json.dumps({"meshes": ["m.obj"], "options": {"frames": 4}}))
        tool = version(cli)

        def check():
            jobs = sweep_file.expand(str(path), sweep_file.load(str(path)), tool)
            assert len(jobs) == 1

        as_a_user(check)
    finally:
        shutil.rmtree(folder)


def test_an_edited_regions_file_reruns_its_job_and_not_from_the_old_checkpoint(cli, mesh_dir,
                                                                                tmp_path):
    regions = tmp_path / "regions.txt"
    regions.write_text("0 1 2 3 4 5\n")
    spec = {"meshes": ["meshes/ico2.off"], "options": {"regions": "regions.txt"},
            "runs": [{"frames": 4}, {"frames": 1000000, "threads": 1}]}
    path = write_sweep(tmp_path, mesh_dir, "s.json", spec, meshes=("ico2.off",))
    out = tmp_path / "out"
    # The long job times out, leaving its checkpoint for a later sweep to resume.
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1", "--job-timeout", "2"])
    assert r.returncode == 3, r.stderr
    first = results(out)
    assert [row["status"] for row in first] == ["ok", "timeout"]
    assert (out / ".work" / "checkpoints" / (first[1]["job"] + ".ckpt")).is_file()
    regions.write_text("100 101 102 103 104 105\n")
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1", "--job-timeout", "2"])
    assert r.returncode == 3, r.stderr
    assert "2 in this run, 0 done already" in r.stderr, r.stderr
    second = results(out)
    assert [row["status"] for row in second] == ["ok", "timeout"]
    assert {row["job"] for row in second}.isdisjoint(row["job"] for row in first)
    # The long job started over with the new regions: the old file's checkpoint is not its.
    record = json.loads((out / "jobs" / second[1]["job"] / "job.json").read_text())
    assert record["resumed"] is False


def test_a_second_sweep_in_one_process_reads_a_changed_mesh_again(cli, mesh_dir, tmp_path,
                                                                  monkeypatch, capsys):
    spec = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4}}
    path = write_sweep(tmp_path, mesh_dir, "s.json", spec, meshes=("ico1.off",))
    out = tmp_path / "out"
    monkeypatch.setenv("SHELLCONTRACT_CLI", cli)
    assert sweep.main([str(path), "-o", str(out), "--shard", "0/1"]) == 0
    assert "1 in this run, 0 done already" in capsys.readouterr().err
    # Another mesh's bytes under the same name: another job, which runs.
    (tmp_path / "meshes" / "ico1.off").write_bytes((mesh_dir / "ico2.off").read_bytes())
    assert sweep.main([str(path), "-o", str(out), "--shard", "0/1"]) == 0
    assert "1 in this run, 0 done already" in capsys.readouterr().err
    assert len(list((out / "jobs").iterdir())) == 2


def test_region_weights_as_a_list_is_refused(cli, mesh_dir, tmp_path):
    # Before: both lists of a grid became one job (the same id), run with the weights as its file
    # name ("--region-weights 0.5,0.5,...": "the file name is too long").
    spec = {"meshes": ["meshes/ico2.off"],
            "grid": {"region_weights": [[0.5] * ICO2_VERTICES, [1.0] * ICO2_VERTICES]}}
    path = write_sweep(tmp_path, mesh_dir, "l.json", spec, meshes=("ico2.off",))
    with pytest.raises(sweep_file.SweepError, match="in a sweep it is a file name"):
        jobs_of(cli, path)


def octahedron_gltf_with_a_nan_uv(path):
    """A .gltf of the closed octahedron whose TEXCOORD_0 has one u that is NaN: read_mesh reads
    it, but its result (a glTF, the input with new positions) cannot hold that value."""
    positions = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    indices = [0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5]
    uv = [(float("nan") if i == 0 else 0.5, 0.5) for i in range(6)]
    data = (b"".join(struct.pack("<3f", *p) for p in positions) + struct.pack("<24I", *indices)
            + b"".join(struct.pack("<2f", *t) for t in uv))
    doc = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 2},
                                    "indices": 1}]}],
        "buffers": [{"uri": "data:application/octet-stream;base64,"
                            + base64.b64encode(data).decode(), "byteLength": len(data)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 72},
                        {"buffer": 0, "byteOffset": 72, "byteLength": 96},
                        {"buffer": 0, "byteOffset": 168, "byteLength": 48}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3",
                       "min": [-1, -1, -1], "max": [1, 1, 1]},
                      {"bufferView": 1, "componentType": 5125, "count": 24, "type": "SCALAR"},
                      {"bufferView": 2, "componentType": 5126, "count": 6, "type": "VEC2"}]}
    path.write_text(json.dumps(doc))
    return path


def test_a_mesh_run_refuses_before_its_run_is_refused_before_the_sweep(cli, tmp_path):
    """The sweep checks each mesh as `run` checks its input before the run (the library's
    check_run_input), not with the reader alone: a .gltf whose result cannot be written (a NaN
    texture coordinate) is refused by --dry-run naming the mesh and the reason, exit 1, instead
    of every job of it ending `bad input` after the sweep started."""
    mesh = octahedron_gltf_with_a_nan_uv(tmp_path / "nan_uv.gltf")
    reason = ("not writable as a glTF: mesh 0 primitive 0 vertex 0: texture coordinate u nan is "
              "not a finite number")
    shellcontract.read_mesh(str(mesh))  # the reader alone accepts it
    r = subprocess.run([cli, "run", str(mesh), "-o", str(tmp_path / "r.gltf"), "-n", "1"],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "{}: {}".format(mesh, reason) in r.stderr, r.stderr
    spec = {"meshes": ["nan_uv.gltf"], "options": {"frames": 1}}
    path = tmp_path / "s.json"
    path.write_text(json.dumps(spec))
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--dry-run"])
    assert r.returncode == 1, r.stdout + r.stderr
    assert "{}: {}".format(mesh, reason) in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()
