"""The files a sweep's mesh needs besides itself, as the library lists them for its output check
(src/mesh/input_dependencies.cpp; docs/design/output-safety.md, "Files the input needs"): an
OBJ's material libraries and the images they name, a PLY's texture files, a glTF's external
buffers and images. The library's list is not reachable from Python, and the sweep writes its
tables by its own renames, so sweep_written.py refuses a table over one of these files by this
list: a results.csv written where the OBJ's mtllib points destroys the user's materials, though
it is not the mesh itself. A file named but missing is listed too (a table that created it would
give the mesh a library it did not have).

The same readings as the library's, in short: an OBJ's statements with continued lines joined
(a backslash ending a line), each `mtllib` name from the OBJ's folder (a name with spaces taken
whole when it names an existing file), each library once; a library's texture keys (`map_*` but
`map_aat`, `bump`, `disp`, `decal`, `refl`, `norm`) with their options skipped; a PLY header's
`comment TextureFile` paths; a glTF's buffer and image URIs, percent-decoded, from its folder
(a buffer also from the current folder, where the reader looks next). Never raises for the
files' contents: a file that cannot be read gives what could be made out (its reader refuses
it before any job runs)."""

import json
import os
import re
import struct
import urllib.parse

# The largest material library read for its images (the library's MAX_MTL_BYTES is larger than
# any real one; a bigger file is not a material library worth reading here).
MAX_MTL_BYTES = 64 << 20
_SPACE = b" \t\v\f\r"
# The options of a texture statement and how many arguments each takes (gltf_material.cpp's
# map_file_name); -o, -s and -t take one to three numbers.
_FIXED = {b"-blendu": 1, b"-blendv": 1, b"-bm": 1, b"-boost": 1, b"-cc": 1, b"-clamp": 1,
          b"-imfchan": 1, b"-mm": 2, b"-texres": 1, b"-type": 1}
_TEXTURE_KEYS = (b"bump", b"disp", b"decal", b"refl", b"norm")


def _read(path, limit=None):
    try:
        with open(path, "rb") as f:
            return f.read() if limit is None else f.read(limit + 1)
    except OSError:
        return None


def _text(b):
    return os.fsdecode(b)


def _quoted(path):
    return "'{}'".format(path)


def _join_continued_lines(data, eol):
    """A backslash with only blanks after it on its line joins the next line (line_tokens.hpp):
    it and the line end become spaces, every byte keeps its offset."""
    s = bytearray(data)
    b = s.find(b"\\")
    while b >= 0:
        e = b + 1
        while e < len(s) and s[e] != eol and s[e] in _SPACE:
            e += 1
        if e == len(s) or (s[e] == eol and e + 1 == len(s)):
            break
        if s[e] == eol:
            s[b] = s[e] = 0x20
            b = e
        b = s.find(b"\\", b + 1)
    return bytes(s)


def _mtllib_lines(data):
    """(line number, the names' text) of each mtllib statement (find_mtllib_lines): a statement
    that starts with the keyword, its line the one it starts on. Found by a search rather than
    line by line: a large OBJ has millions of lines and a few mtllib ones."""
    if b"mtllib" not in data:
        return []
    eol = b"\n" if b"\n" in data else b"\r"
    text = _join_continued_lines(data, eol[0]) if b"\\" in data else data
    space = b" \t\v\f" + (b"\r" if eol == b"\n" else b"")
    blank, e = b"[" + re.escape(space) + b"]", re.escape(eol)
    start = b"(?:\\A(?:\xef\xbb\xbf)?|(?<=" + e + b"))"  # a line's, after the file's BOM
    statement = re.compile(start + blank + b"*mtllib(?=" + blank + b"|" + e + b"|\\Z)([^" + e +
                           b"]*)")
    out = []
    for m in statement.finditer(text):
        rest = m.group(1)
        # A comment after the names ends them: a token that starts with '#'.
        comment = re.search(b"(?:\\A|(?<=" + blank + b"))#", rest)
        if comment:
            rest = rest[:comment.start()]
        out.append((data.count(eol, 0, m.start()) + 1, rest))
    return out


def _mtllib_names(rest, folder):
    """The names of one mtllib line (mtllib_names): from each token, the shortest run of tokens
    (spaces kept) that names an existing file from the OBJ's folder; else the token alone."""
    tokens, at = [], 0
    while True:
        while at < len(rest) and rest[at] in _SPACE:
            at += 1
        if at == len(rest):
            break
        start = at
        while at < len(rest) and rest[at] not in _SPACE:
            at += 1
        tokens.append((start, at))
    names, i = [], 0
    while i < len(tokens):
        j = i
        while j < len(tokens) and not os.path.isfile(
                os.path.join(folder, _text(rest[tokens[i][0]:tokens[j][1]]))):
            j += 1
        if j == len(tokens):
            j = i
        names.append(_text(rest[tokens[i][0]:tokens[j][1]]))
        i = j + 1
    return names


def _number(token):
    try:
        float(token)
        return True
    except ValueError:
        return False


def _map_file_name(args):
    """The file of a texture statement's arguments, its options skipped (map_file_name): the
    rest of the line from the first token that is no option's, as written (a name with spaces)."""
    tokens = list(re.finditer(rb"[^ \t\v\f\r\n]+", args))
    at = 0
    while at < len(tokens) and tokens[at].group().startswith(b"-"):
        option = tokens[at].group()
        at += 1
        if option in _FIXED:
            at += _FIXED[option]
        elif option in (b"-o", b"-s", b"-t"):
            for _ in range(3):
                if at < len(tokens) and _number(tokens[at].group()):
                    at += 1
    if at >= len(tokens):
        return ""
    return _text(args[tokens[at].start():].strip(_SPACE + b"\n"))


def _mtl_textures(library, obj):
    data = _read(library, MAX_MTL_BYTES)
    if data is None or len(data) > MAX_MTL_BYTES:
        return []
    folder = os.path.dirname(library)
    out = []
    for number, line in enumerate(data.split(b"\n"), 1):
        line = line.split(b"#", 1)[0]
        parts = line.split(None, 1)
        if not parts:
            continue
        key = parts[0].lower()
        if not ((key.startswith(b"map_") and key != b"map_aat") or key in _TEXTURE_KEYS):
            continue
        name = _map_file_name(parts[1] if len(parts) > 1 else b"")
        if name:
            out.append((os.path.join(folder, name),
                        "an image that {}, the material library of {}, names ({}, line {})".format(
                            _quoted(library), _quoted(obj), _text(parts[0]), number)))
    return out


def _obj(path, data):
    folder = os.path.dirname(path)
    out, seen = [], set()
    for line, rest in _mtllib_lines(data):
        for name in _mtllib_names(rest, folder):
            library = os.path.join(folder, name)
            key = os.path.realpath(library)
            if key in seen:
                continue
            seen.add(key)
            out.append((library, "the material library that {} reads (mtllib, line {})".format(
                _quoted(path), line)))
            out.extend(_mtl_textures(library, path))
    return out


def _ply(path, data):
    end = data.find(b"end_header")
    folder = os.path.dirname(path)
    out = []
    for number, line in enumerate(data[:end if end >= 0 else len(data)].split(b"\n"), 1):
        words = line.strip().split(None, 1)
        if len(words) < 2 or words[0] != b"comment":
            continue
        text = words[1].strip()
        if not text.startswith(b"TextureFile") or (len(text) > 11 and text[11] not in _SPACE):
            continue
        name = _text(text[11:].strip())
        if name:
            out.append((os.path.join(folder, name),
                        "the texture that {} names (comment TextureFile, header line {})".format(
                            _quoted(path), number)))
    return out


def _gltf_json(path, data):
    if path.lower().endswith(".glb"):
        if len(data) < 20 or data[:4] != b"glTF":
            return None
        length, kind = struct.unpack_from("<II", data, 12)
        if kind != 0x4E4F534A:  # "JSON"
            return None
        data = data[20:20 + length]
    try:
        doc = json.loads(data.decode("utf-8"))
    except ValueError:
        return None
    return doc if isinstance(doc, dict) else None


def _gltf(path, data):
    doc = _gltf_json(path, data)
    if doc is None:
        return []
    folder = os.path.dirname(path)
    out = []
    for key, what in (("buffers", "a file that {} reads (an external buffer)"),
                      ("images", "an image that {} names ({}[{}].uri)")):
        items = doc.get(key)
        for i, item in enumerate(items if isinstance(items, list) else []):
            uri = item.get("uri") if isinstance(item, dict) else None
            if not isinstance(uri, str) or not uri or uri.startswith("data:"):
                continue
            role = what.format(_quoted(path), key, i)
            names = [urllib.parse.unquote(uri)]
            cut = min((k for k in (uri.find("?"), uri.find("#")) if k > 0), default=-1)
            if key == "images" and cut > 0:  # a viewer loads the path before a query
                names.append(urllib.parse.unquote(uri[:cut]))
            for name in names:
                out.append((os.path.join(folder, name), role))
                if key == "buffers":  # the reader looks in the current folder next
                    out.append((os.path.abspath(name), role))
    return out


def needed_files(path):
    """(path, what it is to the mesh) of each file the mesh file `path` needs, by its extension;
    [] for OFF and STL, and for a file that cannot be read."""
    kind = os.path.splitext(path)[1].lower()
    if kind not in (".obj", ".ply", ".gltf", ".glb"):
        return []
    data = _read(path)
    if data is None:
        return []
    try:
        if kind == ".obj":
            return _obj(path, data)
        if kind == ".ply":
            return _ply(path, data)
        return _gltf(path, data)
    except (ValueError, struct.error):
        return []
