"""contract(): callback, stopping, options, input dtypes and refused input."""
import os
import signal
import threading
import time

import numpy as np
import pytest

import shellcontract


def test_callback_sees_every_frame(ico2):
    vertices, faces = ico2
    seen = []

    def callback(frame, v, metrics):
        assert v.shape == vertices.shape and v.dtype == np.float64
        seen.append((frame, metrics["volume_ratio"], v.copy()))

    result = shellcontract.contract(vertices, faces, frames=12, callback=callback)
    assert [s[0] for s in seen] == list(range(1, 13))
    np.testing.assert_array_equal([s[1] for s in seen], result.log["volume_ratio"])
    np.testing.assert_array_equal(seen[-1][2], result.vertices)  # the last frame is the result


def test_stage_callback_hears_the_preparation_then_the_end_check(ico2):
    vertices, faces = ico2
    calls = []
    result = shellcontract.contract(
        vertices, faces, frames=3, regions="auto", validate="end",
        stage=lambda what: calls.append(("stage", what)),
        callback=lambda frame, v, m: calls.append(("frame", frame)))
    assert result.summary["frames_run"] == 3
    stages = [what for kind, what in calls if kind == "stage"]
    first_frame = calls.index(("frame", 1))
    # The preparation's stages, in order, all before the first frame.
    assert [c for c in calls[:first_frame] if c[0] != "stage"] == []
    for earlier, later in [("selecting the regions (curvature)", "building the rest state"),
                           ("building the rest state", "finding the contact pairs at rest")]:
        assert stages.index(earlier) < stages.index(later), stages
    # The last step's check, before that frame's callback.
    assert calls[-2:] == [("stage", "checking the result for self-intersections"), ("frame", 3)]


def test_stage_callback_error_stops_the_run_and_is_raised(ico2):
    vertices, faces = ico2

    def stage(what):
        raise ValueError("stop at " + what)

    with pytest.raises(ValueError, match="stop at"):
        shellcontract.contract(vertices, faces, frames=3, stage=stage)
    with pytest.raises(TypeError, match="stage must be callable"):
        shellcontract.contract(vertices, faces, frames=3, stage=3)


def test_returning_false_cancels_the_run(ico2):
    vertices, faces = ico2
    result = shellcontract.contract(vertices, faces, frames=50,
                                    callback=lambda frame, v, m: frame < 5)
    assert result.status == "cancelled"
    assert result.summary["frames_run"] == 5
    assert list(result.log["frame"]) == [1, 2, 3, 4, 5]


def test_returning_none_goes_on(ico2):
    vertices, faces = ico2
    result = shellcontract.contract(vertices, faces, frames=6, callback=lambda frame, v, m: None)
    assert result.status == "ok" and result.summary["frames_run"] == 6


def test_a_numpy_false_from_the_callback_stops_the_run(ico2):
    """Before: only Python's False stopped; np.False_ (a comparison's result) ran every frame."""
    v, f = ico2
    r = shellcontract.contract(v, f, frames=20, callback=lambda frame, vv, m: np.int64(frame) < 3)
    assert r.status == "cancelled" and r.summary["frames_run"] == 3
    r = shellcontract.contract(v, f, frames=20, callback=lambda frame, vv, m: 0 if frame == 2 else 1)
    assert r.status == "cancelled" and r.summary["frames_run"] == 2
    r = shellcontract.contract(v, f, frames=4, callback=lambda frame, vv, m: None)
    assert r.status == "ok" and r.summary["frames_run"] == 4
    with pytest.raises(ValueError, match="truth value of an array"):
        shellcontract.contract(v, f, frames=4, callback=lambda frame, vv, m: vv[:, 2] > 0)


def test_callback_exception_stops_and_propagates(ico2):
    vertices, faces = ico2

    def callback(frame, v, m):
        if frame == 3:
            raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        shellcontract.contract(vertices, faces, frames=50, callback=callback)


def test_keyboard_interrupt_stops_the_run(ico2):
    """SIGINT during the run (GIL released, no callback) is seen by the observer's poll: the run
    ends long before its frames are done. Durations are compared with each other only (a run of
    a 250th of the frames, timed here, on the same machine and load), not with a fixed bound."""
    vertices, faces = ico2
    frames = 100000
    start = time.monotonic()
    shellcontract.contract(vertices, faces, frames=frames // 250)
    whole = 250 * (time.monotonic() - start)  # about what the uninterrupted run would take
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            shellcontract.contract(vertices, faces, frames=frames)
    finally:
        timer.cancel()
    assert time.monotonic() - start < whole / 4


@pytest.mark.parametrize("face_dtype", [np.int32, np.int64, np.uint16])
def test_face_dtypes_give_the_same_result(ico2, face_dtype):
    vertices, faces = ico2
    reference = shellcontract.contract(vertices, faces.astype(np.int64), frames=5)
    result = shellcontract.contract(np.ascontiguousarray(vertices, dtype=np.float64),
                                    faces.astype(face_dtype), frames=5)
    np.testing.assert_array_equal(result.vertices, reference.vertices)
    np.testing.assert_array_equal(result.faces, faces)


def test_strided_and_list_input_work(ico2):
    vertices, faces = ico2
    reference = shellcontract.contract(vertices, faces, frames=3)
    fortran = shellcontract.contract(np.asfortranarray(vertices), np.asfortranarray(faces), frames=3)
    lists = shellcontract.contract(vertices.tolist(), faces.tolist(), frames=3)
    np.testing.assert_array_equal(fortran.vertices, reference.vertices)
    np.testing.assert_array_equal(lists.vertices, reference.vertices)


def test_float_faces_are_refused(ico2):
    vertices, faces = ico2
    with pytest.raises(TypeError, match="faces must hold integers"):
        shellcontract.contract(vertices, faces.astype(np.float64), frames=1)


def test_wrong_shape_is_refused(ico2):
    vertices, faces = ico2
    with pytest.raises(ValueError, match=r"vertices must be an N by 3 array, got shape \(162, 2\)"):
        shellcontract.contract(vertices[:, :2], faces, frames=1)


def test_nan_coordinate_raises_value_error(ico2):
    vertices, faces = ico2
    vertices = vertices.copy()
    vertices[7, 1] = np.nan
    with pytest.raises(ValueError, match=r"non-finite coordinate: vertex 7 is \(.* nan .*\)"):
        shellcontract.contract(vertices, faces, frames=1)


def test_open_mesh_raises_value_error(ico2):
    vertices, faces = ico2
    with pytest.raises(ValueError, match="open boundary"):
        shellcontract.contract(vertices, faces[1:], frames=1)


def test_unknown_option_raises_and_lists_valid_ones(ico2):
    vertices, faces = ico2
    with pytest.raises(TypeError, match="unknown option 'presure'.*pressure.*k_b") as raised:
        shellcontract.contract(vertices, faces, presure=2.0)
    # contract()'s own arguments are valid options too (they were missing from the list).
    for name in ("checkpoint", "checkpoint_every", "resume"):
        assert name in str(raised.value).split("valid options: ")[1].split(", ")


def test_an_option_spelt_both_ways_is_refused(ico2):
    # An option is also taken as the CLI spells it, once: given both ways, the later spelling
    # had won silently (k-b=0.02, k_b=0.03 ran with 0.03; the other order with 0.02).
    vertices, faces = ico2
    with pytest.raises(TypeError, match="got the option 'k_b' twice"):
        shellcontract.contract(vertices, faces, frames=1, **{"k-b": 0.02, "k_b": 0.03})
    dashed = shellcontract.contract(vertices, faces, frames=2, **{"k-b": 0.02})
    assert dashed.vertices.tolist() == shellcontract.contract(vertices, faces, frames=2, k_b=0.02).vertices.tolist()


def test_bad_option_value_raises_value_error(ico2):
    vertices, faces = ico2
    with pytest.raises(ValueError, match="frames"):
        shellcontract.contract(vertices, faces, frames=-1)
    with pytest.raises(ValueError, match="dt"):
        shellcontract.contract(vertices, faces, dt=float("nan"))


def test_options_are_the_table_and_its_defaults(ico2):
    """options() lists the run's options with the defaults a run reports (frames=0: no step)."""
    table = shellcontract.options()
    names = [o.name for o in table]
    assert len(names) == len(set(names))
    assert {"pressure", "frames", "k_b", "target_volume", "collisions"} <= set(names)
    assert all(o.name == o.cli_name.replace("-", "_") and o.help for o in table)
    vertices, faces = ico2
    result = shellcontract.contract(vertices, faces, frames=0)
    reported = result.summary["options"]
    assert set(reported) == set(names)
    # The default run derives the membrane and the bending from its shell material (E, nu, h):
    # the run reports the values it used, the table the values a caller starts from.
    E, nu, h = (float(reported[n]) for n in ("young", "poisson", "thickness"))
    derived = {"mu": E * h / (2 * (1 + nu)), "lambda": E * h * nu / (1 - nu * nu),
               "k_b": E * h ** 3 / (36 * (1 - nu * nu))}
    # The options left at "auto" report the choice the run made (the default order is the
    # coloured one, whose speculative broad phase is off); the ramp, the one the run used: at most
    # half its frames, at least 1 (docs/cli.md, the summary's options).
    chosen = {"order": ("auto", "coloured"), "speculative_broad_phase": ("auto", "off")}
    # The options without effect in this run are reported empty (the Mooney-Rivlin parameters
    # under StVK, the local contraction's without regions, the ramp without a target, ...): each,
    # given, is a "has no effect" warning.
    unused = {o.name for o in table if reported[o.name] == "" and o.default != ""}
    assert {"c10", "c01", "mu_a", "k_a", "dimple", "region_shrink", "target_ramp"} <= unused
    for name in sorted(unused):
        default = next(o.default for o in table if o.name == name)
        warnings = shellcontract.contract(vertices, faces, frames=0, **{name: default}).summary["warnings"]
        assert any(w.startswith(name + " has no effect") for w in warnings), (name, warnings)
    for o in table:
        if o.name in unused:
            continue
        elif o.name in derived:
            assert float(reported[o.name]) == pytest.approx(derived[o.name], rel=1e-15), o.name
        elif o.name in chosen:
            assert (o.default, reported[o.name]) == chosen[o.name], o.name
        elif o.name != "frames":
            assert reported[o.name] == o.default, o.name


def test_option_help_names_the_other_options_as_python_does():
    """Before: the help read "--young", "--thickness", "-p > 0", names contract() does not take."""
    import re
    table = shellcontract.options()
    flags = {"--" + o.cli_name for o in table} | {"-p", "-n"}
    for o in table:
        found = set(re.findall(r"(?<![\w-])--?[a-z][a-z0-9-]*", o.help))
        assert not (found & flags), (o.name, found & flags, o.help)
    young = next(o for o in table if o.name == "young").help
    assert "(with thickness)" in young and "unless k_b is given" in young, young
    inward = next(o for o in table if o.name == "inward").help
    assert "under pressure > 0 without target_volume" in inward, inward


def test_bool_and_string_values(ico2):
    vertices, faces = ico2
    result = shellcontract.contract(vertices, faces, frames=2, collisions=False, solver="xpbd")
    assert result.summary["options"]["collisions"] == "off"
    assert result.summary["options"]["solver"] == "xpbd"
    assert result.summary["collisions"] is False


def test_gil_is_released_during_the_run(ico2):
    """Another Python thread keeps running while contract() computes (no callback): measured
    against its own rate, it must get a good share of the run's time. With the GIL held it gets
    only the switch intervals (5 ms) around the call, so the call must last many of them: the run
    doubles its frames until it takes at least 0.5 s, however fast the machine."""
    vertices, faces = ico2
    done = threading.Event()
    count = [0]

    def spin():
        while not done.is_set():
            count[0] += 1

    thread = threading.Thread(target=spin)
    thread.start()
    try:
        start, before = time.monotonic(), count[0]
        time.sleep(0.2)  # main thread idle: the spinner's rate alone
        rate = (count[0] - before) / (time.monotonic() - start)
        frames, elapsed = 4000, 0.0
        while elapsed < 0.5:
            start, before = time.monotonic(), count[0]
            result = shellcontract.contract(vertices, faces, frames=frames)
            elapsed, during = time.monotonic() - start, count[0] - before
            # more frames make a longer run only if the run does not stop early
            assert result.summary["frames_run"] == frames, result.summary["frames_run"]
            frames *= 2
    finally:
        done.set()
        thread.join()
    assert during > 0.05 * rate * elapsed, (during, rate, elapsed)


def _subdivided(vertices, faces):
    """Every triangle split in four at its edge midpoints (flat, not projected)."""
    e = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    unique, inverse = np.unique(e, axis=0, return_inverse=True)
    mid = len(vertices) + np.arange(len(unique))
    vertices = np.vstack([vertices, (vertices[unique[:, 0]] + vertices[unique[:, 1]]) / 2])
    ab, bc, ca = mid[inverse.reshape(3, -1)]
    a, b, c = faces.T
    return vertices, np.vstack([np.stack(t, axis=1) for t in
                                ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])


def test_keyboard_interrupt_stops_the_region_search(mesh_dir):
    """SIGINT during regions() (GIL released) is heard inside the search, as during contract()'s
    own: before, regions() raised KeyboardInterrupt only once its whole search had ended (bear
    split in four: at 6.2 s for a SIGINT at 1.0 s). 163,842 vertices: the heat smoothing, most of
    the search, iterates and asks at every iteration (below 100,000 vertices it factorizes, one
    uninterruptible call per smoothing length)."""
    vertices, faces = shellcontract.read_mesh(mesh_dir / "bumpy_sphere.off")
    for _ in range(4):
        vertices, faces = _subdivided(vertices, faces)
    start = time.monotonic()
    assert shellcontract.regions(vertices, faces)
    whole = time.monotonic() - start
    timer = threading.Timer(whole / 10, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            shellcontract.regions(vertices, faces)
    finally:
        timer.cancel()
    assert time.monotonic() - start < whole / 2, whole


def _edge_share(vertices, faces):
    """1/80 of the mean edge length over the bounding-box diagonal, each edge once."""
    edges = np.unique(np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]],
                                              faces[:, [2, 0]]]), axis=1), axis=0)
    diagonal = np.linalg.norm(vertices.max(axis=0) - vertices.min(axis=0))
    mean_edge = np.linalg.norm(vertices[edges[:, 0]] - vertices[edges[:, 1]], axis=1).mean()
    return mean_edge / diagonal / 80


def test_delta_auto_and_the_contact_distance_used(ico2):
    """--delta auto: the default 1e-4 on ico2 (long edges), 1/80 of the mean edge on ico2
    subdivided four times (81,920 faces); the summary reports the delta used."""
    vertices, faces = ico2
    assert _edge_share(vertices, faces) > 1e-4
    result = shellcontract.contract(vertices, faces, frames=1, delta="auto")
    assert result.summary["options"]["delta"] == "auto"
    assert result.summary["contact_distance"] == 1e-4
    for _ in range(4):
        vertices, faces = _subdivided(vertices, faces)
    share = _edge_share(vertices, faces)
    assert share < 1e-4
    result = shellcontract.contract(vertices, faces, frames=0, delta="auto")
    assert result.summary["contact_distance"] == pytest.approx(share, rel=1e-12)
    result = shellcontract.contract(vertices, faces, frames=0, delta=5e-5)
    assert result.summary["contact_distance"] == 5e-5
    result = shellcontract.contract(vertices, faces, frames=0, collisions=False)
    assert result.summary["contact_distance"] == 0.0


def test_file_names_may_be_path_objects(tmp_path, ico2):
    """Before: regions=Path raised 'option regions: expected a number, a string or a bool',
    region_weights=Path a TypeError from float()."""
    v, f = ico2
    reg = tmp_path / "reg.txt"
    reg.write_text("0 1 2 3 4\n")
    by_path = shellcontract.contract(v, f, regions=reg, frames=10, pressure=0)
    by_str = shellcontract.contract(v, f, regions=str(reg), frames=10, pressure=0)
    np.testing.assert_array_equal(by_path.vertices, by_str.vertices)
    weights = tmp_path / "w.txt"
    weights.write_text("".join("1\n" if i < 5 else "0\n" for i in range(len(v))))
    by_path = shellcontract.contract(v, f, region_weights=weights, frames=10, pressure=0)
    by_str = shellcontract.contract(v, f, region_weights=str(weights), frames=10, pressure=0)
    np.testing.assert_array_equal(by_path.vertices, by_str.vertices)
    ckpt = tmp_path / "c.ckpt"
    shellcontract.contract(v, f, callback=lambda fr, vv, m: fr < 4, checkpoint=ckpt,
                           checkpoint_every=4, regions=reg, frames=10, pressure=0)
    resumed = shellcontract.contract(v, f, resume=ckpt)
    whole = shellcontract.contract(v, f, regions=reg, frames=10, pressure=0)
    np.testing.assert_array_equal(resumed.vertices, whole.vertices)


def test_parts_that_touch_at_rest_are_warned_about(mesh_dir):
    """Two unit cubes, one on the other with vertices of their own: the pairs that touch at rest
    are left out of the collision handling for the whole run, and pressed together the cubes
    passed through each other. Before, contract() said nothing (the summary's
    excluded_contact_pairs only); now summary["warnings"] counts them, as the CLI's warning."""
    v, f = shellcontract.read_mesh(mesh_dir / "cube.off")

    def stacked(gap):
        return np.vstack([v, v + [0.0, 0.0, 1.0 + gap]]), np.vstack([f, f + len(v)])

    summary = shellcontract.contract(*stacked(0.0), frames=0).summary
    excluded = summary["excluded_contact_pairs"]
    assert excluded > 0
    touching = [w for w in summary["warnings"] if "touch at rest" in w]
    assert len(touching) == 1, summary["warnings"]
    assert touching[0].startswith(f"{excluded} pairs of primitives ("), touching[0]
    assert "(4, 5, 6, 7, ...)" in touching[0] and "pass through each other" in touching[0]
    summary = shellcontract.contract(*stacked(0.02), frames=0).summary
    assert summary["excluded_contact_pairs"] == 0
    assert not any("touch at rest" in w for w in summary["warnings"]), summary["warnings"]
