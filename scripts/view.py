#!/usr/bin/python3
"""Serves the viewer (viewer/) and a run's files on localhost and prints the URL to open.

Usage: scripts/view.py FILE [FILE2] [--log RUN.csv|RUN.json] [--port N] [--open]

FILE is a run's .glb or a mesh (.off, .obj, .ply, .stl, .glb or .gltf: a result, a frame, a
--fields PLY, a regions -o PLY, shown in its regions' face colours); a .gltf is shown with its
buffers embedded (as run and repair write it), and its image files are not served (its materials
show without their textures);
with FILE2 the two are shown side by side (e.g. before and after).
The page is viewer/index.html with ?file=/run/FILE&compare=/run/FILE2&log=/run/RUN.csv; only
those files and the viewer folder are served, on 127.0.0.1. three.js is served from viewer/node_modules, which
scripts/install_deps.sh installs (npm ci). Stop with Ctrl-C.
"""
import argparse
import errno
import functools
import http.server
import json
import os
import sys
import urllib.parse
import webbrowser

VIEWER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "viewer")


class Handler(http.server.SimpleHTTPRequestHandler):
    extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map,
                      ".glb": "model/gltf-binary", ".gltf": "model/gltf+json", ".js": "text/javascript", ".mjs": "text/javascript",
                      ".csv": "text/csv", ".json": "application/json", ".off": "text/plain",
                      ".obj": "text/plain", ".ply": "application/octet-stream", ".stl": "application/octet-stream"}

    def __init__(self, *args, run_files=None, **kwargs):
        self.run_files = run_files or {}
        super().__init__(*args, directory=VIEWER, **kwargs)

    def translate_path(self, path):
        p = urllib.parse.unquote(urllib.parse.urlsplit(path).path)
        if p.startswith("/run/"):
            return self.run_files.get(p[len("/run/"):], os.path.join(VIEWER, "__missing__"))
        return super().translate_path(path)

    def list_directory(self, path):
        # The page, its scripts and the run's files, not a listing of the viewer's folders.
        self.send_error(404, "No listing")
        return None

    def log_message(self, fmt, *args):  # quiet: errors only
        if len(args) > 1 and str(args[1]).startswith(("4", "5")):
            super().log_message(fmt, *args)


# What viewer/src/mesh_files.js shows (GLTF_EXTENSIONS and MESH_EXTENSIONS there).
MESH_EXTENSIONS = (".glb", ".gltf", ".off", ".obj", ".ply", ".stl")
LOG_EXTENSIONS = (".csv", ".json")


def port_number(text):
    try:
        port = int(text)
    except ValueError:
        port = -1
    if not 0 <= port <= 65535:
        raise argparse.ArgumentTypeError(f"'{text}' is not a port number (0 to 65535)")
    return port


def checked_file(path, extensions, what):
    """The path, if it is a readable file the viewer can show; else the reason, at once (the page
    would only say so in the browser's console)."""
    if os.path.isdir(path):
        sys.exit(f"view.py: {path}: it is a folder, not {what}")
    if not os.path.isfile(path):
        sys.exit(f"view.py: no such file: {path}")
    if not path.lower().endswith(extensions):
        sys.exit(f"view.py: {path}: not {what} ({', '.join(extensions)})")
    # A binary glTF starts with its magic, "glTF" (glTF 2.0, 4.4.3.1): anything else would only
    # fail in the browser's console.
    if path.lower().endswith(".glb"):
        with open(path, "rb") as f:
            if f.read(4) != b"glTF":
                sys.exit(f"view.py: {path}: not a binary glTF (it does not start with 'glTF')")
    if path.lower().endswith(".gltf"):
        refuse_gltf_buffer_files(path)
    return path


def refuse_gltf_buffer_files(path):
    """Exits naming a .gltf's buffer that is not embedded (a data: URI) or a file that is not a
    glTF's JSON: the page reads the .gltf alone (viewer/src/file_checks.js checkGltf), and only
    the files named here are served."""
    try:
        with open(path, "rb") as f:
            doc = json.loads(f.read().decode("utf-8"))
    except (ValueError, UnicodeDecodeError) as e:
        sys.exit(f"view.py: {path}: not a glTF's JSON text ({e})")
    if not isinstance(doc, dict):
        sys.exit(f"view.py: {path}: not a glTF (its JSON is not an object)")
    buffers = doc.get("buffers")
    for k, b in enumerate(buffers if isinstance(buffers, list) else []):
        uri = b.get("uri") if isinstance(b, dict) else None
        if not (isinstance(uri, str) and uri.startswith("data:")):
            what = f"the file '{uri}'" if isinstance(uri, str) else "not embedded"
            sys.exit(f"view.py: {path}: buffer {k} is {what}, which the viewer does not read (it "
                     "shows a .gltf whose buffers are in it, as run and repair write them, or a .glb)")


def main():
    ap = argparse.ArgumentParser(
        description="Serve the ShellContract viewer with a run's .glb or meshes",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Only the files named here and the viewer are served, on 127.0.0.1; an OBJ's .mtl and\n"
               "textures are not (open the .obj, its .mtl and textures together with the page's Open\n"
               "button to see its materials). In the page: space plays or pauses, the left and right\n"
               "arrows step a frame. The server runs until stopped with Ctrl-C.")
    ap.add_argument("glb", metavar="FILE",
                    help="the run's animated glTF (shellcontract run ... --gltf RUN.glb) or a mesh (.off, .obj, .ply, .stl, .glb, .gltf)")
    ap.add_argument("compare", metavar="FILE2", nargs="?", help="a second .glb, .gltf or mesh, shown beside the first")
    ap.add_argument("--log", help="the run's --log CSV or --summary JSON, for the V/V0 plot")
    ap.add_argument("--port", type=port_number, default=8765,
                    help="port on 127.0.0.1 (default: %(default)s; 0: any free port)")
    ap.add_argument("--open", action="store_true", help="also open the page in the default browser")
    args = ap.parse_args()

    if not os.path.isdir(os.path.join(VIEWER, "node_modules", "three")):
        sys.exit("view.py: viewer/node_modules is missing; run scripts/install_deps.sh (or npm ci in viewer/)")
    run_files, query = {}, {}
    given = [(k, p) for k, p in (("file", args.glb), ("compare", args.compare), ("log", args.log)) if p is not None]
    for key, path in given:
        if key == "log":
            checked_file(path, LOG_EXTENSIONS, "a --log CSV or a --summary JSON")
        else:
            checked_file(path, MESH_EXTENSIONS, "a .glb, a .gltf or a mesh")
    # The page names each file by its name here; two files of one name (before/out.off,
    # after/out.off) are named with their folders, which the user knows them by.
    paths = [os.path.abspath(p) for _, p in given]
    for key, path in given:
        full = os.path.abspath(path)
        name = os.path.basename(full)
        if any(os.path.basename(p) == name and p != full for p in paths):
            name = os.path.join(os.path.basename(os.path.dirname(full)), name)
        if name in run_files and run_files[name] != full:
            name = f"{key}_{name}"  # the same folder name too: told apart by the key
        run_files[name] = full
        query[key] = "/run/" + urllib.parse.quote(name, safe="")

    handler = functools.partial(Handler, run_files=run_files)
    try:
        server = http.server.ThreadingHTTPServer(("127.0.0.1", args.port), handler)
    except OSError as e:
        sys.exit(f"view.py: cannot serve on 127.0.0.1:{args.port}: {e.strerror or e}"
                 + (" (another viewer? use --port 0 for any free port)" if e.errno == errno.EADDRINUSE else ""))
    url = f"http://127.0.0.1:{server.server_address[1]}/index.html?" + urllib.parse.urlencode(query, safe="/")
    print(url, flush=True)
    print("view.py: serving the viewer at the URL above; Ctrl-C stops it", file=sys.stderr, flush=True)
    if args.open and not webbrowser.open(url):
        print("view.py: no browser could be opened; open the URL above in one", file=sys.stderr, flush=True)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        sys.exit(130)  # as the tool: stopped by Ctrl-C


if __name__ == "__main__":
    main()
