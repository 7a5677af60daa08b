"""scripts/view.py refuses what the viewer cannot show, at once and with the reason, instead of
serving a page that fails in the browser's console or ending in a traceback.

Run by CTest (view_refusals): python3 -m pytest viewer/tests/view_refusals_test.py."""
import json
import os
import socket
import subprocess
import sys

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
VIEW = os.path.join(REPO, "scripts", "view.py")
MESH = os.path.join(REPO, "meshes", "ico2.off")


def view(*args):
    """view.py's exit code and stderr; a server that starts is stopped by the timeout (a failure)."""
    try:
        r = subprocess.run([sys.executable, VIEW, *args], capture_output=True, text=True, timeout=20)
    except subprocess.TimeoutExpired:
        pytest.fail("view.py started serving: " + " ".join(args))
    return r.returncode, r.stderr


def test_a_folder_is_named_as_a_folder(tmp_path):
    code, err = view(str(tmp_path))
    assert code == 1 and "it is a folder" in err, err


def test_a_file_the_viewer_cannot_read_is_refused(tmp_path):
    notes = tmp_path / "notes.txt"
    notes.write_text("not a mesh\n")
    code, err = view(str(notes))
    assert code == 1 and "not a .glb, a .gltf or a mesh" in err, err
    code, err = view(MESH, "--log", str(notes))
    assert code == 1 and "not a --log CSV or a --summary JSON" in err, err


@pytest.mark.parametrize("port", ["-5", "65536", "x"])
def test_a_port_out_of_range_is_a_usage_error(port):
    code, err = view(MESH, "--port", port)
    assert code == 2 and "is not a port number" in err and "Traceback" not in err, err


def test_a_port_in_use_says_so():
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        code, err = view(MESH, "--port", str(taken.getsockname()[1]))
    assert code == 1 and "cannot serve" in err and "--port 0" in err and "Traceback" not in err, err


def test_a_glb_that_is_not_a_binary_gltf_is_refused(tmp_path):
    # Before: served, and the page failed in the browser's console.
    fake = tmp_path / "fake.glb"
    fake.write_bytes(b"OFF\n3 1 0\n")
    code, err = view(str(fake))
    assert code == 1 and "not a binary glTF" in err, err


def gltf_text(buffer_uri):
    """A .gltf of one triangle whose buffer is `buffer_uri` (its bytes are not read here)."""
    return json.dumps({
        "asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "buffers": [{"byteLength": 36, "uri": buffer_uri}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}]})


def test_a_gltf_is_served_and_one_with_a_buffer_file_is_refused(tmp_path):
    # Before: every .gltf was refused ("not a .glb or a mesh"), though run writes one for a .gltf
    # input and repair on request. The page reads the .gltf alone: a buffer in a file of its own
    # would fail in the browser's console, so it is refused here, naming the buffer.
    external = tmp_path / "external.gltf"
    external.write_text(gltf_text("external.bin"))
    code, err = view(str(external))
    assert code == 1 and "buffer 0 is the file 'external.bin'" in err, err
    cut = tmp_path / "cut.gltf"
    cut.write_text(gltf_text("data:application/octet-stream;base64,AAAA")[:-1])
    code, err = view(str(cut))
    assert code == 1 and "not a glTF's JSON text" in err, err
    import urllib.request
    embedded = tmp_path / "embedded.gltf"
    embedded.write_text(gltf_text("data:application/octet-stream;base64," + "A" * 48))
    p = subprocess.Popen([sys.executable, VIEW, str(embedded), "--port", "0"],
                         stdout=subprocess.PIPE, text=True)
    try:
        url = p.stdout.readline().strip()
        assert "file=/run/embedded.gltf" in url, url
        root = url[:url.index("/index.html")]
        with urllib.request.urlopen(root + "/run/embedded.gltf", timeout=10) as served:
            assert served.read() == embedded.read_bytes()
    finally:
        p.terminate()
        p.wait(timeout=10)


def test_the_help_names_the_default_port():
    r = subprocess.run([sys.executable, VIEW, "--help"], capture_output=True, text=True, timeout=20)
    assert r.returncode == 0 and "default: 8765" in r.stdout, r.stdout


def test_the_help_says_what_is_served_and_how_to_stop():
    # Before: --help gave only the description; "Stop with Ctrl-C" was in the docstring alone.
    r = subprocess.run([sys.executable, VIEW, "--help"], capture_output=True, text=True, timeout=20)
    text = " ".join(r.stdout.split())
    assert r.returncode == 0 and "Ctrl-C" in text and "Only the files named here" in text and ".mtl" in text, r.stdout


def test_folders_are_not_listed():
    # Before: /tests/ (any folder of viewer/) was served as a directory listing.
    import urllib.error
    import urllib.request
    p = subprocess.Popen([sys.executable, VIEW, MESH, "--port", "0"], stdout=subprocess.PIPE, text=True)
    try:
        url = p.stdout.readline().strip()
        root = url[:url.index("/index.html")]
        with urllib.request.urlopen(url, timeout=10) as page:
            assert page.status == 200
        with pytest.raises(urllib.error.HTTPError) as e:
            urllib.request.urlopen(root + "/tests/", timeout=10)
        assert e.value.code == 404
    finally:
        p.terminate()
        p.wait(timeout=10)
