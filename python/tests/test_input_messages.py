"""What the CLI says about inputs that are nearly right (review14 D5-D8, review13 L4 and L6): a stray
vertex that makes a shape "flat", near-duplicate vertices that open a crack, an inside-out input's
winding per output format, a shell whose every vertex is held at rest, an input that cannot be
opened for want of file descriptors, and a frame count that is not an integer."""
import json
import resource
import subprocess

import numpy as np
import pytest


def read_off(path):
    lines = [l.split("#")[0].split() for l in open(path)]
    lines = [l for l in lines if l]
    nv, nf = int(lines[1][0]), int(lines[1][1])
    v = np.array([[float(x) for x in l[:3]] for l in lines[2:2 + nv]])
    f = np.array([[int(x) for x in l[1:4]] for l in lines[2 + nv:2 + nv + nf]])
    return v, f


def write_off(path, v, f):
    with open(path, "w") as out:
        out.write("OFF\n%d %d 0\n" % (len(v), len(f)))
        for p in v:
            out.write("%r %r %r\n" % tuple(float(x) for x in p))
        for t in f:
            out.write("3 %d %d %d\n" % tuple(t))


def write_obj(path, v, f):
    with open(path, "w") as out:
        for p in v:
            out.write("v %r %r %r\n" % tuple(float(x) for x in p))
        for t in f:
            out.write("f %d %d %d\n" % tuple(t + 1))


def write_ply(path, v, f):
    with open(path, "w") as out:
        out.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty double x\nproperty double y\n"
                  "property double z\nelement face %d\nproperty list uchar int vertex_indices\n"
                  "end_header\n" % (len(v), len(f)))
        for p in v:
            out.write("%r %r %r\n" % tuple(float(x) for x in p))
        for t in f:
            out.write("3 %d %d %d\n" % tuple(t))


def sc(cli, *args, **kwargs):
    return subprocess.run([cli, *map(str, args)], capture_output=True, text=True, **kwargs)


@pytest.fixture
def bumpy(mesh_dir):
    return read_off(mesh_dir / "bumpy_sphere.off")


def diagonal(v):
    return float(np.linalg.norm(v.max(0) - v.min(0)))


# ------------------------------------------------------------------ D5: stray vertices

def test_a_spike_vertex_that_makes_a_component_flat_is_named(cli, bumpy, tmp_path):
    v, f = bumpy
    v = v.copy()
    v[5] *= 1e4  # one vertex far out: the component's diagonal is the spike's
    write_off(tmp_path / "spike.off", v, f)
    r = sc(cli, "check", tmp_path / "spike.off")
    assert r.returncode == 2, r.stderr
    assert "component with no volume" in r.stderr
    assert "vertex 5 at (" in r.stderr and "from the other vertices" in r.stderr, r.stderr


def test_a_vertex_left_at_the_origin_of_a_far_mesh_is_named(cli, bumpy, tmp_path):
    v, f = bumpy
    v = v + np.array([500000.0, 5000000.0, 100.0])
    v[7] = 0.0
    write_off(tmp_path / "stray.off", v, f)
    r = sc(cli, "run", tmp_path / "stray.off", "-o", tmp_path / "out.off", "-n", 1)
    assert r.returncode == 2, r.stderr
    assert "vertex 7 at (0, 0, 0)" in r.stderr, r.stderr
    # The distance said is the stray's from the others' box: millions, against their diagonal.
    said = float(r.stderr.split("vertex 7 at (0, 0, 0) lies ")[1].split()[0])
    rest = v[np.arange(len(v)) != 7]
    assert said > 1e6 and abs(said - np.linalg.norm(np.maximum(rest.min(0) - 0.0, 0))) < 1e-2 * said


def test_repair_names_the_stray_it_cannot_help_with(cli, bumpy, tmp_path):
    v, f = bumpy
    v = v + np.array([500000.0, 5000000.0, 100.0])
    v[7] = 0.0
    write_off(tmp_path / "stray.off", v, f)
    r = sc(cli, "repair", tmp_path / "stray.off", "-o", tmp_path / "fixed.off")
    assert r.returncode == 2
    assert "cannot repair" in r.stderr and "vertex 7 at (0, 0, 0)" in r.stderr, r.stderr


def test_two_strays_at_one_place_are_named_together(cli, bumpy, tmp_path):
    v, f = bumpy
    v = v.copy()
    v[3] = v[9] = np.array([1e5, 0.0, 0.0])
    write_off(tmp_path / "two.off", v, f)
    r = sc(cli, "check", tmp_path / "two.off")
    assert r.returncode == 2
    assert "vertices " in r.stderr and " lie up to " in r.stderr, r.stderr
    named = r.stderr.split("; vertices ")[1].split(" lie up to")[0]
    assert sorted(int(p.split(" at")[0]) for p in named.split(", ") if " at " in p) == [3, 9], named


def test_a_truly_flat_shape_names_no_stray(cli, bumpy, tmp_path):
    v, f = bumpy
    write_off(tmp_path / "flat.off", v * np.array([1.0, 1.0, 1e-12]), f)
    r = sc(cli, "check", tmp_path / "flat.off")
    assert r.returncode == 2
    assert "volume" in r.stderr and "from the other vertices" not in r.stderr, r.stderr


# ------------------------------------------------------------- D6: near-duplicate vertices

def near_duplicate_seam(v, f):
    """Vertex 0 split in two copies 1e-12 apart, half of its faces on each."""
    faces = np.where((f == 0).any(1))[0]
    v2 = np.vstack([v, v[0] + np.array([1e-12, 0.0, 0.0])])
    f2 = f.copy()
    for k in faces[:len(faces) // 2]:
        f2[k][f2[k] == 0] = len(v)
    return v2, f2


def test_an_open_boundary_at_a_near_duplicate_says_so_and_names_repair(cli, bumpy, tmp_path):
    write_off(tmp_path / "seam.off", *near_duplicate_seam(*bumpy))
    r = sc(cli, "run", tmp_path / "seam.off", "-o", tmp_path / "out.off", "-n", 1)
    assert r.returncode == 2
    assert "open boundary" in r.stderr
    assert "near-duplicate" in r.stderr and "shellcontract repair" in r.stderr, r.stderr


def test_a_far_open_boundary_names_no_near_duplicate(cli, bumpy, tmp_path):
    v, f = bumpy
    write_off(tmp_path / "hole.off", v, f[1:])
    r = sc(cli, "check", tmp_path / "hole.off")
    assert r.returncode == 2 and "open boundary" in r.stderr
    assert "near-duplicate" not in r.stderr


def test_exact_seam_copies_of_a_mesh_open_elsewhere_are_no_near_duplicates(cli, bumpy, tmp_path):
    v, f = bumpy
    v2, f2 = near_duplicate_seam(v, f)
    v2[-1] = v2[0]  # an exact copy: a UV seam's, welded by the reader
    # The hole at the copied vertex: its open edges end at a vertex that has an exact copy.
    at_copy = [k for k in range(len(f2)) if (f2[k] == 0).any()][0]
    write_off(tmp_path / "seam_hole.off", v2, np.delete(f2, at_copy, axis=0))
    r = sc(cli, "check", tmp_path / "seam_hole.off")
    assert r.returncode == 2 and "open boundary" in r.stderr, r.stderr
    assert "near-duplicate" not in r.stderr, r.stderr


def test_repair_merges_near_duplicates_instead_of_filling_the_crack(cli, bumpy, tmp_path):
    v, f = bumpy
    write_off(tmp_path / "seam.off", *near_duplicate_seam(v, f))
    r = sc(cli, "repair", tmp_path / "seam.off", "-o", tmp_path / "fixed.off", "--json")
    assert r.returncode == 0, r.stderr
    report = json.loads(r.stdout)
    assert report["duplicate_points_merged"] == 1
    fv, ff = read_off(tmp_path / "fixed.off")
    # The original sphere back: no hole faces, no needle faces, every kept vertex an input one.
    assert len(fv) == len(v) and len(ff) == len(f)
    assert np.array_equal(np.sort(fv, axis=0), np.sort(v, axis=0))
    c = sc(cli, "check", "--json", tmp_path / "fixed.off")
    assert c.returncode == 0 and json.loads(c.stdout)["zero_area_faces"] == []


# --------------------------------------------- D7: an inside-out input's winding per format

@pytest.mark.parametrize("source,output,kept", [
    ("off", "off", False), ("off", "obj", False), ("obj", "off", False), ("off", "stl", False),
    ("obj", "obj", True), ("ply", "ply", True),
])
def test_an_inside_out_inputs_winding_is_flipped_except_in_a_same_format_copy(
        cli, mesh_dir, tmp_path, source, output, kept):
    v, f = read_off(mesh_dir / "ico2.off")
    v = v * np.array([-1.0, 1.0, 1.0])  # mirrored: every face winds inward
    {"off": write_off, "obj": write_obj, "ply": write_ply}[source](tmp_path / ("in." + source), v, f)
    r = sc(cli, "run", tmp_path / ("in." + source), "-o", tmp_path / ("out." + output), "-n", 2)
    assert r.returncode == 0 and "was inside-out" in r.stderr, r.stderr
    c = sc(cli, "check", "--json", tmp_path / ("out." + output))
    assert c.returncode == 0, c.stderr
    assert json.loads(c.stdout)["reoriented"] is kept


# ------------------------------------------------------- D8: every vertex held at rest

def test_a_run_that_holds_every_vertex_says_first_that_nothing_can_move(cli, bumpy, tmp_path):
    v, f = bumpy
    write_off(tmp_path / "flat.off", v * np.array([1.0, 1.0, 1e-4]), f)
    r = sc(cli, "run", tmp_path / "flat.off", "-o", tmp_path / "out.off", "-n", 2)
    warnings = [l for l in r.stderr.splitlines() if l.startswith("warning:")]
    assert warnings and "nothing can move" in warnings[0], r.stderr
    assert "--delta auto" in warnings[0]


def test_a_run_that_holds_a_few_vertices_does_not_say_nothing_can_move(cli, tmp_path, mesh_dir):
    r = sc(cli, "run", mesh_dir / "bumpy_sphere.off", "-o", tmp_path / "out.off", "-n", 2)
    assert r.returncode == 0 and "nothing can move" not in r.stderr


# ------------------------------------------------- review13 L4: out of file descriptors

def test_no_file_descriptor_for_the_input_is_a_resource_failure(cli, mesh_dir, tmp_path):
    seen = 0
    for limit in range(3, 9):
        def low():
            resource.setrlimit(resource.RLIMIT_NOFILE, (limit, limit))
        r = sc(cli, "run", mesh_dir / "ico2.off", "-o", tmp_path / "o.off", "-n", 2, "-q",
               "--checkpoint", tmp_path / "ck", preexec_fn=low)
        if "ico2.off: cannot open file" in r.stderr:
            seen += 1
            assert "Too many open files" in r.stderr
            assert r.returncode == 3, r.stderr  # a resource the system refused, not a bad input
    assert seen > 0, "no limit ran out of descriptors while opening the input"


# ----------------------------------------------------------- review13 L6: frame counts

@pytest.mark.parametrize("option", ["--checkpoint-every", "--export-every"])
def test_a_frame_count_that_is_not_an_integer_gets_the_range(cli, mesh_dir, tmp_path, option):
    extra = ["--checkpoint", tmp_path / "ck"] if option == "--checkpoint-every" else [
        "--export-dir", tmp_path / "frames"]
    r = sc(cli, "run", mesh_dir / "ico2.off", "-o", tmp_path / "o.off", "-n", 2, option, "2,5", *extra)
    assert r.returncode == 1
    assert option + ": '2,5' is not an integer in [1, " in r.stderr, r.stderr


# ------------------------------------------------------------------ the Python API likewise

def test_arrays_with_a_stray_vertex_name_it(bumpy):
    import shellcontract
    v, f = bumpy
    v = v + np.array([500000.0, 5000000.0, 100.0])
    v[7] = 0.0
    with pytest.raises(ValueError, match=r"vertex 7 at \(0, 0, 0\) lies"):
        shellcontract.check(v, f)


def test_python_no_file_descriptor_for_the_input_is_an_oserror_of_its_errno(mesh_dir):
    import sys
    code = ("import errno, resource, shellcontract\n"
            "resource.setrlimit(resource.RLIMIT_NOFILE, (3, 3))\n"
            "try:\n"
            "    shellcontract.read_mesh(%r)\n"
            "except OSError as e:\n"
            "    print(type(e).__name__, e.errno == errno.EMFILE)\n" % str(mesh_dir / "ico2.off"))
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.stdout.split() == ["FileError", "True"], r.stdout + r.stderr
