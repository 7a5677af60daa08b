"""ShellContract: contract closed triangle meshes like thin elastic shells under pressure.

Meshes are numpy arrays: vertices (N by 3, float64) and faces (M by 3, int32 or int64, 0-based,
outward or inward oriented, closed and manifold). Other real dtypes (float32, any integer type
for faces, uint64 checked for range), any memory layout and lists of lists are converted by
numpy; bool or complex values are a TypeError, and a masked array with a masked element a
ValueError (numpy would pass on the values under the mask). Memory running out in a conversion
raises numpy's MemoryError. The options of ``contract`` are those of
``shellcontract run`` with underscores (``k_b`` for ``--k-b``), with the same defaults and
ranges; ``options()`` lists them. The same input and options give the same result as the CLI,
to the last bit.

A mesh the library refuses raises ValueError with the CLI's message; where particular faces are
to blame (an open boundary, a non-manifold edge or vertex, a duplicate or degenerate face, ...) it is a
``MeshError``, a ValueError whose ``faces`` lists the indices into the faces array of the faces
the message is about, all of them even where the message shortens its list with "...": for an
open boundary, an inconsistent orientation or a non-manifold edge every face with such an edge;
for a duplicate face the pair found first, for a degenerate face the first one.

A file that cannot be read or written (missing, a folder, not permitted, its folder missing or
read-only, the disk full) raises what Python's open() would: FileNotFoundError,
PermissionError, IsADirectoryError, NotADirectoryError, FileExistsError or another OSError,
with ``errno`` and ``filename`` set; ``str()`` (and ``strerror``) is the library's message, the
CLI's. Each is a ``FileError``, which is an OSError and a ValueError as well, so that code
catching ValueError, what these errors were before, still catches them. So are: a device, a
FIFO or a socket given as an input or found in an output's place (a FileError with errno None:
open() would take it, so no errno says why); an input over its size limit (errno EFBIG); a
glTF's external buffer that cannot be read (its own error, ``filename`` the buffer's path); a
checkpoint whose lock another run holds (BlockingIOError, errno EWOULDBLOCK).
"""

import atexit
import collections
import numbers
import os
import queue
import tempfile
import threading

import numpy as np

from . import _core, number_text
from ._region_arguments import _region_lists, _strengths, _weights, refuse_masked

__all__ = ["Option", "Result", "MeshError", "FileError", "contract", "frames", "options", "check",
           "regions", "read_mesh", "write_mesh"]

# A ValueError for a mesh refused because of some of its faces, with their indices as `faces`
# (a list of int); `except ValueError` catches it as before.
MeshError = _core.MeshError
# A file the file system refused: an OSError (raised as the subclass for its errno, which is
# FileError and the builtin of the same name, e.g. shellcontract._core.FileNotFoundError) and a
# ValueError, as these errors were before. The subclasses stay in _core: bound here, their names
# would hide the builtins from this module's own code.
FileError = _core.FileError
# The build, "0.2.0+g0123456789ab.tc.5e6f7a8b", and the kernels of this machine, "avx2" or
# "scalar": what `shellcontract --version` prints and checkpoints name (docs/cli.md, on
# `--version`).
__version__ = _core.__version__
kernels = _core.kernels

Option = collections.namedtuple("Option", "name default help cli_name")
Option.__doc__ = "One run option: Python name, default as text ('' when unset), help, CLI name."


class Result:
    """What a run produced.

    vertices: N by 3 float64, final positions in the input's units (vertex order kept).
    faces:    M by 3 int64, the faces as run (inside-out components flipped, as the CLI does).
    log:      dict column -> array, one entry per step (frame 1 on): the CLI's --log CSV
              columns (docs/cli.md, "The log and the summary").
    summary:  dict, the CLI's --summary JSON with the options under their Python names
              (target_volume), without the CLI's own keys "input", "output", "input_file",
              "setup", "peak_memory_mb", "outputs", "export" and "repair".
              summary["target_reached"] is None when no target_volume or stop_volume_ratio
              was asked for.
    status:   "ok", "target not reached", "failed", "new self-intersections" or "cancelled".
              "failed" (non-finite positions, a blow-up, or memory running out during the
              frames) keeps the last good state in vertices; summary["failure"] says which.
              Memory running out before the first frame raises MemoryError ("out of
              memory while building the rest state (10242 vertices, 20480 faces)"; where glibc
              cannot give a new thread its thread-local storage, it ends the process itself);
              a thread the system refuses then (under an address-space limit) RuntimeError
              "pthread_create has failed: Resource temporarily unavailable" (the CLI's exit
              code 3 for both). The process is left usable: a later run can succeed.
    """

    def __init__(self, raw):
        self.vertices = raw["vertices"]
        self.faces = raw["faces"]
        self.log = raw["log"]
        self.summary = raw["summary"]
        self.status = raw["status"]

    def __repr__(self):
        # Angle brackets: not a call that rebuilds the object, and every name shown is one to
        # read (frames_run is a summary key, not an attribute).
        return "<Result status={!r}, {} vertices, summary['frames_run']={}, " \
            "summary['final_volume_ratio']={:.6g}>".format(
                self.status, len(self.vertices), self.summary["frames_run"],
                self.summary["final_volume_ratio"])


def options():
    """The run options, in ``shellcontract run --help`` order, as Option tuples."""
    return [Option(*row) for row in _core.option_table()]


def contract(vertices, faces, *, callback=None, stage=None, **options):
    """Contracts a closed triangle mesh and returns a Result.

    callback(frame, vertices, metrics) is called after every step (frame = 1, 2, ...) with the
    current positions (input units) and that frame's log row as a dict; returning a false value
    stops the run (status "cancelled"): False, numpy's False_ (``v[:, 2].max() > 10``), 0.
    Returning None (or nothing) goes on, as does any true value; a value without a truth value
    (an array of several elements) raises its error, as ``if value:`` would. Ctrl-C stops the
    run cleanly and raises KeyboardInterrupt, after the step it is in and, with checkpoint=, the
    save of the state; more Ctrl-Cs meanwhile are the same request (one KeyboardInterrupt), not
    an end at once as the CLI's second Ctrl-C (SIGTERM, SIGKILL end the process at once).
    stage(what) is called as the run enters a stage that can take seconds on a large mesh, with
    a few words for a person ("selecting the regions (curvature)", "building the rest state",
    ...; the set may change): the preparation's stages before frame 1, and "checking the result
    for self-intersections" in the last step (validate="end"), before its callback. An error it
    raises stops the run and is raised.
    Both are called on the thread that called contract(), the GIL held, also while other
    threads run contract() at once (each run works on threads of its own), so that an object
    tied to its thread (a sqlite3 connection) may be used there; either may call contract()
    again. Ctrl-C, which Python hands to the main thread, stops the main thread's contract()
    alone: contract() in other threads runs on.
    Raises ValueError for a mesh the library refuses or a bad option value (MeshError, a
    ValueError with the faces' indices as ``faces``, where particular faces are to blame),
    TypeError for an unknown option; MemoryError, or RuntimeError for a thread the system
    refuses, when memory runs out before the first frame (Result.status: after it, "failed").
    The options are the CLI's with '_' for '-' (the CLI's
    spelling is taken too, as regions() takes it; one option given both ways is a TypeError);
    ``lambda``, a Python keyword, is also ``lambda_``.

    Values (regions() takes its numbers alike): a number is an int or a float (numpy's too) or
    the CLI's text ("0.5"; no blanks, no hexadecimal); an integer option (frames, threads, ...,
    and checkpoint_every) takes a whole float of any size (3.0, 1e5; 3.5 is a ValueError). A bool (numpy's bool_ too) is for the on/off
    options alone (collisions=False, or "on"/"off"); for a number, a TypeError, as is a list for
    an option of one value. ``pressure`` and ``target_volume`` take one number or keyframes
    (docs/design/keyframes.md): a list of (frame, value) pairs, ``[(0, 1), (60, 0.5)]``, an
    N by 2 array of them, or the CLI's text ``"0:1, 60:0.5"``; a list of numbers
    (``pressure=[4]``, a 1-D array) is a TypeError.

    ``regions`` (None, the default, is "not given") takes, told apart by type:

    - a str or os.PathLike: "auto", "none" or a face-list file;
    - one label per face (-1 = no region, else 0..n-1 without a gap): a 1-D numpy integer
      array, or a flat list or tuple of ints;
    - a list or tuple of regions, each a sequence or array of face indices (0-based, each face
      in one region at most, no region empty): what regions() returns; [] = no regions.

    Anything else is a TypeError. Labels and face indices must be integers (Python or numpy
    ints): a float is refused even when its value is whole (2.0), and so is NaN. With the last
    two forms, ``region_strengths`` (one value in [0, 1] per region) scales each region's
    region_shrink.

    ``region_at`` takes one point (x, y, z), a list or N by 3 array of points, or the CLI's text
    'X,Y,Z' ('X,Y,Z;X,Y,Z' for several); None is a TypeError, no point or a coordinate that is
    not finite a ValueError (naming region_at[i]).

    File names (regions, region_weights, checkpoint, resume) are a str or an os.PathLike; one
    that cannot be opened raises its OSError (FileNotFoundError, ...: a FileError, a ValueError
    too).

    checkpoint=FILE saves the whole state every checkpoint_every=N frames and when Ctrl-C
    cancels the run, as the CLI's: the run's first save holds the log and V/V0 of the frames so
    far in FILE itself (a run cancelled before any other save leaves FILE alone), later saves
    keep them in FILE.log and FILE.history beside it and append what is new (move or copy FILE
    with FILE.log and FILE.history when they are there: a checkpoint that needs them is refused
    without them);
    FILE is checked before the run as the CLI checks its outputs (ValueError
    for an input's file; FileNotFoundError for a missing folder, IsADirectoryError for a folder
    in its place, PermissionError for a read-only folder, a FileError with errno None for a
    device or FIFO: each a FileError, a ValueError too; resume= of a missing file is a
    FileNotFoundError). resume=FILE continues such a
    run (the same vertices and faces; options, if given, must equal the checkpoint's, threads
    excepted) to the result the uninterrupted run gives, bit for bit, its log included
    (``shellcontract run --checkpoint/--resume``, whose checkpoints this reads and the other way
    round). ValueError for a checkpoint of another mesh, other options or another version, or
    whose face-list or weights file has changed since, saying which. Regions or weights given as
    arrays are not in the checkpoint: give the same ones again to resume (compared by their
    values: the regions as face sets with their strengths, the weights bit for bit).

    As ``shellcontract run --resume FILE``, resume=FILE without checkpoint= goes on saving to
    FILE, every checkpoint_every=N frames (by default as often as the checkpoint's run did) and
    when the run is cancelled; a FILE that cannot be written is a UserWarning, and the run saves
    nothing. checkpoint=OTHER saves there instead. While it runs, contract() holds the lock
    ``.FILE.lock`` beside each checkpoint it saves to or resumes from, as the CLI does: a second
    run naming one (another contract(), in this process or another, or a CLI run) is refused
    before any work, BlockingIOError ("another shellcontract run is saving to this checkpoint or
    resuming from it": a FileError, a ValueError too, as Python's own flock() refuses a lock
    held). The lock file is removed when contract() returns or raises, and by
    SIGTERM, SIGHUP or SIGUSR1 left at their default action (docs/design/output-safety.md).
    """
    options = dict(options)
    # The CLI's spelling of the options checked here, before the library sees them, is taken as
    # their Python name (the library's option table takes either for the others).
    for dashed in ("region-weights", "region-strengths", "checkpoint-every"):
        if dashed in options:
            name = dashed.replace("-", "_")
            if name in options:
                raise TypeError("contract() got {} and {}, the same option".format(name, dashed))
            options[name] = options.pop(dashed)
    every = options.get("checkpoint_every")
    if isinstance(every, str):
        # The CLI's --checkpoint-every text, as frames="2" is the CLI's --frames text.
        if number_text.integer(every) is None:
            raise ValueError("checkpoint_every: expected an integer >= 1, with checkpoint=FILE or "
                             "resume=FILE, got {!r}".format(every))
        options["checkpoint_every"] = number_text.integer(every)
    if faces is None:
        raise TypeError("faces must be an array-like of integers, got None")
    for name in ("region_at", "region-at"):
        refuse_masked(options.get(name), "region_at")
    if "lambda_" in options:  # `lambda` is a Python keyword: lambda_=0.5 works where lambda=0.5 cannot
        if "lambda" in options:
            raise TypeError("contract() got lambda and lambda_, the same option")
        options["lambda"] = options.pop("lambda_")
    strengths = options.pop("region_strengths", None)
    for name in ("regions", "region_weights"):
        if name in options and options[name] is None:
            del options[name]  # None: not given, the default
    weights_array = "region_weights" in options and not isinstance(options["region_weights"],
                                                                     (str, bytes, os.PathLike))
    if weights_array:
        options["region_weights"] = _weights(options["region_weights"])
    regions = options.get("regions")
    if regions is None or isinstance(regions, (str, os.PathLike)):
        if strengths is not None:
            raise ValueError("region_strengths needs regions given as face lists or labels "
                             "(a face-list file takes them as its 'S:' column)")
        return _given_arrays(Result(_core.contract(vertices, faces, callback=callback, stage=stage, **options)),
                             weights=weights_array)
    # Face lists (what regions() returns) or one label per face (-1 = none): handed to the
    # library as a temporary face-list file, the format `run --regions FILE` reads, with each
    # region's strength as its "S:" column.
    lists = _region_lists(regions, len(faces) if hasattr(faces, "__len__") else len(np.asarray(faces)))
    if not lists:
        # No region: run as "none", warned as a file that lists none is, but naming the argument
        # (an empty temporary file would be named in the warning instead).
        if strengths is not None:
            _strengths(strengths, 0)
        result = Result(_core.contract(vertices, faces, callback=callback, stage=stage, **dict(options, regions="none")))
        warnings = result.summary.setdefault("warnings", [])
        # As the library warns of an empty face-list file: not when the regions are only measured,
        # and once (an aniso option's warning already says no region was given).
        if not options.get("measure_regions") and not any("no region" in w for w in warnings):
            warnings.append("regions: the list holds no region: the local contraction has no effect")
        return result
    prefixes = [""] * len(lists) if strengths is None else ["{!r}: ".format(s) for s in _strengths(strengths, len(lists))]
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "regions.txt")
        # Each region's faces in ascending order: the same regions give the same file whatever
        # the order they were listed in, and a checkpoint knows them by the file's hash.
        with open(path, "w") as f:
            f.write("".join(p + " ".join(str(int(i)) for i in np.sort(r)) + "\n" for p, r in zip(prefixes, lists)))
        result = Result(_core.contract(vertices, faces, callback=callback, stage=stage,
                                       **dict(options, regions=path, _regions_from_arrays=True)))
    return _given_arrays(result, regions=len(lists),
                         strengths=None if strengths is None else _strengths(strengths, len(lists)),
                         weights=weights_array, regions_file=path)


def _given_arrays(result, regions=None, strengths=None, weights=False, regions_file=None):
    """The summary's options and warnings say that regions or weights were arrays, not the
    temporary file the regions went through (deleted by now) or an empty weights file name."""
    given = "<{} regions given as arrays>".format(regions)
    warnings = result.summary.get("warnings")
    if regions_file is not None and isinstance(warnings, list):
        # The library names the face-list file it read ("regions FILE: every region's strength
        # is 0: ..."); the argument is named as for regions that hold no region.
        result.summary["warnings"] = [w.replace("regions " + regions_file + ":", "regions:")
                                      .replace(regions_file, given) for w in warnings]
    options = result.summary.get("options")
    if isinstance(options, dict):
        if regions is not None:
            options["regions"] = given
        if strengths is not None:
            options["region_strengths"] = list(strengths)
        if weights:
            options["region_weights"] = "<weights given as an array>"
    return result


# The frames() runs whose generator is still open: at exit, a suspended generator's worker waits
# in its callback for a consumer that will not come; _stop_frames_at_exit hands it its stop, before
# the module's own exit hook (registered earlier, so run later) waits for every run to end.
_live_frames = set()


def _finish_frames_run(stop, handoff, worker):
    stop.set()
    while worker.is_alive():  # unblock a pending put until the run has seen the stop
        try:
            handoff.get(timeout=0.05)
        except queue.Empty:
            pass
    worker.join()


@atexit.register
def _stop_frames_at_exit():
    for run in list(_live_frames):
        _finish_frames_run(*run)


def frames(vertices, faces, every=1, **options):
    """Runs ``contract`` and yields (frame, vertices, metrics) at every ``every``-th frame.

    The run goes on in a worker thread, one frame ahead at most; the generator's return value
    (StopIteration.value, or ``result = yield from frames(...)``) is the Result. Closing the
    generator early cancels the run.
    """
    if "callback" in options:
        raise TypeError("frames() takes no callback: it yields the frames (contract() takes one)")
    if isinstance(every, bool) or not isinstance(every, numbers.Integral):
        raise TypeError("every must be an integer, got {}".format(type(every).__name__))
    if every < 1:
        raise ValueError("every must be >= 1, got {}".format(every))
    handoff = queue.Queue(maxsize=1)
    stop = threading.Event()

    def on_frame(frame, v, metrics):
        if stop.is_set():
            return False
        if frame % every == 0:
            handoff.put(("frame", (frame, v, metrics)))
        return not stop.is_set()

    def work():
        try:
            handoff.put(("done", contract(vertices, faces, callback=on_frame, **options)))
        except BaseException as e:  # handed to the consumer, raised there
            handoff.put(("error", e))

    worker = threading.Thread(target=work, name="shellcontract.frames", daemon=True)
    run = (stop, handoff, worker)
    _live_frames.add(run)
    worker.start()
    try:
        while True:
            kind, payload = handoff.get()
            if kind == "frame":
                yield payload
            elif kind == "done":
                return payload
            else:
                raise payload
    finally:
        _finish_frames_run(stop, handoff, worker)
        _live_frames.discard(run)


def check(vertices, faces):
    """What ``shellcontract check`` reports (counts, genus, volume, self-intersecting face pairs:
    ``self_intersecting_pairs`` counts them all, ``self_intersections`` holds the first 1000 in
    face order, and ``self_intersections_truncated`` says whether it leaves some out, as ``check
    --json``; a mesh whose parts pass through each other has pairs in the square of its faces);
    raises ValueError with the reason when the mesh cannot be used (MeshError, with ``faces``,
    where particular faces are to blame)."""
    return _core.check(vertices, faces)


def regions(vertices, faces, **region_options):
    """The spherical regions ``--regions auto`` would choose: a list of face-index arrays, largest
    region first. Options: those of ``shellcontract regions`` (``fit_tolerance``, ``contrast``,
    ``max_area_fraction``, ... with '_' or '-'; ``min_faces`` from 1 to 2**31 - 1), their numbers
    given as contract()'s are (an int or a float, numpy's too, a whole float such as 3.0 for
    min_faces, or a str of the CLI's text, "0.5"; a bool is a TypeError); ``region_at``
    picks the caps around points instead, in the forms and with the errors of contract()'s
    region_at (one point, a list or array of points, or 'X,Y,Z' text). A region_at point farther
    from the surface than 1.5 % of the bounding box's diagonal is a UserWarning naming the surface
    point taken (contract(region_at=...): a warning in its summary). Other Python threads run
    during the search; Ctrl-C stops it within a fraction of a second (as during contract()'s own
    region search) and raises KeyboardInterrupt."""
    for name in ("region_at", "region-at"):
        refuse_masked(region_options.get(name), "region_at")
    return _core.regions(vertices, faces, **number_text.region_numbers(region_options))


def read_mesh(path):
    """Reads OFF/OBJ/PLY/STL with the CLI's checks; returns (vertices, faces): the triangles as
    the run takes them, polygons split and a component that is inside out turned outward (so a
    file's face order or corner order may differ; write_mesh's `like` keeps the file's own).
    A file that cannot be opened raises its OSError (FileNotFoundError, IsADirectoryError,
    PermissionError, ...: a FileError, a ValueError too; for a glTF's missing or unreadable
    external buffer, about the buffer; a device or FIFO: a FileError with errno None); one whose
    content is refused raises
    ValueError (MeshError, with ``faces``, where particular faces are to blame); one too large
    for the memory there is raises MemoryError ("FILE: out of memory: reading it needs more
    memory than there is (...)", the CLI's exit code 3). Other Python threads run while the file
    is read and checked."""
    return _core.read_mesh(path)  # str or os.PathLike; TypeError otherwise


def write_mesh(path, vertices, faces, like=None):
    """Writes OFF/OBJ/PLY/STL (by extension; with ``like``, also .glb or .gltf) atomically, as
    the CLI writes its -o output. The
    mesh must pass the same checks as an input (closed, manifold, no isolated vertex: MeshError
    or ValueError otherwise), so that what is written can be read back. An STL keeps no vertex
    identity (its readers merge equal positions): a mesh with two vertices at one position is a
    ValueError there (write .off, .obj or .ply).
    like: the OBJ, PLY, .glb or .gltf file that read_mesh read `faces` from; the output, a file
    of like's format, is then that file with the new positions (UVs, normals, groups,
    materials, polygons, extra properties, a glTF's scene kept), each written in the file's own
    type: a position its type cannot hold (beyond a float32's range, a whole mesh below the
    smallest normal float32, an integer type's range) is a ValueError naming the vertex. An
    OFF or STL like, or an output of another format, is a ValueError.
    A file that cannot be written raises its OSError (FileNotFoundError for a missing folder,
    PermissionError for a read-only one, IsADirectoryError for a folder in its place, a
    FileError with errno None for a device, FIFO or socket in its place, another OSError for a
    full disk: a FileError, a ValueError too). Other Python threads run while the file is
    written."""
    _core.write_mesh(path, vertices, faces, like)  # str or os.PathLike (or None)
