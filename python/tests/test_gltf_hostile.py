"""read_mesh on a glTF whose JSON nests deeply (review7 F1): 20,000 nested arrays in an `extras`
raise a ValueError naming the file; before, the interpreter died of a stack overflow (SIGSEGV)
in the reader's recursive JSON parse. The call runs in a child interpreter, so that a crash fails
this test instead of ending the test session. 512 levels (the reader's limit) are read."""
import base64
import json
import struct
import subprocess
import sys

import pytest

import shellcontract as sc

POSITIONS = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
INDICES = [0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5]


def octahedron_gltf(path, extras):
    """A .gltf of the closed octahedron (buffer in a data URI); `extras`: the top-level extras'
    JSON text."""
    data = b"".join(struct.pack("<3f", *p) for p in POSITIONS) + struct.pack("<24I", *INDICES)
    doc = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode(),
                     "byteLength": len(data)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 72},
                        {"buffer": 0, "byteOffset": 72, "byteLength": 96}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3",
                       "min": [-1, -1, -1], "max": [1, 1, 1]},
                      {"bufferView": 1, "componentType": 5125, "count": 24, "type": "SCALAR"}],
        "extras": "EXTRAS"}
    path.write_text(json.dumps(doc).replace('"EXTRAS"', extras))
    return path


CHILD = """
import sys
import shellcontract as sc
try:
    sc.read_mesh(sys.argv[1])
except ValueError as e:
    print(type(e).__name__, e)
"""


@pytest.mark.parametrize("arrays", [512, 20000])
def test_a_json_nested_too_deeply_is_a_value_error_not_a_crash(tmp_path, arrays):
    gltf = octahedron_gltf(tmp_path / "deep.gltf", "[" * arrays + "]" * arrays)
    child = subprocess.run([sys.executable, "-c", CHILD, str(gltf)], capture_output=True,
                           text=True, timeout=120)
    assert child.returncode == 0, (child.returncode, child.stderr)
    assert child.stdout.startswith(
        "ValueError {}: JSON nested too deeply: the JSON nests deeper than 512 levels".format(gltf)
    ), child.stdout + child.stderr


def test_a_json_of_512_levels_is_read(tmp_path):
    gltf = octahedron_gltf(tmp_path / "d512.gltf", "[" * 511 + "]" * 511)
    vertices, faces = sc.read_mesh(gltf)
    assert len(vertices) == 6 and len(faces) == 8
