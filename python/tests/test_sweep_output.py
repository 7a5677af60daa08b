"""The sweep's output folder: refused with a message naming the path (exit 1, no traceback, nothing
written) when it is a file, when it holds files that no sweep wrote, or when it holds another sweep
file's results; the same sweep file, edited, goes on in its folder."""
import json

import pytest

from test_sweep import results, run_sweep, write_sweep

pytest.importorskip("distributed")

SPEC = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4}, "grid": {"pressure": [2, 3]}}


def refused(r, *texts):
    assert r.returncode == 1, r.stderr
    assert "Traceback" not in r.stderr, r.stderr
    for t in texts:
        assert t in r.stderr, r.stderr


@pytest.mark.parametrize("dry_run", [False, True], ids=["run", "dry-run"])
def test_a_file_as_the_output_folder_is_refused(cli, mesh_dir, tmp_path, dry_run):
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    afile = tmp_path / "afile"
    afile.write_text("mine\n")
    r = run_sweep(cli, [str(path), "-o", str(afile), "--shard", "0/1"] + ["--dry-run"] * dry_run)
    refused(r, str(afile), "not a folder")
    assert afile.read_text() == "mine\n"


@pytest.mark.parametrize("name,is_dir", [("results.csv", False), ("results.json", False),
                                         ("jobs", False), ("notes.txt", False), ("data", True)])
def test_a_folder_with_files_no_sweep_wrote_is_refused_and_left_alone(cli, mesh_dir, tmp_path,
                                                                     name, is_dir):
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    out = tmp_path / "out"
    out.mkdir()
    if is_dir:
        (out / name).mkdir()
    else:
        (out / name).write_text("the user's own\n")
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    refused(r, str(out), "holds files that no sweep wrote", name)
    assert sorted(p.name for p in out.iterdir()) == [name]
    if not is_dir:
        assert (out / name).read_text() == "the user's own\n"


def test_an_empty_folder_is_used(cli, mesh_dir, tmp_path):
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    (tmp_path / "out").mkdir()
    r = run_sweep(cli, [str(path), "-o", str(tmp_path / "out"), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    assert [row["status"] for row in results(tmp_path / "out")] == ["ok", "ok"]


def test_another_sweep_file_is_refused_and_the_same_file_edited_goes_on(cli, mesh_dir, tmp_path):
    first = write_sweep(tmp_path, mesh_dir, "first.json", SPEC, meshes=("ico1.off",))
    out = tmp_path / "out"
    r = run_sweep(cli, [str(first), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    table = (out / "results.csv").read_text()
    second = write_sweep(tmp_path, mesh_dir, "second.json", dict(SPEC, grid={"pressure": [5]}),
                         meshes=("ico1.off",))
    for extra in ([], ["--dry-run"]):
        r = run_sweep(cli, [str(second), "-o", str(out), "--shard", "0/1"] + extra)
        refused(r, str(out), "holds the results of another sweep file, {}".format(first))
    assert (out / "results.csv").read_text() == table  # the first file's rows, untouched
    # The first file edited (a grid value added): its finished jobs are kept, the new one runs.
    first.write_text(json.dumps(dict(SPEC, grid={"pressure": [2, 3, 5]})))
    r = run_sweep(cli, [str(first), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    assert "1 in this run, 2 done already" in r.stderr
    assert len(results(out)) == 3
    # The study moved (its sweep file renamed): the refusal says the recorded file is gone and
    # how to go on with the results; done so, the finished jobs are kept.
    moved = tmp_path / "moved.json"
    first.rename(moved)
    r = run_sweep(cli, [str(moved), "-o", str(out), "--shard", "0/1"])
    refused(r, "which no longer exists (moved or renamed?)",
            '"sweep_file" in ' + str(out / ".shellcontract-sweep.json"))
    marker = out / ".shellcontract-sweep.json"
    data = json.loads(marker.read_text())
    data["sweep_file"] = str(moved)
    marker.write_text(json.dumps(data))
    r = run_sweep(cli, [str(moved), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0 and "0 in this run, 3 done already" in r.stderr, r.stderr


def test_the_sweeps_own_entries_replaced_by_other_kinds_are_refused(cli, mesh_dir, tmp_path):
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    out = tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    for p in (out / "jobs").iterdir():
        for f in p.iterdir():
            f.unlink()
        p.rmdir()
    (out / "jobs").rmdir()
    (out / "jobs").write_text("not a folder\n")
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    refused(r, str(out / "jobs"), "expected the sweep's folder, found a file")


def test_shards_claiming_a_new_folder_at_once_all_get_it(mesh_dir, tmp_path):
    import threading
    from shellcontract import sweep_output
    path = write_sweep(tmp_path, mesh_dir, "s.json", SPEC, meshes=("ico1.off",))
    out = tmp_path / "out"
    errors = []
    start = threading.Barrier(8)

    def shard():
        start.wait()
        try:
            sweep_output.claim(str(out), str(path))
        except Exception as e:  # noqa: BLE001 - any error is the test's failure
            errors.append(e)

    threads = [threading.Thread(target=shard) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    assert json.loads((out / sweep_output.MARKER).read_text())["sweep_file"] == str(path.resolve())
