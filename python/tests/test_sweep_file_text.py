"""The sweep file as text: option names in either spelling, and JSON that no sweep can mean,
refused by name before anything runs."""
import os
import re

import pytest

from shellcontract import sweep_file
from test_sweep import write_sweep
from test_sweep_inputs import ICO2_VERTICES, jobs_of

pytest.importorskip("distributed")


def test_an_option_spelt_as_the_cli_spells_it_is_the_same_option(cli, mesh_dir, tmp_path):
    # Before: "target-volume" passed the check but was left off the job's command line, while
    # results.csv recorded it and the job id counted it (a rerun with the right name kept the
    # wrong result as done).
    spec = {"meshes": ["meshes/ico2.off"], "options": {"frames": 4},
            "runs": [{"target-volume": 0.5}]}
    dashed = jobs_of(cli, write_sweep(tmp_path, mesh_dir, "d.json", spec, meshes=("ico2.off",)))
    spec["runs"] = [{"target_volume": 0.5}]
    python = jobs_of(cli, write_sweep(tmp_path, mesh_dir, "p.json", spec, meshes=("ico2.off",)))
    assert "--target-volume" in dashed[0].args, dashed[0].args
    assert dashed[0].args == python[0].args and dashed[0].id == python[0].id
    assert dashed[0].options == {"frames": 4, "target_volume": 0.5}
    # A path option spelt so is still relative to the sweep file.
    (tmp_path / "w.txt").write_text("1\n" * ICO2_VERTICES)
    spec = {"meshes": ["meshes/ico2.off"], "options": {"region-weights": "w.txt"}}
    job = jobs_of(cli, write_sweep(tmp_path, mesh_dir, "w.json", spec, meshes=("ico2.off",)))[0]
    assert job.args[job.args.index("--region-weights") + 1] == str(tmp_path / "w.txt")


@pytest.mark.parametrize("table", ["options", "runs"])
def test_one_option_spelt_both_ways_is_refused(cli, mesh_dir, tmp_path, table):
    both = {"pressure": 1, "k-b": 0.02, "k_b": 0.03}
    spec = {"meshes": ["meshes/ico2.off"], table: both if table == "options" else [both]}
    path = write_sweep(tmp_path, mesh_dir, "b.json", spec, meshes=("ico2.off",))
    with pytest.raises(sweep_file.SweepError, match="option 'k_b' is given twice"):
        jobs_of(cli, path)


@pytest.mark.parametrize("text,message", [
    ('{"meshes": ["m.off"], "options": {"material": "\\ud800"}}', "is not text (a lone surrogate"),
    ('{"meshes": ["\\udc00.off"]}', "is not text (a lone surrogate"),
    ('{"meshes": ["m.off"], "options": {"fiber": ' + "[" * 5000 + "]" * 5000 + "}}",
     "the JSON nests too deeply"),
], ids=["option", "mesh", "deep"])
def test_json_that_no_sweep_can_mean_is_refused_by_name(tmp_path, text, message):
    # Before: a pybind11 cast error ("Unable to cast Python instance to C++ type") and a
    # RecursionError traceback.
    path = tmp_path / "s.json"
    path.write_text(text)
    with pytest.raises(sweep_file.SweepError, match=r"s\.json: .*" + re.escape(message)):
        sweep_file.load(str(path))


def test_a_sweep_file_that_is_not_a_regular_file_is_refused_without_reading(tmp_path):
    # Before: the sweep file was read with f.read(): /dev/zero grew until a MemoryError traceback
    # (or the kernel's OOM killer), and a FIFO waited for a writer for ever.
    fifo = tmp_path / "fifo.json"
    os.mkfifo(fifo)
    for path, why in ((str(fifo), "FIFO"), ("/dev/zero", "device"), (str(tmp_path), "folder")):
        with pytest.raises(sweep_file.SweepError) as e:
            sweep_file.load(path)
        assert str(e.value).startswith(path + ": cannot read the sweep file"), str(e.value)
        assert why in str(e.value), str(e.value)


def test_a_sweep_file_too_large_to_be_one_is_refused_by_its_size(tmp_path):
    # A sparse file: its size is known without reading it (before: read whole, 20 GB in memory).
    big = tmp_path / "big.json"
    with open(big, "wb") as f:
        f.truncate(sweep_file.MAX_SWEEP_FILE_BYTES + 1)
    with pytest.raises(sweep_file.SweepError, match="file too large for a sweep file"):
        sweep_file.load(str(big))
