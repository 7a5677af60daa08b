"""The sweep file (docs/design/sweeps.md): JSON naming meshes, fixed options, a grid and/or a list
of runs; expanded into jobs, every one validated before any runs.

Option names are the Python names of the one option table (``shellcontract.options()``); values
are checked by the library itself (``_core.resolve_options``), so the sweep holds no second copy
of the names or the ranges.
"""

import errno
import glob
import hashlib
import itertools
import json
import os
import re
import stat

from . import _core
from . import sweep_needs

TOP_LEVEL_KEYS = ("meshes", "options", "grid", "runs")
# Options whose value is a file name (the keywords they take instead): relative to the sweep
# file, as the meshes are; a job's id covers the file's bytes, not its name.
PATH_OPTIONS = {"regions": ("auto", "none"), "region_weights": ()}
# Options that do not change a run's result (the library guarantees the same bytes for any
# thread count), left out of the job id so that a change of them reruns nothing: the library's
# list, the one a resumed run may change.
RESULT_NEUTRAL = tuple(_core.result_neutral_options())


class SweepError(Exception):
    """A sweep file that cannot be run; the message names the file and the job or entry."""


class ResourceShort(Exception):
    """The machine, not the sweep file: memory or open files ran short while a mesh was checked
    (the CLI's exit code 3 for the same mesh, not a refused file's 1)."""


# An OSError of these errnos is the system's refusal of a resource (the readers' ResourceFileError).
_RESOURCE_ERRNOS = (errno.EMFILE, errno.ENFILE, errno.ENOMEM)


class Job:
    """One run: a mesh and its options (the given ones; the library resolves the rest)."""

    def __init__(self, index, mesh, options, args, resolved, job_id, varying):
        self.index = index        # position in the sweep's expansion order
        self.mesh = mesh          # absolute path of the input mesh
        self.options = options    # Python option name -> value as the sweep file gives it
        self.args = args          # `shellcontract run` arguments of those options
        self.resolved = resolved  # every option's resolved text (the job id's input)
        self.id = job_id
        self.varying = varying    # option name -> value for the grid/runs columns

    def label(self):
        parts = ["{}={}".format(k, v) for k, v in sorted(self.options.items())]
        return "job {} ({}{})".format(self.index, os.path.basename(self.mesh),
                                      ", " + ", ".join(parts) if parts else "")

    def to_dict(self):
        return {"index": self.index, "mesh": self.mesh, "options": self.options,
                "args": self.args, "id": self.id}


def _fail(path, what):
    raise SweepError("{}: {}".format(path, what))


def _check_value(path, where, name, value):
    if isinstance(value, (dict,)) or value is None:
        _fail(path, "{}: option {!r} has a value {!r}; expected a number, a string, a bool or a "
                    "list of numbers".format(where, name, value))
    # contract() takes region_weights as an array too; a job is a command line, which takes the
    # file. A list had passed the check and run as the file name "0.5,0.5,...".
    if name in PATH_OPTIONS and not isinstance(value, str):
        _fail(path, "{}: option {!r} has the value {}; in a sweep it is a file name (relative to "
                    "the sweep file)".format(where, name, _short(value)))


def _short(value):
    text = json.dumps(value)
    return text if len(text) <= 60 else text[:57] + "..."


class _DuplicateKey(Exception):
    pass


def _unique_keys(pairs):
    """json's object hook: an object whose key repeats is refused (json keeps the last value
    silently, so a sweep file with "pressure" twice ran only one of them)."""
    out = {}
    for key, value in pairs:
        if key in out:
            raise _DuplicateKey(key)
        out[key] = value
    return out


def _python_names(path, where, table):
    """The table with its option names spelt as Python spells them: an option written as the
    CLI writes it ("target-volume") is the same option, and keyed so everywhere after (the
    paths, the job id, the run's arguments); it had been checked under one name and left off
    the run's command line under the other. Given both ways it is refused."""
    known = {row[0] for row in _core.option_table()}
    out = {}
    for name, value in table.items():
        python = name.replace("-", "_")
        python = python if python in known else name
        if python in out:
            _fail(path, "{}: option {!r} is given twice (as '-' and as '_')".format(where, python))
        out[python] = value
    return out


def _require_text(path, data):
    """Every string of the file is text: JSON's escapes can spell a lone surrogate ("\\ud800"),
    which no file name or option value is, and which had reached the library as an internal
    cast error. Walked without recursion (the file's depth is JSON's)."""
    stack = [data]
    while stack:
        item = stack.pop()
        strings = []
        if isinstance(item, dict):
            strings = list(item)
            stack.extend(item.values())
        elif isinstance(item, list):
            stack.extend(item)
        elif isinstance(item, str):
            strings = [item]
        for text in strings:
            try:
                text.encode("utf-8")
            except UnicodeEncodeError:
                _fail(path, "the string {} is not text (a lone surrogate escape)".format(
                    ascii(text)[:60]))


# A sweep file lists meshes, options and runs: a few kilobytes. The bound only keeps a wrong file
# (a disk image, a log) from being read whole into memory before it is refused.
MAX_SWEEP_FILE_BYTES = 64 << 20


def _kind_refusal(mode):
    """Why a file of this mode cannot be a sweep file (as the tool's own inputs say it), or None."""
    if stat.S_ISDIR(mode):
        return "it is a folder"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "not a regular file: it is a device; inputs must be regular files"
    if stat.S_ISFIFO(mode):
        return "not a regular file: it is a FIFO (named pipe); inputs must be regular files"
    if stat.S_ISSOCK(mode):
        return "not a regular file: it is a socket; inputs must be regular files"
    if not stat.S_ISREG(mode):
        return "not a regular file; inputs must be regular files"
    return None


def _read_sweep_file(path):
    """The sweep file's bytes: a regular file of at most MAX_SWEEP_FILE_BYTES, else SweepError.
    Opened without blocking (a FIFO put in its place after a check would otherwise wait for a
    writer) and checked on the open file, so what is read is what was checked."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_CLOEXEC | os.O_NONBLOCK)
    except OSError as e:
        if e.errno == errno.EISDIR:
            raise SweepError("{}: cannot read the sweep file (it is a folder)".format(path))
        raise SweepError("{}: cannot read the sweep file ({})".format(path, e.strerror))
    try:
        st = os.fstat(fd)
    except OSError as e:
        os.close(fd)
        raise SweepError("{}: cannot read the sweep file ({})".format(path, e.strerror))
    why = _kind_refusal(st.st_mode)
    if why:
        os.close(fd)
        raise SweepError("{}: cannot read the sweep file ({})".format(path, why))
    with os.fdopen(fd, "rb") as f:
        if st.st_size > MAX_SWEEP_FILE_BYTES:
            raise SweepError("{}: file too large for a sweep file: {} bytes, more than {}".format(
                path, st.st_size, MAX_SWEEP_FILE_BYTES))
        try:
            text = f.read(MAX_SWEEP_FILE_BYTES + 1)
        except OSError as e:
            raise SweepError("{}: cannot read the sweep file ({})".format(path, e.strerror))
    if len(text) > MAX_SWEEP_FILE_BYTES:  # grew after the check
        raise SweepError("{}: file too large for a sweep file: more than {} bytes".format(
            path, MAX_SWEEP_FILE_BYTES))
    return text


def load(path):
    """Reads and checks the sweep file's structure; returns its dict."""
    text = _read_sweep_file(path)
    try:
        data = json.loads(text.decode("utf-8"), object_pairs_hook=_unique_keys)
    except _DuplicateKey as e:
        raise SweepError("{}: the key {!r} is given twice in one object (JSON readers keep one of "
                         "the two values; give it once)".format(path, e.args[0]))
    except (UnicodeDecodeError, ValueError) as e:
        raise SweepError("{}: not valid JSON ({})".format(path, e))
    except RecursionError:
        raise SweepError("{}: the JSON nests too deeply (a sweep file is a few levels deep)".format(
            path))
    _require_text(path, data)
    if not isinstance(data, dict):
        _fail(path, "expected a JSON object with 'meshes' and optionally 'options', 'grid', "
                    "'runs'")
    unknown = [k for k in data if k not in TOP_LEVEL_KEYS]
    if unknown:
        _fail(path, "unknown key {!r} (expected {})".format(unknown[0], ", ".join(TOP_LEVEL_KEYS)))
    meshes = data.get("meshes")
    if isinstance(meshes, str):
        meshes = [meshes]
    if not isinstance(meshes, list) or not meshes or not all(isinstance(m, str) for m in meshes):
        _fail(path, "'meshes' must be a non-empty list of paths or globs (relative to the file)")
    options = data.get("options", {})
    if not isinstance(options, dict):
        _fail(path, "'options' must be an object: option name -> value")
    options = _python_names(path, "options", options)
    grid = data.get("grid", {})
    if not isinstance(grid, dict):
        _fail(path, "'grid' must be an object: option name -> list of values")
    grid = _python_names(path, "grid", grid)
    for name, values in grid.items():
        if not isinstance(values, list) or not values:
            _fail(path, "grid option {!r}: expected a non-empty list of values".format(name))
        if name in options:
            _fail(path, "option {!r} is both in 'options' and in 'grid'".format(name))
        if name in RESULT_NEUTRAL and len(values) > 1:
            # Its jobs have one id, so all but the first would be dropped as repeats.
            _fail(path, "grid option {!r}: it does not change a run's result (the same bytes at "
                        "any value), so each of its values would be the same job; give it in "
                        "'options' (to time it, use shellcontract bench)".format(name))
    runs = data.get("runs", [{}])
    if not isinstance(runs, list) or not runs or not all(isinstance(r, dict) for r in runs):
        _fail(path, "'runs' must be a non-empty list of objects (option name -> value)")
    runs = [_python_names(path, "runs[{}]".format(i), r) for i, r in enumerate(runs)]
    for i, run in enumerate(runs):
        for name in run:
            if name in grid:
                _fail(path, "runs[{}]: option {!r} is also in 'grid' (the run's value would "
                            "replace every grid value, collapsing that axis): put it in one of "
                            "them".format(i, name))
    for where, table in [("options", options)] + [("runs[{}]".format(i), r) for i, r in
                                                  enumerate(runs)]:
        for name, value in table.items():
            _check_value(path, where, name, value)
    for name, values in grid.items():
        for value in values:
            _check_value(path, "grid", name, value)
    return {"meshes": meshes, "options": options, "grid": grid, "runs": runs}


def expand_meshes(path, patterns):
    """The meshes' absolute paths, each pattern's matches sorted, in the file's order; a
    pattern that matches nothing is an error. A pattern is relative to the sweep file's folder,
    whose name is taken as it is: before, it was globbed with the pattern, so a folder `r[12]`
    ran its sibling `r1`'s mesh of the same name, and a folder `run [2024]` matched nothing. A
    pattern that names an existing file (`part[1].off`) is that file; else `*`, `?` and `[...]`
    make it a glob."""
    base = os.path.dirname(os.path.abspath(path))
    out = []
    for pattern in patterns:
        full = pattern if os.path.isabs(pattern) else os.path.join(base, pattern)
        if glob.has_magic(pattern) and not os.path.isfile(full):
            where = pattern if os.path.isabs(pattern) else os.path.join(glob.escape(base), pattern)
            matches = sorted(m for m in glob.glob(where) if os.path.isfile(m))
            if not matches:
                _fail(path, "mesh pattern {!r} matches no file".format(pattern))
        else:
            matches = [full]
        for m in matches:
            m = os.path.abspath(m)
            if m not in out:
                out.append(m)
    return out


def _option_error(e):
    """The library's message for a bad option, worded for a sweep file: its unknown-option error
    names the Python call that shares its parser ("contract() got an unknown option 'x'")."""
    text = str(e)
    m = re.match(r"\w+\(\) got an unknown option ('[^']*')", text)
    if m:
        text = ("unknown option {} (options are the Python names of shellcontract.options())"
                "{}".format(m.group(1), text[m.end():]))
    return text


def _with_paths(path, options):
    """Options whose value is a file, made absolute (relative to the sweep file)."""
    base = os.path.dirname(os.path.abspath(path))
    out = dict(options)
    for name, keywords in PATH_OPTIONS.items():
        v = out.get(name)
        if isinstance(v, str) and v not in keywords and not os.path.isabs(v):
            out[name] = os.path.join(base, v)
    return out


def file_sha256(path, cache=None):
    """The file's bytes' SHA-256; `cache` (path -> digest), where given, is one expansion's, so
    that a file is read once per sweep and a changed file is read again by the next."""
    if cache is None:
        cache = {}
    if path not in cache:
        h = hashlib.sha256()
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
        cache[path] = h.hexdigest()
    return cache[path]


def input_files(options):
    """The files a job reads besides its mesh: option name -> path, for every path option
    (PATH_OPTIONS) whose value is a file rather than one of its keywords. `options` as
    _with_paths gives them (absolute paths)."""
    out = {}
    for name, keywords in PATH_OPTIONS.items():
        v = options.get(name)
        if isinstance(v, str) and v not in keywords:
            out[name] = v
    return out


def inputs(path, jobs):
    """(what, path) of every file the sweep of the file `path` and its `jobs` reads: the sweep
    file, each mesh, each regions or weights file; each once."""
    out, seen = [("the sweep file", os.path.abspath(path))], set()
    for job in jobs:
        for what, p in [("mesh", job.mesh)] + sorted(
                input_files(_with_paths(path, job.options)).items()):
            if p not in seen:
                seen.add(p)
                out.append((what, p))
    return out


def mesh_needs_shas(mesh, needs, cache):
    """{"mesh needs NAME": SHA-256} of each file the mesh reads or names besides itself that is
    there (a glTF's external buffers, which hold its geometry; an OBJ's material libraries and
    textures, which its result names and a glTF result embeds), NAME as the mesh names it
    (relative to its folder, so that a moved folder keeps its ids). `needs`: mesh -> the list,
    found once per expansion. A named file that is missing is the reader's to refuse (a buffer)
    or to warn about (a texture), not a byte of the job."""
    if mesh not in needs:
        needs[mesh] = [p for p, _ in sweep_needs.needed_files(mesh) if os.path.isfile(p)]
    folder = os.path.dirname(os.path.abspath(mesh))
    out = {}
    for p in needs[mesh]:
        try:
            out["mesh needs " + os.path.relpath(p, folder)] = file_sha256(p, cache)
        except MemoryError as e:
            raise ResourceShort("{}: {}".format(p, e or "out of memory")) from e
        except OSError as e:
            if e.errno in _RESOURCE_ERRNOS:
                raise ResourceShort("{}: {}".format(p, e.strerror or e)) from e
            # A file the mesh names that this user cannot read (a texture, a material library:
            # a buffer the reader would have refused above) is the run's to warn about, as
            # `run` does, not a byte of the job.
    return out


def job_id(mesh_sha, resolved, version, file_shas=None):
    """A stable id: the mesh's bytes, every resolved option (less the result-neutral ones), the
    bytes of every other file the job reads (`file_shas`: option name -> SHA-256, standing for
    the option's path, so that an edited file is another job and a moved one is not) and the
    tool's version. The same job in another sweep file has the same id."""
    key = {k: v for k, v in resolved.items() if k not in RESULT_NEUTRAL}
    for name, sha in (file_shas or {}).items():
        key[name] = "file sha256:" + sha
    text = json.dumps({"mesh": mesh_sha, "options": key, "version": version}, sort_keys=True)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


# The most jobs one sweep file may make: far more than a machine or a small cluster runs in a
# sweep, so that a mistyped grid is refused before its expansion exhausts the memory.
MAX_JOBS = 100000


def expand(path, data, version, check_mesh=None):
    """The jobs of a loaded sweep file, validated; raises SweepError naming the first bad job
    (nothing is run before every job has passed).

    check_mesh(path) raises ValueError/OSError for an unusable mesh (default: what `run` checks
    of its input before the run, for a result in the input's format, as each job writes it: the
    reader's checks, and for a glTF that its result can be written).
    """
    check_mesh = check_mesh or _core.check_run_input
    cache = {}  # path -> SHA-256, for this expansion only (a later one reads the files again)
    meshes = expand_meshes(path, data["meshes"])
    for m in meshes:
        try:
            check_mesh(m)
        except (ValueError, OSError, RuntimeError, MemoryError) as e:
            text = str(e)  # the reader's messages start with the file's name
            text = text if text.startswith(m) else "mesh {}: {}".format(m, text or type(e).__name__)
            if isinstance(e, MemoryError) or (isinstance(e, OSError) and e.errno in _RESOURCE_ERRNOS):
                raise ResourceShort("{}: {}".format(path, text)) from e
            _fail(path, text)
    grid = data["grid"]
    names = list(grid)
    # Counted before the grid is made: its product is built whole, and a grid of a hundred
    # million points ended in a MemoryError instead of a message.
    count = len(meshes) * len(data["runs"])
    for values in grid.values():
        count *= len(values)
    if count > MAX_JOBS:
        _fail(path, "the meshes, grid and runs make {} jobs; at most {} in one sweep file (split "
                    "it, or shard it over several files)".format(count, MAX_JOBS))
    points = [dict(zip(names, values)) for values in itertools.product(*grid.values())] or [{}]
    jobs, seen, index = [], {}, -1  # seen: job id -> the job kept for it
    needs = {}  # mesh -> the files it needs (mesh_needs_shas)
    for mesh in meshes:
        for point in points:
            for run in data["runs"]:
                options = dict(data["options"])
                options.update(point)
                options.update(run)
                varying = dict(point)
                varying.update(run)
                index += 1
                where = "job {} (mesh {}, options {})".format(
                    index, os.path.relpath(mesh, os.path.dirname(os.path.abspath(path))),
                    json.dumps(options, sort_keys=True))
                absolute = _with_paths(path, options)
                try:
                    checked = _core.resolve_options(**absolute)
                except (TypeError, ValueError) as e:
                    _fail(path, "{}: {}".format(where, _option_error(e)))
                file_shas = {}
                for name, file in input_files(absolute).items():
                    try:
                        if not os.path.isfile(file):
                            raise OSError("not a file" if os.path.exists(file) else
                                          "no such file")
                        file_shas[name] = file_sha256(file, cache)
                    except OSError as e:
                        _fail(path, "{}: {} file {} is not readable ({})".format(
                            where, name, file, e.strerror or e))
                file_shas.update(mesh_needs_shas(mesh, needs, cache))
                jid = job_id(file_sha256(mesh, cache), checked["resolved"], version, file_shas)
                kept = seen.get(jid)
                if kept is not None:
                    # The same run twice (e.g. a grid value equal to the default) is run once.
                    # Runs that differ only in a result-neutral option share an id as well, but
                    # the user asked for each of them: dropping all but the first would lose
                    # that option's values silently, as the grid check above says.
                    for name in RESULT_NEUTRAL:
                        if kept.resolved.get(name) != checked["resolved"].get(name):
                            _fail(path, "{}: differs from {} only in {!r}, which does not "
                                        "change a run's result (the same bytes at any value), "
                                        "so it would be the same job; give {!r} once (to time "
                                        "it, use shellcontract bench)".format(
                                            where, kept.label(), name, name))
                    continue
                job = Job(len(jobs), mesh, options, list(checked["args"]), checked["resolved"],
                          jid, varying)
                seen[jid] = job
                jobs.append(job)
    return jobs


def varying_names(data):
    """The results' option columns: the grid's names, then the runs' names, in file order."""
    names = list(data["grid"])
    for run in data["runs"]:
        for name in run:
            if name not in names:
                names.append(name)
    return names
