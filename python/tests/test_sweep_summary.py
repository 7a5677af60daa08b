"""What a sweep job's summary.json says of its files: the tool records them as given, and the job
runs in its attempt folder, which becomes DIR/jobs/<id>/, so they are named in that folder (review
determinism F2: they were paths through the attempt folder, gone once the job had its outcome,
and two sweeps of one job wrote summaries differing in its random suffix)."""
import json

import pytest

from test_sweep import run_sweep, write_sweep

pytest.importorskip("distributed")


def test_a_jobs_summary_names_its_files_in_the_jobs_folder(cli, mesh_dir, tmp_path):
    spec = {"meshes": ["meshes/ico1.off"], "options": {"frames": 4}}
    path = write_sweep(tmp_path, mesh_dir, "s.json", spec, meshes=("ico1.off",))
    summaries = []
    for out in (tmp_path / "a", tmp_path / "b"):
        r = run_sweep(cli, [str(path), "-o", str(out), "--shard", "0/1"])
        assert r.returncode == 0, r.stderr
        (job,) = list((out / "jobs").iterdir())
        summary = json.loads((job / "summary.json").read_text())
        assert summary["output"] == "ico1.off", summary["output"]
        assert (job / summary["output"]).is_file()
        summaries.append((job / "summary.json").read_text())
    # Two sweeps of the same job: the same summary but for the run's own timings.
    a, b = (json.loads(s) for s in summaries)
    assert {k: v for k, v in a.items() if k in ("input", "output", "log")} == \
        {k: v for k, v in b.items() if k in ("input", "output", "log")}
