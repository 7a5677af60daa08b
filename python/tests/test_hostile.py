"""The Python module never crashes the interpreter and refuses bad arguments by type. Each test
failed against the module before the fix as its docstring says."""
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import shellcontract


def _exit_while_running(mesh_dir, body):
    """Runs a Python process that starts a long run, then lets the interpreter exit."""
    script = textwrap.dedent("""
        import sys, threading, time
        import shellcontract
        v, f = shellcontract.read_mesh(sys.argv[1])
    """) + textwrap.dedent(body)
    env = dict(os.environ)
    return subprocess.run([sys.executable, "-c", script, str(mesh_dir / "ico2.off")], env=env,
                          capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize("attempt", range(4))
def test_exit_while_contract_runs_in_a_daemon_thread(mesh_dir, attempt):
    """Before: the worker took the GIL back during finalization: SIGABRT (13 of 16 tries)."""
    r = _exit_while_running(mesh_dir, """
        t = threading.Thread(target=lambda: shellcontract.contract(v, f, frames=1000000), daemon=True)
        t.start()
        time.sleep(0.3 + 0.1 * %d)
    """ % attempt)
    assert r.returncode == 0, (r.returncode, r.stderr[-2000:])


def test_exit_while_regions_runs_in_a_daemon_thread(mesh_dir):
    """The exit stops a region search as it stops a run (regions() asks for Ctrl-C and the exit
    at its cancellation points): the process ends at once, silently. A search the exit stopped
    that took the GIL back to raise printed "Exception in thread" as the interpreter went away."""
    r = _exit_while_running(mesh_dir, """
        import numpy as np
        for _ in range(4):  # ico2 split in four, four times: 81,920 faces
            e = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
            u, inverse = np.unique(e, axis=0, return_inverse=True)
            mid = len(v) + np.arange(len(u))
            v = np.vstack([v, (v[u[:, 0]] + v[u[:, 1]]) / 2])
            ab, bc, ca = mid[inverse.reshape(3, -1)]
            a, b, c = f.T
            f = np.vstack([np.stack(t, axis=1)
                           for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])
        t = threading.Thread(target=shellcontract.regions, args=(v, f), daemon=True)
        t.start()
        time.sleep(0.3)
    """)
    assert r.returncode == 0, (r.returncode, r.stderr[-2000:])
    assert r.stderr == "", r.stderr[-2000:]


@pytest.mark.parametrize("attempt", range(4))
def test_exit_with_a_suspended_frames_generator(mesh_dir, attempt):
    """Before: the generator's worker, blocked in its callback, woke during finalization: abort."""
    r = _exit_while_running(mesh_dir, """
        gen = shellcontract.frames(v, f, frames=1000000)
        for _ in range(1 + %d):
            next(gen)
    """ % attempt)
    assert r.returncode == 0, (r.returncode, r.stderr[-2000:])


def test_exit_while_a_callback_run_is_going(mesh_dir):
    """A callback that Python would run during the exit is not called: exit 0."""
    r = _exit_while_running(mesh_dir, """
        seen = []
        t = threading.Thread(target=lambda: shellcontract.contract(
            v, f, frames=1000000, callback=lambda *a: seen.append(a[0])), daemon=True)
        t.start()
        time.sleep(0.5)
    """)
    assert r.returncode == 0, (r.returncode, r.stderr[-2000:])


@pytest.mark.parametrize("call", ["check", "regions", "contract", "write_mesh"])
def test_exit_while_arrays_are_checked_in_a_daemon_thread(mesh_dir, call):
    """The check of a mesh given as arrays runs without the GIL: a daemon thread still in it when
    the interpreter finalized took the GIL back then, and the process aborted ("terminate called
    without an active exception", exit 134). The exit now waits for it as for a run. An object
    whose __del__ sleeps (GIL free) during finalization keeps the window open."""
    r = _exit_while_running(mesh_dir, """
        import os, tempfile
        import numpy as np
        folder = tempfile.TemporaryDirectory()  # removed at exit
        import types
        class SlowToGo:
            def __del__(self, _sleep=time.sleep):
                _sleep(1.0)
        slow = types.ModuleType("slow_to_go")  # a module's objects go during finalization
        slow.keep = SlowToGo()
        sys.modules["slow_to_go"] = slow
        n = 500  # a torus of 500,000 faces, and a duplicate of its first face last: refused
        u = np.arange(n) * 2 * np.pi / n  # after the whole check
        uu, vv = np.meshgrid(u, u, indexing="ij")
        ring = 1 + 0.4 * np.cos(vv)
        V = np.stack([ring * np.cos(uu), ring * np.sin(uu), 0.4 * np.sin(vv)], -1).reshape(-1, 3)
        i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
        a, b = i * n + j, (i + 1) %% n * n + j
        c, d = (i + 1) %% n * n + (j + 1) %% n, i * n + (j + 1) %% n
        F = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                            np.stack([a, c, d], -1).reshape(-1, 3)])
        F = np.vstack([F, F[:1]])
        calls = {"check": lambda: shellcontract.check(V, F),
                 "regions": lambda: shellcontract.regions(V, F),
                 "contract": lambda: shellcontract.contract(V, F, frames=1),
                 "write_mesh": lambda: shellcontract.write_mesh(
                     os.path.join(folder.name, "never.off"), V, F)}
        def work():
            try:
                calls["%s"]()
            except shellcontract.MeshError:
                pass
        threading.Thread(target=work, daemon=True).start()
        time.sleep(0.05)
    """ % call)
    assert r.returncode == 0, (r.returncode, r.stderr[-2000:])


def test_a_call_while_the_interpreter_finalizes_returns(mesh_dir):
    """A __del__ run as the interpreter finalizes may call the module: the finalizing thread
    holds the GIL and keeps it for the work. Before, the exit's guard parked that thread too
    (meant for other threads, which may not take the GIL back then): the process hung."""
    r = _exit_while_running(mesh_dir, """
        import types
        class Report:
            def __del__(self):
                print("genus", shellcontract.check(v, f)["genus"],
                      "frames", len(shellcontract.contract(v, f, frames=2).log["frame"]), flush=True)
        late = types.ModuleType("late_report")  # a module's objects go during finalization
        late.keep = Report()
        sys.modules["late_report"] = late
    """)
    assert r.returncode == 0, (r.returncode, r.stderr[-2000:])
    assert "genus 0 frames" in r.stdout, (r.stdout, r.stderr[-2000:])


def test_a_path_with_nul_is_a_value_error(tmp_path, ico2):
    """Before: write_mesh('a.off\\x00/../b.off') reported success and overwrote a.off."""
    a = tmp_path / "a.off"
    a.write_text("keep")
    with pytest.raises(ValueError):
        shellcontract.write_mesh(str(a) + "\x00/../b.off", *ico2)
    assert a.read_text() == "keep"
    with pytest.raises(ValueError):
        shellcontract.read_mesh(str(a) + "\x00x.off")


def test_read_mesh_none_is_a_type_error(tmp_path, monkeypatch):
    """Before: str(None) opened a file named "None"."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(TypeError):
        shellcontract.read_mesh(None)
    with pytest.raises(TypeError):
        shellcontract.write_mesh(None, np.zeros((4, 3)), np.zeros((4, 3), dtype=np.int64))
    assert not os.path.exists(tmp_path / "None")


def test_write_mesh_never_replaces_a_fifo(tmp_path, ico2):
    """Before: the rename replaced the FIFO by a regular file."""
    fifo = tmp_path / "out.off"
    os.mkfifo(fifo)
    with pytest.raises(ValueError):
        shellcontract.write_mesh(fifo, *ico2)
    assert os.path.exists(fifo) and not os.path.isfile(fifo)


# A number's text ("0.5") and a whole float for min_faces are taken, as contract() takes them,
# and 1.5 is a ValueError there (test_option_types.py).
@pytest.mark.parametrize("option,value", [("min_faces", [1]), ("min_faces", True),
                                          ("contrast", b"0.5"), ("min_area_fraction", None),
                                          ("contrast_is_unknown", 1.0), ("method", 1), ("method", None),
                                          ("method", b"tips")])
def test_regions_wrong_types_are_type_errors(ico2, option, value):
    """Before: a string for a float option raised RuntimeError (pybind11's cast_error)."""
    with pytest.raises(TypeError):
        shellcontract.regions(*ico2, **{option: value})


@pytest.mark.parametrize("option,value", [("contrast", float("nan")),
                                          ("fit_tolerance", float("inf")),
                                          ("min_area_fraction", -0.1), ("min_faces", -1)])
def test_regions_out_of_range_values_are_value_errors(ico2, option, value):
    """Before: NaN thresholds were accepted (and selected nothing, silently)."""
    with pytest.raises(ValueError):
        shellcontract.regions(*ico2, **{option: value})


@pytest.mark.parametrize("value", ["blobs", "Tips", "", "caps "])
def test_regions_unknown_method_is_a_value_error_naming_the_methods(ico2, value):
    with pytest.raises(ValueError, match="expected 'caps', 'tips' or 'parts'"):
        shellcontract.regions(*ico2, method=value)


def test_regions_region_at_with_method_tips_is_a_value_error(ico2):
    with pytest.raises(ValueError, match="region_at"):
        shellcontract.regions(*ico2, method="tips", region_at=[(0.0, 0.0, 1.0)])


@pytest.mark.parametrize("option", ["fit_tolerance", "min_cap_angle", "contrast"])
def test_regions_cap_shape_options_with_method_tips_are_a_value_error(ico2, option):
    """Before: taken and ignored (the same regions as without them)."""
    with pytest.raises(ValueError, match=option + " shapes the cap finder's caps"):
        shellcontract.regions(*ico2, method="tips", **{option: 5})
    shellcontract.regions(*ico2, **{option: 5})  # the cap finder takes it


def test_a_uint64_index_is_reported_as_given(ico2):
    """Before: 2**64 - 1 was converted to int64 first and reported as -1."""
    vertices, faces = ico2
    bad = faces.astype(np.uint64)
    bad[5, 1] = np.uint64(2**64 - 1)
    with pytest.raises(ValueError, match="18446744073709551615"):
        shellcontract.check(vertices, bad)
    # With the valid range, as the library says it for any other index type (before: without).
    with pytest.raises(ValueError, match=r"has 162 vertices \(0\.\.161\)"):
        shellcontract.check(vertices, bad)


@pytest.mark.parametrize("every", [1.5, "2", None, True])
def test_frames_every_of_a_wrong_type_is_a_type_error(ico2, every):
    """Before: every=1.5 was accepted (frame % 1.5), every=True counted as 1."""
    with pytest.raises(TypeError):
        next(shellcontract.frames(*ico2, every=every, frames=3))
