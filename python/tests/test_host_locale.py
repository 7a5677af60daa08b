"""The module reads and writes the same whatever locale its host program set, and takes every
file name Python's open() takes.

A program that calls setlocale(LC_ALL, "") on a decimal-comma desktop (PyQt and GTK front ends
do it themselves) puts the C library's LC_NUMERIC in the module's process: std::strtod then
stopped at the '.' of "0.5", so ASCII PLY input, write_mesh(like=) of a PLY or OBJ, face-list
strengths (region_strengths= too: the module writes that file itself) and weight files were
refused, resume= read the checkpoint's log as zeros without a word, and messages said "0,5000".
The CI and build machines have only C and C.UTF-8 installed, so the locale is built with
localedef (glibc's libc-bin) from a definition and a character map written here; a child
process sets it (LOCPATH) and does everything twice, in the "C" locale and in that one.
Checked to fail on the code before core/decimal_text.hpp's parsers (every case but the OFF and
the comma files differed) and before path_argument's os.fsencode (pybind11's "Unable to cast").
"""
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import shellcontract

CHILD = r'''
import json, locale, os, sys
import numpy as np
import shellcontract as sc

work = sys.argv[1]
v, f = sc.read_mesh(os.path.join(work, "m.off"))


def attempt(fn):
    try:
        return fn()
    except Exception as e:  # the comparison shows which case failed, and how
        return {"error": "%s: %s" % (type(e).__name__, e)}


def log_of(r, *columns):
    return {c: r.log[c].tolist() for c in columns}


def cases(tag):
    out = {}
    out["ply"] = attempt(lambda: sc.read_mesh(os.path.join(work, "m.ply"))[0].tolist())
    for ext in ("ply", "obj"):
        def like(ext=ext):
            target = os.path.join(work, "like_%s.%s" % (tag, ext))
            sc.write_mesh(target, v * 0.5, f, like=os.path.join(work, "m." + ext))
            with open(target) as fh:
                return fh.read()
        out["like_" + ext] = attempt(like)
    out["strength_file"] = attempt(lambda: log_of(
        sc.contract(v, f, frames=2, regions=os.path.join(work, "faces.txt")), "volume_ratio"))
    out["strength_arrays"] = attempt(lambda: log_of(
        sc.contract(v, f, frames=2, regions=[[0, 1, 2, 3]], region_strengths=[0.5]), "volume_ratio"))
    out["weights"] = attempt(lambda: log_of(sc.contract(
        v, f, frames=2, region_weights=os.path.join(work, "w.txt")),
        "volume_ratio"))
    columns = ("frame", "time", "volume_ratio", "energy_membrane", "candidates")

    def resumed():
        ck = os.path.join(work, "ck_%s.ckpt" % tag)
        sc.contract(v, f, frames=6, checkpoint=ck, checkpoint_every=3)
        return log_of(sc.contract(v, f, frames=6, resume=ck), *columns)
    out["resumed"] = attempt(resumed)
    out["uninterrupted"] = attempt(lambda: log_of(sc.contract(v, f, frames=6), *columns))
    out["failure"] = attempt(
        lambda: sc.contract(v, f, frames=2, stop_volume_ratio=0.5).summary["failure"])
    # "1,0" is no number in the "C" locale (the CLI's): refused in both.
    out["comma_off"] = attempt(lambda: sc.read_mesh(os.path.join(work, "comma.off"))[0].tolist())
    return out


result = {"C": cases("C")}
locale.setlocale(locale.LC_NUMERIC, "xx_XX")  # LC_ALL too would make open() ask for its charmap
result["point"] = locale.localeconv()["decimal_point"]
result["comma"] = cases("comma")
print(json.dumps(result))
'''

COMMA_DEFINITION = ("LC_NUMERIC\ndecimal_point \"<U002C>\"\nthousands_sep \"<U002E>\"\n"
                    "grouping 3;3\nEND LC_NUMERIC\n")


def fail_or_skip(why):
    if os.environ.get("SHELLCONTRACT_STRICT_TESTS") == "1":
        pytest.fail("SHELLCONTRACT_STRICT_TESTS=1, where this test must run, but: " + why)
    pytest.skip(why)


@pytest.fixture(scope="module")
def comma_locpath(tmp_path_factory):
    """A folder holding the locale xx_XX, whose decimal point is ',' (for LOCPATH)."""
    localedef = shutil.which("localedef")
    if localedef is None:
        fail_or_skip("localedef (glibc's libc-bin) is not installed: no decimal-comma locale")
    d = tmp_path_factory.mktemp("locale")
    (d / "comma.def").write_text(COMMA_DEFINITION)
    charmap = ["<code_set_name> COMMA_TEST", "<comment_char> %", "<escape_char> /",
               "<mb_cur_min> 1", "<mb_cur_max> 1", "CHARMAP"]
    charmap += ["<U%04X> /x%02x" % (c, c) for c in range(128)] + ["END CHARMAP"]
    (d / "ascii.map").write_text("\n".join(charmap) + "\n")
    # -c: it warns that the other categories are missing (exit 1) and writes the locale anyway.
    made = subprocess.run([localedef, "-c", "-i", str(d / "comma.def"), "-f", str(d / "ascii.map"),
                           str(d / "xx_XX")], capture_output=True, text=True)
    if not (d / "xx_XX" / "LC_NUMERIC").exists():
        fail_or_skip("localedef made no locale: " + made.stderr[-500:])
    return d


def vertex_lines(v, prefix=""):
    return "".join(prefix + " ".join(repr(float(c)) for c in row) + "\n" for row in v)


def test_files_and_messages_are_the_same_under_a_decimal_comma_locale(comma_locpath, mesh_dir, tmp_path):
    v, f = shellcontract.read_mesh(mesh_dir / "ico1.off")
    shutil.copy(mesh_dir / "ico1.off", tmp_path / "m.off")
    (tmp_path / "m.ply").write_text(
        "ply\nformat ascii 1.0\nelement vertex %d\nproperty double x\nproperty double y\n"
        "property double z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
        % (len(v), len(f)) + vertex_lines(v) + "".join("3 %d %d %d\n" % tuple(t) for t in f))
    (tmp_path / "m.obj").write_text(
        vertex_lines(v, "v ") + "".join("f %d %d %d\n" % tuple(t + 1) for t in f))
    (tmp_path / "faces.txt").write_text("0.5: 0 1 2 3\n")
    (tmp_path / "w.txt").write_text("0.5\n" * len(v))
    (tmp_path / "comma.off").write_text(
        "OFF\n6 8 0\n1,0 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n3 0 2 4\n3 2 1 4\n"
        "3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n")
    env = dict(os.environ, LOCPATH=str(comma_locpath))
    child = subprocess.run([sys.executable, "-c", CHILD, str(tmp_path)], env=env,
                           capture_output=True, text=True, timeout=600)
    assert child.returncode == 0, child.stderr
    result = json.loads(child.stdout)
    assert result["point"] == ",", "the premise: the child's LC_NUMERIC has a decimal comma"
    c_locale, comma = result["C"], result["comma"]
    # The C locale's answers are the right ones (the CLI's): the files read, the log resumed.
    assert np.array_equal(np.array(c_locale["ply"]), v)
    assert c_locale["resumed"] == c_locale["uninterrupted"]
    assert "stop volume ratio 0.5000 not reached" in c_locale["failure"]
    assert c_locale["comma_off"]["error"].startswith("ValueError: ")
    assert "'1,0' is not a number" in c_locale["comma_off"]["error"]
    assert [case for case in c_locale if "error" in c_locale[case]] == ["comma_off"], c_locale
    differ = {case: comma[case] for case in c_locale if comma[case] != c_locale[case]}
    assert not differ


def test_a_file_name_that_is_not_utf8_works_as_with_open(mesh_dir, tmp_path):
    # os.listdir, glob and pathlib give such a name as a str with surrogate escapes (PEP 383);
    # open() takes it, and so does every function of the module that takes a path.
    def name(raw):
        return os.path.join(str(tmp_path), os.fsdecode(raw))

    src = name(b"lat\xe9.off")
    shutil.copy(mesh_dir / "ico1.off", src)
    assert os.fsdecode(b"lat\xe9.off") in os.listdir(tmp_path)
    v, f = shellcontract.read_mesh(src)
    out = name(b"out\xe9.off")
    shellcontract.write_mesh(out, v, f)
    assert np.array_equal(shellcontract.read_mesh(out)[0], v)
    obj = name(b"lat\xe9.obj")
    with open(obj, "w") as fh:
        fh.write(vertex_lines(v, "v ") + "".join("f %d %d %d\n" % tuple(t + 1) for t in f))
    shellcontract.write_mesh(name(b"out\xe9.obj"), v * 0.5, f, like=obj)
    assert np.array_equal(shellcontract.read_mesh(name(b"out\xe9.obj"))[0], v * 0.5)
    weights, faces = name(b"w\xe9.txt"), name(b"f\xe9.txt")
    with open(weights, "w") as fh:
        fh.write("0.5\n" * len(v))
    with open(faces, "w") as fh:
        fh.write("0 1 2 3\n")
    ck = name(b"ck\xe9.ckpt")
    shellcontract.contract(v, f, frames=2, regions=faces)
    # A message names such a file with \xNN for the byte (an empty ValueError before: the
    # message was decoded as strict UTF-8).
    bad = name(b"bad\xe9.off")
    with open(bad, "w") as fh:
        fh.write("OFF\n6 8 0\n0 0 x\n")
    with pytest.raises(ValueError, match=r"bad\\xe9\.off: parse error: .*'x' is not a number"):
        shellcontract.read_mesh(bad)
    full = shellcontract.contract(v, f, frames=4, region_weights=weights, checkpoint=ck,
                                  checkpoint_every=2)
    assert os.path.exists(ck)
    resumed = shellcontract.contract(v, f, frames=4, region_weights=weights, resume=ck)
    assert np.array_equal(resumed.vertices, full.vertices)
