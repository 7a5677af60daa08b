"""frames(), check(), regions(), read_mesh() and write_mesh(), each against the CLI's answer."""
import os
import pathlib
import re
import subprocess

import numpy as np
import pytest

import shellcontract


def test_frames_yields_every_nth_frame_and_returns_the_result(ico2):
    vertices, faces = ico2
    gen = shellcontract.frames(vertices, faces, every=3, frames=10)
    got = []
    with pytest.raises(StopIteration) as stop:
        while True:
            got.append(next(gen))
    result = stop.value.value
    assert [f for f, _, _ in got] == [3, 6, 9]
    assert result.summary["frames_run"] == 10
    np.testing.assert_array_equal([m["volume_ratio"] for _, _, m in got],
                                  result.log["volume_ratio"][[2, 5, 8]])


def test_closing_frames_early_cancels_the_run(ico2, monkeypatch):
    # The run behind frames() is watched through contract(), which frames() calls: the frames its
    # callback saw and the Result it returned prove that the run stopped a frame or two after the
    # close, not after its 100,000 frames (which would also keep close() from returning).
    seen = []
    results = []
    real_contract = shellcontract.contract

    def watched(vertices, faces, *, callback=None, **options):
        def counting(frame, v, metrics):
            seen.append(frame)
            return callback(frame, v, metrics)
        result = real_contract(vertices, faces, callback=counting, **options)
        results.append(result)
        return result

    monkeypatch.setattr(shellcontract, "contract", watched)
    vertices, faces = ico2
    gen = shellcontract.frames(vertices, faces, frames=100000)
    assert next(gen)[0] == 1
    gen.close()  # joins the worker: when it returns, the run has returned
    assert len(results) == 1
    # Frame 1 was handed over, frame 2 at most waits in the one-slot queue, and the callback of
    # the frame after it sees the stop.
    assert results[0].summary["frames_run"] <= 3
    assert seen == list(range(1, len(seen) + 1)) and len(seen) <= 3
    assert results[0].status == "cancelled"


def test_check_reports_what_the_cli_reports(cli, mesh_dir):
    path = mesh_dir / "torus.off"
    report = shellcontract.check(*shellcontract.read_mesh(path))
    text = subprocess.run([cli, "check", str(path)], check=True, capture_output=True, text=True).stdout
    cli_values = dict(line.split(": ", 1) for line in text.splitlines() if ": " in line)
    assert report["genus"] == int(cli_values["genus"]) == 1
    assert report["euler_characteristic"] == int(cli_values["euler_characteristic"])
    assert report["edges"] == int(cli_values["edges"])
    assert report["volume"] == float(cli_values["volume"])
    assert report["self_intersections"].shape == (0, 2)


def test_regions_match_the_cli_face_list(cli, mesh_dir, tmp_path):
    path = mesh_dir / "bumpy_sphere.off"
    face_list = tmp_path / "regions.txt"
    subprocess.run([cli, "regions", str(path), "-o", str(tmp_path / "r.ply"), "--face-list", str(face_list)],
                   check=True, capture_output=True)
    expected = [[int(t) for t in line.split()] for line in face_list.read_text().splitlines() if line.strip()]
    got = shellcontract.regions(*shellcontract.read_mesh(path))
    assert len(got) == 3  # the mesh's three bumps (meshes/README.md)
    assert [list(r) for r in got] == expected


def test_regions_options_are_used_and_checked(mesh_dir):
    # The CLI's option names, with '_' or '-'.
    vertices, faces = shellcontract.read_mesh(mesh_dir / "bumpy_sphere.off")
    assert shellcontract.regions(vertices, faces, contrast=100.0) == []
    assert shellcontract.regions(vertices, faces, **{"min-cap-angle": 180.0}) == []
    with pytest.raises(TypeError, match="unknown option 'min_curvature_contrast'"):
        shellcontract.regions(vertices, faces, min_curvature_contrast=2.0)


def capsule(r=1.0, length=4.0, rings=60, around=32):
    """A closed capsule along z (cylinder of radius r and the given length, hemispherical ends),
    rings equally spaced in arc length from pole to pole; faces outward."""
    total = np.pi * r + length

    def profile(s):
        if s < 0.5 * np.pi * r:
            a = s / r
            return r * np.sin(a), 0.5 * length + r * np.cos(a)
        if s < 0.5 * np.pi * r + length:
            return r, 0.5 * length - (s - 0.5 * np.pi * r)
        a = (total - s) / r
        return r * np.sin(a), -0.5 * length - r * np.cos(a)
    phi = 2 * np.pi * np.arange(around) / around
    v = [[0.0, 0.0, 0.5 * length + r]]
    for k in range(1, rings):
        rho, z = profile(total * k / rings)
        v += [[rho * np.cos(p), rho * np.sin(p), z] for p in phi]
    v.append([0.0, 0.0, -0.5 * length - r])
    ring = lambda k, j: 1 + (k - 1) * around + j % around  # noqa: E731
    f = [[0, ring(1, j), ring(1, j + 1)] for j in range(around)]
    for k in range(1, rings - 1):
        for j in range(around):
            f += [[ring(k, j), ring(k + 1, j), ring(k + 1, j + 1)], [ring(k, j), ring(k + 1, j + 1), ring(k, j + 1)]]
    f += [[len(v) - 1, ring(rings - 1, j + 1), ring(rings - 1, j)] for j in range(around)]
    v, f = np.array(v), np.array(f, dtype=np.int64)
    if np.einsum("ij,ij->i", v[f[:, 0]], np.cross(v[f[:, 1]], v[f[:, 2]])).sum() < 0:
        f = f[:, [0, 2, 1]]
    return v, f


def test_regions_method_tips_matches_the_cli_and_finds_the_capsule_ends(cli, tmp_path):
    vertices, faces = capsule()
    path = tmp_path / "capsule.off"
    shellcontract.write_mesh(path, vertices, faces)
    face_list = tmp_path / "tips.txt"
    subprocess.run([cli, "regions", str(path), "-o", str(tmp_path / "t.ply"), "--method", "tips",
                    "--face-list", str(face_list)], check=True, capture_output=True)
    expected = [[int(t) for t in line.split()] for line in face_list.read_text().splitlines() if line.strip()]
    got = shellcontract.regions(*shellcontract.read_mesh(path), method="tips")
    assert [list(r) for r in got] == expected
    # The two ends: one region holds the top pole's fan (the first 32 faces), the other the
    # bottom's (the last 32).
    assert len(got) == 2
    top, bottom = set(range(32)), set(range(len(faces) - 32, len(faces)))
    sets = [set(int(i) for i in r) for r in got]
    assert (top <= sets[0] and bottom <= sets[1]) or (top <= sets[1] and bottom <= sets[0])


def test_regions_method_caps_is_the_default(mesh_dir):
    vertices, faces = shellcontract.read_mesh(mesh_dir / "bumpy_sphere.off")
    default = shellcontract.regions(vertices, faces)
    assert len(default) == 3
    assert [list(r) for r in shellcontract.regions(vertices, faces, method="caps")] == [list(r) for r in default]


def test_write_then_read_gives_the_same_arrays(ico2, tmp_path):
    vertices, faces = ico2
    for ext in ("off", "obj", "ply"):
        path = tmp_path / ("copy." + ext)
        shellcontract.write_mesh(path, vertices, faces.astype(np.int32))
        v, f = shellcontract.read_mesh(path)
        np.testing.assert_array_equal(v, vertices, err_msg=ext)
        np.testing.assert_array_equal(f, faces, err_msg=ext)


def test_read_mesh_refuses_like_the_cli(mesh_dir):
    with pytest.raises(ValueError, match="non-finite coordinate"):
        shellcontract.read_mesh(mesh_dir / "bad" / "nan.off")


def test_read_mesh_warns_of_what_the_reader_changed(mesh_dir):
    """Before, the reader's warnings (an inside-out mesh flipped, polygons split) were dropped:
    the CLI said them, Python said nothing."""
    with pytest.warns(UserWarning, match="inside.out"):
        shellcontract.read_mesh(mesh_dir / "inside_out_sphere.off")


def test_write_mesh_says_a_gltf_needs_like(tmp_path, ico2):
    """Before: "unknown extension '.glb'", though a .glb is written with like=."""
    v, f = ico2
    for name in ("x.glb", "x.GLTF"):
        with pytest.raises(ValueError, match=r"is written only with like="):
            shellcontract.write_mesh(tmp_path / name, v, f)
        assert not (tmp_path / name).exists()


def test_a_file_without_extension_is_said_to_have_none(tmp_path):
    """Before: "unknown extension: '.'"."""
    plain = tmp_path / "mesh_without_extension"
    plain.write_text("OFF\n")
    with pytest.raises(ValueError, match=r"has no extension: expected \.off, \.obj, \.ply, "
                                         r"\.stl, \.glb or \.gltf") as e:
        shellcontract.read_mesh(plain)
    assert "'.'" not in str(e.value)
    with pytest.raises(ValueError, match="unknown extension: '.xyz'"):
        (tmp_path / "m.xyz").write_text("x")
        shellcontract.read_mesh(pathlib.Path(tmp_path / "m.xyz"))


def test_write_mesh_names_what_is_wrong_with_the_name(tmp_path, ico2):
    """Before: "unknown extension '.'" for a name without one and for a folder."""
    v, f = ico2
    with pytest.raises(ValueError, match="the file name has no extension") as e:
        shellcontract.write_mesh(tmp_path / "noext", v, f)
    assert "'.'" not in str(e.value)
    with pytest.raises(ValueError, match="it is a folder"):
        shellcontract.write_mesh(tmp_path, v, f)
    assert os.listdir(tmp_path) == []


def off_arrays(path):
    """A plain triangle OFF file's arrays, without any check (the checks are what is tested)."""
    rows = [line.split("#")[0].split() for line in path.read_text().splitlines()]
    rows = [r for r in rows if r]
    nv, nf = int(rows[1][0]), int(rows[1][1])
    vertices = np.array([[float(t) for t in r[:3]] for r in rows[2:2 + nv]])
    faces = np.array([[int(t) for t in r[1:4]] for r in rows[2 + nv:2 + nv + nf]])
    return vertices, faces


BAD_TRIANGLE_MESHES = ["nan.off", "duplicate_face.off", "inconsistent_orientation.off",
                       "index_out_of_range.off", "nonmanifold_edge.off", "nonmanifold_vertex.off",
                       "open_sheet.off", "repeated_vertex.off"]


@pytest.mark.parametrize("name", BAD_TRIANGLE_MESHES)
def test_arrays_are_refused_for_the_cli_reason(cli, mesh_dir, name):
    """The array checks (mesh/from_arrays.cpp) name the same problem as the file reader."""
    path = mesh_dir / "bad" / name
    cli_error = subprocess.run([cli, "check", str(path)], capture_output=True, text=True)
    assert cli_error.returncode == 2
    problem = re.search(re.escape(str(path)) + r": ([a-z -]+):", cli_error.stderr).group(1)
    with pytest.raises(ValueError, match="^input arrays: " + problem + ":"):
        shellcontract.check(*off_arrays(path))


def test_contract_takes_what_regions_returns_and_per_face_labels(mesh_dir):
    # The three forms of regions give the same run.
    vertices, faces = shellcontract.read_mesh(mesh_dir / "bumpy_sphere.off")
    found = shellcontract.regions(vertices, faces)
    labels = [-1] * len(faces)
    for k, r in enumerate(found):
        for f in r:
            labels[int(f)] = k
    a = shellcontract.contract(vertices, faces, regions=found, frames=3, pressure=0.0)
    b = shellcontract.contract(vertices, faces, regions=labels, frames=3, pressure=0.0)
    assert a.summary["regions"] == len(found) == 3
    assert (a.vertices == b.vertices).all()
    with pytest.raises(ValueError, match="one entry per face"):
        shellcontract.contract(vertices, faces, regions=[0, 1], frames=1)


def test_region_strengths_scale_each_region(mesh_dir):
    # A strength per region from Python. Strength 1 everywhere is the run
    # without strengths; 0.5 everywhere is region_shrink times 0.5, bit for bit (a power of two
    # keeps the area-weighted mean strength exact), so it sinks less.
    vertices, faces = shellcontract.read_mesh(mesh_dir / "bumpy_sphere.off")
    found = shellcontract.regions(vertices, faces)
    run = dict(frames=40, pressure=0.0)
    plain = shellcontract.contract(vertices, faces, regions=found, **run)
    ones = shellcontract.contract(vertices, faces, regions=found, region_strengths=[1.0] * len(found), **run)
    half = shellcontract.contract(vertices, faces, regions=found, region_strengths=np.full(len(found), 0.5), **run)
    shrunk = shellcontract.contract(vertices, faces, regions=found, region_shrink=0.7 * 0.5, **run)
    assert (ones.vertices == plain.vertices).all()
    assert (half.vertices == shrunk.vertices).all()
    assert 0.0 < half.summary["region_inward_displacement"] < 0.8 * plain.summary["region_inward_displacement"]
    with pytest.raises(ValueError, match="2 values for 3 regions"):
        shellcontract.contract(vertices, faces, regions=found, region_strengths=[1, 1], frames=1)
    with pytest.raises(ValueError, match=r"region_strengths\[1\] = 1.5"):
        shellcontract.contract(vertices, faces, regions=found, region_strengths=[1, 1.5, 1], frames=1)
    with pytest.raises(ValueError, match="face lists or labels"):
        shellcontract.contract(vertices, faces, regions="auto", region_strengths=[1], frames=1)


def test_the_result_repr_names_only_what_can_be_read(ico2):
    # Before, repr gave "Result(status='ok', frames_run=2, ...)", but result.frames_run raised
    # AttributeError: each name the repr shows must be an attribute or a summary key.
    vertices, faces = ico2
    result = shellcontract.contract(vertices, faces, frames=2)
    text = repr(result)
    assert text.startswith("<Result status='ok'")
    for key in re.findall(r"summary\['(\w+)'\]", text):
        assert key in result.summary
    for name in re.findall(r"[<,] (\w+)=", text):
        assert hasattr(result, name), name
    assert "frames_run=" not in text.replace("summary['frames_run']=", "")
    assert str(len(vertices)) + " vertices" in text


def test_the_version_is_the_cli_s(cli):
    # Before: no __version__, though checkpoints are refused for "another version".
    out = subprocess.run([cli, "--version"], capture_output=True, text=True, check=True).stdout.split()
    # "shellcontract BUILD (KERNELS kernels)": the build and the kernels are the module's too.
    assert out[0] == "shellcontract"
    assert shellcontract.__version__ == out[1]
    assert out[2:] == ["(" + shellcontract.kernels, "kernels)"]


def test_regions_refuses_an_option_given_by_both_spellings(mesh_dir):
    # Before: region-at and region_at both given, the last one silently won.
    v, f = shellcontract.read_mesh(mesh_dir / "bumpy_sphere.off")
    with pytest.raises(TypeError, match="given .*twice|twice"):
        shellcontract.regions(v, f, **{"region-at": v[0], "region_at": v[1]})


def test_a_bool_for_a_number_says_it_is_a_bool(ico2):
    # Before: "frames: 'on' is not an integer", a ValueError about a value never given.
    v, f = ico2
    with pytest.raises(TypeError, match="frames: got the bool True, which only on/off options take"):
        shellcontract.contract(v, f, frames=True)
    assert shellcontract.contract(v, f, frames=2, collisions=False).status == "ok"


def test_lambda_is_also_lambda_and_frames_takes_no_callback(ico2):
    # Before: lambda_ was an unknown option (lambda, a keyword, only through **{"lambda": x}),
    # and frames(..., callback=f) failed with "multiple values for keyword argument 'callback'".
    v, f = ico2
    a = shellcontract.contract(v, f, frames=2, **{"lambda": 0.7})
    b = shellcontract.contract(v, f, frames=2, lambda_=0.7)
    assert a.vertices.tolist() == b.vertices.tolist() and float(b.summary["options"]["lambda"]) == 0.7
    with pytest.raises(TypeError, match="the same option"):
        shellcontract.contract(v, f, frames=2, lambda_=0.7, **{"lambda": 0.7})
    with pytest.raises(TypeError, match="frames\\(\\) takes no callback"):
        next(shellcontract.frames(v, f, callback=lambda *a: None, frames=2))


def test_a_list_for_an_option_of_one_value_is_refused(ico2):
    # Before: frames=[2] ran 2 frames (the list's items reached the option table as text), and a
    # sweep file's "frames": [5] read as 5.
    v, f = ico2
    for bad in ([2], (2,), np.array([2])):
        with pytest.raises(TypeError, match="frames: got .*it takes one value"):
            shellcontract.contract(v, f, frames=bad)
    with pytest.raises(TypeError, match="damping: got"):
        shellcontract.contract(v, f, frames=2, damping=[0.1])
    # The options that take a list, and a numpy scalar, still work.
    r = shellcontract.contract(v, f, frames=np.int64(2), collisions=False, fiber=[1, 0, 0],
                               aniso="active-fiber", target_volume=[(0, 1.0), (2, 0.9)],
                               pressure=[(0, 4), (2, 3)])
    assert r.status in ("ok", "target not reached")


def test_a_refused_float_is_quoted_as_the_tool_writes_it(ico2):
    # Before: "--pressure: '2000000.0' is not a number", Python's repr where the CLI, --help and
    # the summary write 2e+06.
    v, f = ico2
    with pytest.raises(ValueError, match="pressure: '2e\\+06' is not a number in \\[-1e\\+06, 1e\\+06\\]"):
        shellcontract.contract(v, f, pressure=2e6)
    # A whole float for an integer option is that integer (a JSON sweep file's 10.0).
    assert shellcontract.contract(v, f, frames=2.0, collisions=False).summary["options"]["frames"] == "2"


def test_lambda_takes_back_a_negative_poisson_ratios_value(ico2):
    # Before: poisson=-0.5 recorded lambda -1.33, which lambda_ refused ("a finite number >= 0")
    # (review9 D5). The membrane needs mu + lambda > 0 (a Poisson ratio above -1), no more.
    v, f = ico2
    a = shellcontract.contract(v, f, frames=2, poisson=-0.5)
    recorded = {k: float(a.summary["options"][k]) for k in ("young", "thickness", "poisson", "mu", "lambda")}
    assert recorded["lambda"] < 0
    b = shellcontract.contract(v, f, frames=2, **recorded)
    assert a.vertices.tolist() == b.vertices.tolist()
    c = shellcontract.contract(v, f, frames=2, solver="pbd", mu=2, lambda_=-1.9)
    assert c.status == "ok" and float(c.summary["options"]["lambda"]) == -1.9
    with pytest.raises(ValueError, match="lambda must be greater than -mu"):
        shellcontract.contract(v, f, frames=2, solver="pbd", mu=2, lambda_=-2)


def test_the_fallback_bending_is_a_warning(ico2):
    # Before: mu and lambda given under xpbd dropped the shell material and k_B became 0.01
    # without a word (review9 D3).
    v, f = ico2
    assert not any("k_B" in w for w in shellcontract.contract(v, f, frames=1).summary["warnings"])
    r = shellcontract.contract(v, f, frames=1, mu=0.7, lambda_=0.6)
    assert any(w.startswith("the bending k_B is 0.01") and "k_b" in w for w in r.summary["warnings"]), r.summary["warnings"]


def test_the_isometric_bendings_k_b_is_a_warning(ico2):
    # Before: bending="isometric" under xpbd ran with k_B 0.01 whatever the shell material, with no
    # word; the warning names the shell's k_B, the dihedral bending's of the same shell.
    v, f = ico2
    shell_k_b = shellcontract.contract(v, f, frames=1).summary["options"]["k_b"]
    r = shellcontract.contract(v, f, frames=1, bending="isometric")
    assert any(w.startswith("the bending k_B is 0.01") and "has k_B " + shell_k_b + ": give k_b" in w
               for w in r.summary["warnings"]), r.summary["warnings"]
    given = shellcontract.contract(v, f, frames=1, bending="isometric", k_b=float(shell_k_b))
    assert not any(w.startswith("the bending k_B") for w in given.summary["warnings"])


def test_the_summary_s_options_without_the_empty_ones_rerun_the_run(ico2):
    # Before: the options a run ignored were recorded with their table values (mu_a, k_a, the
    # dimple, delta with collisions off, ...). Now empty: left out, the others rerun the run.
    v, f = ico2
    # mu given: no shell material, whose recorded mu and lambda a rerun beside young and
    # thickness would be warned of (set by those; the same run).
    a = shellcontract.contract(v, f, frames=3, mu=2, mu_a=3, k_a=0.3, dimple="volume",
                               inward="force", mass="unit", density=2, collisions=False,
                               delta=0.01, target_ramp=2)
    options = a.summary["options"]
    for name in ("mu_a", "k_a", "dimple", "inward", "density", "delta", "target_ramp", "fiber",
                 "poisson", "young"):
        assert options[name] == "", name
    assert options["mass"] == "unit" and options["collisions"] == "off"
    b = shellcontract.contract(v, f, **{k: value for k, value in options.items() if value != ""})
    assert a.vertices.tolist() == b.vertices.tolist()
    assert not any("has no effect" in w for w in b.summary["warnings"]), b.summary["warnings"]
