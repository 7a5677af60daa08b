"""What the sweep reports: the progress counts jobs finished in an earlier sweep as the final
summary does (a failure stays a failure), and the results table writes numbers as the tool does
(std::to_chars: 1e6 is 1e+06, as in the tool's resolved options), not as Python's repr."""
import csv
import subprocess

import pytest

from shellcontract import sweep_file, sweep_results
from test_sweep import run_sweep, write_sweep

pytest.importorskip("distributed")


def test_progress_counts_an_earlier_failure_as_failed(cli, mesh_dir, tmp_path):
    # A regions file naming a face ico1 does not have: the run refuses it (exit 2, 'bad input'),
    # a final outcome that the next sweep does not run again.
    (tmp_path / "bad_regions.txt").write_text("0 1 99999\n")
    spec = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4},
            "runs": [{"regions": "bad_regions.txt"}]}
    path = write_sweep(tmp_path, mesh_dir, "s.json", spec, meshes=("ico1.off",))
    out = tmp_path / "out"
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    assert "0 done, 1 failed, 0 left" in r.stderr, r.stderr
    # One more run in the file: the progress line after it counts the earlier failure as failed.
    spec["runs"].append({"pressure": 2})
    path.write_text(__import__("json").dumps(spec))
    r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
    assert r.returncode == 0, r.stderr
    assert "1 in this run, 1 done already" in r.stderr
    progress = [line for line in r.stderr.splitlines() if line.startswith("job 1 ")]
    assert progress and progress[0].endswith("-- 1 done, 1 failed, 0 left"), r.stderr
    assert "shellcontract sweep: 1 done, 1 failed, 0 left" in r.stderr


def written_table(cli, mesh_dir, tmp_path, spec):
    """The jobs of `spec` (a sweep file on ico1) and the rows of the results.csv written for them,
    with no job run."""
    path = write_sweep(tmp_path, mesh_dir, "s.json", spec, meshes=("ico1.off",))
    data = sweep_file.load(str(path))
    version = subprocess.run([cli, "--version"], capture_output=True, text=True).stdout.strip()
    jobs = sweep_file.expand(str(path), data, version)
    out = tmp_path / "out"
    sweep_results.write(jobs, sweep_file.varying_names(data), str(out), str(tmp_path))
    with open(out / "results.csv") as f:
        return jobs, list(csv.DictReader(f))


def test_numbers_in_the_table_read_as_the_tools_own(cli, mesh_dir, tmp_path):
    spec = {"meshes": ["meshes/ico1.off"],
            "grid": {"pressure": [1e6, 250000.0, 0.0001, 0.001, 0.5, 2, 3.0]}}
    jobs, table = written_table(cli, mesh_dir, tmp_path, spec)
    cells = [row["pressure"] for row in table]
    assert cells == ["1e+06", "250000", "1e-04", "0.001", "0.5", "2", "3"]
    # Each the library's own text of the value (its resolved options, its --summary).
    assert cells == [job.resolved["pressure"] for job in jobs]


def test_an_integer_in_the_file_reads_as_the_same_number_given_as_a_float(cli, mesh_dir,
                                                                            tmp_path):
    # JSON 1000000 beside 1e6: one number, one text (the tool's), in every column type.
    spec = {"meshes": ["meshes/ico1.off"],
            "grid": {"pressure": [1000000, 0.5], "frames": [10, 12]},
            "runs": [{"target_volume": [[0, 1], [60, 0.5]]}, {"air_balance": 0}]}
    _, table = written_table(cli, mesh_dir, tmp_path, spec)
    assert [row["pressure"] for row in table] == ["1e+06"] * 4 + ["0.5"] * 4
    assert [row["frames"] for row in table] == ["10", "10", "12", "12"] * 2
    assert [row["target_volume"] for row in table] == ["0:1, 60:0.5", ""] * 4
    assert [row["air_balance"] for row in table] == ["", "0"] * 4


def test_a_result_not_there_is_null_in_json_and_empty_in_csv(cli, mesh_dir, tmp_path):
    # Before: "" in results.json, a string in a column of numbers, where job.json has null.
    spec = {"meshes": ["meshes/ico1.off"], "grid": {"pressure": [1, 2]}}
    _, table = written_table(cli, mesh_dir, tmp_path, spec)
    rows = __import__("json").loads((tmp_path / "out" / "results.json").read_text())
    for csv_row, json_row in zip(table, rows):
        assert json_row["status"] == csv_row["status"] == "pending"
        for k in sweep_results.RESULT_COLUMNS:
            if k != "status":
                assert json_row[k] is None and csv_row[k] == "", (k, json_row, csv_row)


@pytest.mark.parametrize("value,text", [
    (1e6, "1e+06"), (1e5, "1e+05"), (123456.0, "123456"), (1e-5, "1e-05"), (0.003, "0.003"),
    (-2.5, "-2.5"), (0.1 + 0.2, "0.30000000000000004"), (2.0 ** 70, "1180591620717411303424"),
    (1e22, "1e+22"), (float("inf"), "inf"), (float("nan"), "nan"), (-0.0, "-0")])
def test_shortest_text_is_std_to_chars(value, text):
    assert sweep_results.shortest_text(value) == text
