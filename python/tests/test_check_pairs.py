"""check()'s self-intersecting pairs on a mesh whose parts all pass through each other (review
complexity F7): the pairs number the square of the faces, and check() returned them all. Now it
counts them all and returns the first 1000 in face order, as `check --json` lists them."""
import json
import subprocess

import numpy as np

import shellcontract


def crossing_needles(count, width=0.05):
    """tests/support/crossing_needles.hpp's mesh: thin tetrahedra through the origin."""
    golden = np.pi * (3.0 - np.sqrt(5.0))
    vertices, faces = [], []
    for n in range(count):
        z = 1.0 - (n + 0.5) / count
        r = np.sqrt(1.0 - z * z)
        d = np.array([r * np.cos(golden * n), r * np.sin(golden * n), z])
        u = np.cross(d, [1.0, 0, 0] if abs(d[0]) < 0.9 else [0, 1.0, 0])
        u /= np.linalg.norm(u)
        v = np.cross(d, u)
        vertices += [-d, d + width * u, d + width * (-0.5 * u + 0.87 * v), d + width * (-0.5 * u - 0.87 * v)]
        o = 4 * n
        faces += [[o, o + 2, o + 1], [o, o + 3, o + 2], [o, o + 1, o + 3], [o + 1, o + 2, o + 3]]
    return np.array(vertices), np.array(faces)


def test_check_counts_all_pairs_and_returns_the_first_thousand(cli, tmp_path):
    vertices, faces = crossing_needles(40)
    report = shellcontract.check(vertices, faces)
    count = report["self_intersecting_pairs"]
    pairs = report["self_intersections"]
    assert count > 2000
    assert pairs.shape == (1000, 2)
    assert report["self_intersections_truncated"] is True
    assert (pairs[:, 0] < pairs[:, 1]).all()
    assert [tuple(p) for p in pairs] == sorted(tuple(p) for p in pairs)
    # The same pairs and count as the CLI's report of the same mesh.
    path = tmp_path / "needles.off"
    shellcontract.write_mesh(path, vertices, faces)
    cli_report = json.loads(subprocess.run([cli, "check", str(path), "--json"], check=True,
                                           capture_output=True, text=True).stdout)
    assert cli_report["self_intersecting_pairs"] == count
    assert cli_report["self_intersections"] == pairs.tolist()
    assert cli_report["self_intersections_truncated"] is True


def test_check_of_a_mesh_without_pairs_says_nothing_is_left_out(ico2):
    report = shellcontract.check(*ico2)
    assert report["self_intersecting_pairs"] == 0
    assert report["self_intersections"].shape == (0, 2)
    assert report["self_intersections_truncated"] is False
