"""What the sweep writes or removes in its folder goes through the output rule every command's
outputs follow (docs/design/output-safety.md): an input, a folder, a FIFO, a link or a
write-protected file in the place of a file the sweep replaces, and an input in a folder it
replaces or removes, are refused before any job runs (exit 1, the message naming the path), and
the user's file is left as it was. Before, the tables were renamed over whatever was there: the
sweep file kept in the results folder as results.json, a FIFO, a mesh's hard link."""
import json
import os
import shutil
import stat
import tempfile

import pytest

from test_sweep import results, run_sweep, write_sweep
from test_sweep_output import refused

pytest.importorskip("distributed")

SPEC = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4}, "grid": {"pressure": [2, 3]}}


def finished_sweep(cli, mesh_dir, tmp_path):
    """A sweep run to its end, then one of its two jobs' folder removed: the next sweep of the
    file would run that job again. (the sweep file, DIR, the removed job's id)"""
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    out = tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    job = results(out)[1]["job"]
    shutil.rmtree(out / "jobs" / job)
    return path, out, job


def assert_refused_before_any_job(cli, path, out, job, *texts):
    for dry_run in ([], ["--dry-run"]):
        r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"] + dry_run)
        refused(r, "refused, nothing run", *texts)
    assert not (out / "jobs" / job / "job.json").exists(), "the job ran"
    assert [p.name for p in (out / ".work").iterdir()] == ["checkpoints"]


def user_file(tmp_path, name="mine.txt"):
    p = tmp_path / "elsewhere" / name
    p.parent.mkdir(exist_ok=True)
    p.write_text("the user's own\n")
    return p


@pytest.mark.parametrize("table", ["results.csv", "results.json"])
@pytest.mark.parametrize("what", ["folder", "fifo", "link to a file", "link to nothing",
                                  "write-protected"])
def test_a_table_in_the_place_of_what_is_not_the_sweeps_file_is_refused(cli, mesh_dir, tmp_path,
                                                                        table, what):
    path, out, job = finished_sweep(cli, mesh_dir, tmp_path)
    p = out / table
    p.unlink()
    mine = user_file(tmp_path)
    if what == "folder":
        p.mkdir()
        (p / "inside.txt").write_text("the user's own\n")
        expected = "found a folder"
    elif what == "fifo":  # a device's stand-in: open() would take it, a rename would drop it
        os.mkfifo(p)
        expected = "found a device, FIFO or socket"
    elif what == "link to a file":
        p.symlink_to(mine)
        expected = "found a link"
    elif what == "link to nothing":
        p.symlink_to(tmp_path / "elsewhere" / "none.txt")
        expected = "found a link"
    else:
        p.write_text("the user's own\n")
        p.chmod(0o444)
        expected = "it is write-protected"
    before = os.lstat(p)
    assert_refused_before_any_job(cli, path, out, job, str(p), expected)
    after = os.lstat(p)
    assert after.st_ino == before.st_ino
    assert stat.S_IFMT(after.st_mode) == stat.S_IFMT(before.st_mode)
    assert mine.read_text() == "the user's own\n"
    if what == "folder":
        assert [x.name for x in p.iterdir()] == ["inside.txt"]


@pytest.mark.parametrize("how", ["the sweep file itself", "a hard link of the sweep file",
                                 "a hard link of a mesh"])
def test_a_table_that_is_an_input_is_refused(cli, mesh_dir, tmp_path, how):
    path, out, job = finished_sweep(cli, mesh_dir, tmp_path)
    text = path.read_text()
    if how == "the sweep file itself":
        # The study's file kept in its results folder under a table's name, the marker set to
        # it as a moved study's is (docs/design/sweeps.md, "Results").
        (out / "results.json").unlink()
        shutil.copytree(tmp_path / "meshes", out / "meshes")
        path.rename(out / "results.json")
        path = out / "results.json"
        marker = out / ".shellcontract-sweep.json"
        marker.write_text(json.dumps(dict(json.loads(marker.read_text()),
                                          sweep_file=str(path))))
        table, kept, expected = path, path, "is the sweep's input the sweep file"
    elif how == "a hard link of the sweep file":
        # The message names the link as what is in the way, not the input (which is elsewhere).
        table, kept = out / "results.csv", path
        expected = "is another name (a hard link) of the sweep's input the sweep file"
        table.unlink()
        os.link(path, table)
    else:
        kept = tmp_path / "meshes" / "ico1.off"
        text = kept.read_text()
        table, expected = out / "results.json", "is another name (a hard link) of the sweep's input mesh"
        table.unlink()
        os.link(kept, table)
    assert_refused_before_any_job(cli, path, out, job, str(table), expected)
    assert kept.read_text() == text and os.path.samefile(table, kept)


def test_an_input_in_a_folder_the_sweep_replaces_or_removes_is_refused(cli, mesh_dir, tmp_path):
    path, out, job = finished_sweep(cli, mesh_dir, tmp_path)
    # A mesh in DIR/.work, whose attempts' folders a sweep removes.
    inside = out / ".work" / "m"
    inside.mkdir()
    shutil.copy(mesh_dir / "octahedron.off", inside / "o.off")
    spec = dict(SPEC, meshes=["meshes/ico1.off", str(inside / "o.off")])
    path.write_text(json.dumps(spec))
    for dry_run in ([], ["--dry-run"]):
        r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"] + dry_run)
        refused(r, "mesh {} is in {}, which the sweep replaces or removes".format(
            inside / "o.off", out / ".work"))
    assert (inside / "o.off").read_bytes() == (mesh_dir / "octahedron.off").read_bytes()
    assert not (out / "jobs" / job).exists()
    shutil.rmtree(inside)
    # A regions file in the folder of a job that crashed: the job runs again, and its folder is
    # replaced.
    path.write_text(json.dumps(SPEC))
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    record = out / "jobs" / job / "job.json"
    record.write_text(json.dumps(dict(json.loads(record.read_text()), status="crashed")))
    faces = out / "jobs" / job / "faces.txt"
    faces.write_text("0 1 2\n")
    spec = dict(SPEC, runs=[{}, {"regions": str(faces)}])
    path.write_text(json.dumps(spec))
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    refused(r, "regions {} is in {}, which the sweep replaces or removes".format(
        faces, out / "jobs" / job))
    assert faces.read_text() == "0 1 2\n"
    # A finished job's folder is never replaced: a file in it may be an input.
    record.write_text(json.dumps(dict(json.loads(record.read_text()), status="ok")))
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1", "--dry-run"])
    assert r.returncode == 0, r.stderr


@pytest.mark.parametrize("what", ["link to a file", "fifo", "folder"])
def test_a_jobs_checkpoint_or_folder_that_is_not_the_sweeps_is_refused(cli, mesh_dir, tmp_path,
                                                                      what):
    path, out, job = finished_sweep(cli, mesh_dir, tmp_path)
    mine = user_file(tmp_path)
    for p in (out / ".work" / "checkpoints" / (job + ".ckpt"), out / "jobs" / job):
        if what == "link to a file":
            p.symlink_to(mine)
        elif what == "fifo":
            os.mkfifo(p)
        elif p.parent.name == "checkpoints":
            p.mkdir()
        else:
            continue  # a job's folder is a folder
        assert_refused_before_any_job(
            cli, path, out, job, str(p), "found a " + ("link" if what.startswith("link") else
                                                     "device, FIFO or socket" if what == "fifo"
                                                     else "folder"))
        assert mine.read_text() == "the user's own\n"
        if p.is_dir():
            p.rmdir()
        else:
            p.unlink()


def as_user(uid, fn):
    """fn() in a child process running as `uid` (root only): what it returned or raised, as text."""
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:  # pragma: no cover (the child)
        os.close(r)
        try:
            os.setgroups([])
            os.setresgid(uid, uid, uid)
            os.setresuid(uid, uid, uid)
            text = "returned {!r}".format(fn())
        except BaseException as e:  # noqa: B902 (reported to the parent)
            text = "{}: {}".format(type(e).__name__, e)
        os.write(w, text.encode())
        os._exit(0)
    os.close(w)
    with os.fdopen(r) as f:
        text = f.read()
    os.waitpid(pid, 0)
    return text


@pytest.mark.skipif(os.geteuid() != 0, reason="needs root: a file of another user in a sticky "
                    "folder, checked by a process of a third user")
@pytest.mark.parametrize("what", ["a table", "a job's folder"])
def test_another_users_file_in_a_sticky_folder_is_refused_before_any_job(tmp_path, what):
    """The kernel lets only the file's owner, the folder's owner or root rename over a file in a
    sticky folder (like /tmp): the library refuses such an output before work
    (output_target.cpp, sticky_problem), and so does the sweep, for a table it would replace and
    a job's folder it would move away; the owner of the folder may."""
    from shellcontract import sweep_output
    nobody, other = 65534, 1
    sweep = tmp_path / "s.json"
    sweep.write_text("{}")
    tmp_path.chmod(0o755)
    out = tempfile.mkdtemp(dir="/tmp")  # pytest's own folders are the caller's only (0700)
    try:
        os.chmod(out, 0o1777)
        job = "0123456789abcdef"
        with open(os.path.join(out, sweep_output.MARKER), "w") as f:
            json.dump({"sweep_file": str(sweep)}, f)
        for name in ("jobs", ".work"):
            os.mkdir(os.path.join(out, name), 0o1777)
            os.chmod(os.path.join(out, name), 0o1777)
        if what == "a table":
            theirs = os.path.join(out, "results.csv")
            with open(theirs, "w") as f:
                f.write("job,status\n")
            os.chmod(theirs, 0o666)  # writable by all: refused for its owner, not its mode
            os.chown(theirs, other, other)
        else:
            theirs = os.path.join(out, "jobs", job)
            os.mkdir(theirs)
            with open(os.path.join(theirs, "job.json"), "w") as f:
                json.dump({"status": "crashed"}, f)  # not final: the job runs again
            os.chmod(theirs, 0o777)
            os.chown(theirs, other, other)
        check = lambda: sweep_output.check(out, str(sweep), [("the sweep file", str(sweep))],
                                           [job])
        # The kernel's rule, which the check foresees: the sweep's rename is refused.
        spare = os.path.join(out, "spare")
        rename = ((lambda: (open(spare, "w").close(), os.replace(spare, theirs))) if what ==
                  "a table" else lambda: os.rename(theirs, theirs + ".old"))
        assert as_user(nobody, rename).startswith("PermissionError"), "no sticky rule here?"
        got = as_user(nobody, check)
        assert got.startswith("OutputError: {}: exists and cannot be replaced: it belongs to "
                              "another user (uid {}) and its folder is sticky".format(theirs,
                                                                                      other)), got
        # Root may (CAP_FOWNER), and so may the folder's owner.
        assert check() is None
        os.chown(os.path.dirname(theirs), nobody, nobody)
        assert as_user(nobody, check) == "returned None"
    finally:
        shutil.rmtree(out)
