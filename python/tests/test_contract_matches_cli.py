"""The Python module and the CLI are two front ends of one run: the same input and options must
give the same output file, byte for byte, and the same per-frame log."""
import csv
import filecmp
import subprocess

import numpy as np
import pytest

import shellcontract

# (mesh, Python options, the CLI's spelling of the same options). Floats with many digits check
# that the value reaches the library as the same double; the inside-out sphere checks that both
# flip it the same way.
CASES = [
    ("bumpy_sphere.off", dict(frames=25, pressure=2.7182818284590451, k_b=0.015, target_volume=0.8,
                              target_ramp=10),
     ["--frames", "25", "-p", "2.718281828459045", "--k-b", "0.015", "--target-volume", "0.8",
      "--target-ramp", "10"]),
    ("inside_out_sphere.off", dict(frames=15, damping=0.1, collisions=False),
     ["--frames", "15", "--damping", "0.1", "--collisions", "off"]),
]


@pytest.mark.parametrize("mesh,options,cli_args", CASES, ids=[c[0] for c in CASES])
def test_result_file_equals_cli_output(cli, mesh_dir, tmp_path, mesh, options, cli_args):
    source = mesh_dir / mesh
    cli_out, cli_log = tmp_path / "cli.off", tmp_path / "cli.csv"
    subprocess.run([cli, "run", str(source), "-o", str(cli_out), "--log", str(cli_log), "-q"] + cli_args,
                   check=True)

    vertices, faces = shellcontract.read_mesh(source)
    result = shellcontract.contract(vertices, faces, **options)
    py_out = tmp_path / "python.off"
    shellcontract.write_mesh(py_out, result.vertices, result.faces)

    assert result.status == "ok"
    assert filecmp.cmp(cli_out, py_out, shallow=False), "Python's result differs from the CLI's"
    # The result moved: equal files of an unchanged mesh would prove nothing.
    assert not np.array_equal(result.vertices, vertices)

    with open(cli_log) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == options["frames"] == len(result.log["frame"])
    for column in ("frame", "time", "volume_ratio", "energy_membrane", "energy_bending",
                   "max_displacement", "contacts", "new_intersections"):
        expected = np.array([float(r[column]) for r in rows])
        np.testing.assert_array_equal(result.log[column], expected, err_msg=column)


def test_summary_keys_and_target_reached_match_the_cli(cli, mesh_dir, tmp_path):
    """summary["target_reached"] is None (JSON null) when nothing was to be reached (it was True,
    also for a failed run), and every key the CLI's summary has beyond Python's is named in
    Result's docstring (it named neither "outputs", "export" nor "repair")."""
    import json
    source = mesh_dir / "ico2.off"
    vertices, faces = shellcontract.read_mesh(source)
    for i, (options, cli_args, expected) in enumerate([
            (dict(frames=3), ["--frames", "3"], None),
            (dict(frames=40, target_volume=0.9, target_ramp=10),
             ["--frames", "40", "--target-volume", "0.9", "--target-ramp", "10"], True)]):
        run_dir = tmp_path / str(i)
        run_dir.mkdir()
        summary = run_dir / "s.json"
        subprocess.run([cli, "run", str(source), "-o", str(run_dir / "o.off"), "--summary",
                        str(summary), "--export-dir", str(run_dir), "--export-every", "100",
                        "--repair", "-q"] + cli_args, check=True)
        with open(summary) as f:
            from_cli = json.load(f)
        result = shellcontract.contract(vertices, faces, **options)
        assert from_cli["target_reached"] is expected
        assert result.summary["target_reached"] is expected
        only_cli = set(from_cli) - set(result.summary)
        assert {"outputs", "export", "repair"} <= only_cli
        for key in only_cli:
            assert '"{}"'.format(key) in shellcontract.Result.__doc__, key
