"""The run, apart from Blender's data: finding the module, the schedules of keyframed settings,
and a job that runs shellcontract.contract in a thread and keeps the frames for the shape keys.
No bpy here, so that it can be read and tested on its own."""

import math
import os
import re
import struct
import sys
import threading
import time


class AddonError(Exception):
    """A problem the user can fix (shown as an error report, nothing on the object changes)."""


def import_shellcontract(module_path=""):
    """The shellcontract module: from sys.path, `module_path` or SHELLCONTRACT_PYTHONPATH."""
    for path in (module_path, os.environ.get("SHELLCONTRACT_PYTHONPATH", "")):
        path = bpy_abspath(path)
        if path and os.path.isdir(path) and path not in sys.path:
            sys.path.insert(0, path)
    try:
        import shellcontract
    except ImportError as e:
        raise AddonError(
            "cannot import the shellcontract module ({}): set Edit > Preferences > Add-ons > "
            "ShellContract > Module path to the folder that holds it (the project's "
            "build/python), or SHELLCONTRACT_PYTHONPATH".format(e)) from e
    return shellcontract


def bpy_abspath(path):
    """Blender's '//' relative paths, when bpy is there; other paths unchanged."""
    if not path:
        return ""
    try:
        import bpy
        return os.path.normpath(bpy.path.abspath(path))
    except ImportError:
        return os.path.normpath(path)


def float32_text(value):
    """The shortest text of a float32 setting (Blender stores FloatProperty values and keyframe
    values as float32): 0.6, not 0.6000000238418579 -- what the user typed, and what the run
    is given, so that its record reads the same."""
    f = struct.unpack("f", struct.pack("f", value))[0]
    if not math.isfinite(f):
        return repr(f)
    for digits in range(1, 10):
        text = "{:.{}g}".format(f, digits)
        if struct.unpack("f", struct.pack("f", float(text)))[0] == f:
            return text
    return repr(f)


def frame_text(frame):
    """A timeline frame as Blender shows it: 41, or 40.5 for a key between frames."""
    return "{:g}".format(frame)


# The library's rules for the two keyframable settings (docs/design/keyframes.md): an unkeyed
# target volume is a V/V0 in [0, 1) held after a ramp, 0 = off (the pressure decides); keys are
# in (0, 2], and at simulation frame 0 (the scene's start frame) the shell is at its rest volume,
# so a key there is 1 (a later first key is reached from 1). Keyed pressures are in
# [-1e6, 1e6], as the Pressure field. Checked here so that a refusal speaks the panel's terms.
MAX_KEYED_VOLUME = 2.0
MAX_PRESSURE = 1e6


def unkeyed_target_volume(value):
    """The Target volume field's value for the run (0 = off) or AddonError."""
    v = float(float32_text(value))
    if not (0.0 <= v < 1.0):
        raise AddonError(
            "Target volume {}: without keyframes it is a V/V0 below 1, reached and held (0 = "
            "off: the Pressure decides); to re-inflate to 1 or above (at most {}), keyframe "
            "it".format(float32_text(value), float32_text(MAX_KEYED_VOLUME)))
    return v


def schedule_keys(keys, start, field):
    """(simulation frame, value) of the keyframes (timeline frame, value) of a setting,
    simulation frame = timeline frame - the scene's start frame (a key between frames on the
    nearest, a half frame on the later), values as float32 shows them.
    A key before the start, or two keys on one frame, is an AddonError in timeline frames."""
    out = []
    previous = None
    for frame, value in sorted(keys):
        # The nearest frame, a half frame to the later one: Python's round() goes to the even
        # one, so keys at 10.5 and 11.5 fell on one frame while 11.5 and 12.5 did not.
        sim_frame = int(math.floor(frame - start + 0.5))
        if sim_frame < 0:
            raise AddonError("{}: the key at frame {} comes before the scene's start frame {}, "
                             "where the run starts; move it to frame {} or later".format(
                                 field, frame_text(frame), start, start))
        if previous is not None and sim_frame == out[-1][0]:
            raise AddonError("{}: the keys at frames {} and {} fall on the same frame {} (the "
                             "run takes one value per frame); move one of them".format(
                                 field, frame_text(previous), frame_text(frame),
                                 start + sim_frame))
        previous = frame
        out.append((sim_frame, float(float32_text(value))))
    return out


def target_volume_schedule(keys, start):
    """The run's target_volume text 'F:V, ...' for the Target volume's keyframes, or
    AddonError naming the key by its timeline frame."""
    pairs = schedule_keys(keys, start, "Target volume")
    for sim_frame, v in pairs:
        if not (0.0 < v <= MAX_KEYED_VOLUME):
            raise AddonError(
                "Target volume: the key at frame {} is {}; a keyed Target volume is a V/V0 above "
                "0 and at most {} (0 = off is for a Target volume without keys)".format(
                    start + sim_frame, float32_text(v), float32_text(MAX_KEYED_VOLUME)))
    if pairs[0][0] == 0 and pairs[0][1] != 1.0:
        raise AddonError(
            "Target volume: the key at frame {} (the scene's start frame) is {}; the run starts "
            "at the rest volume, V/V0 = 1, so a key there must be 1 (or key a later frame "
            "only: the run goes there from 1)".format(start, float32_text(pairs[0][1])))
    return schedule_text(pairs)


def pressure_schedule(keys, start):
    """The run's pressure text 'F:P, ...' for the Pressure's keyframes, or AddonError."""
    pairs = schedule_keys(keys, start, "Pressure")
    for sim_frame, v in pairs:
        if not (-MAX_PRESSURE <= v <= MAX_PRESSURE):
            raise AddonError("Pressure: the key at frame {} is {}; a Pressure is between {} and "
                             "{}".format(start + sim_frame, float32_text(v),
                                         float32_text(-MAX_PRESSURE), float32_text(MAX_PRESSURE)))
    return schedule_text(pairs)


def schedule_text(pairs):
    return ", ".join("{}:{}".format(f, float32_text(v)) for f, v in pairs)


# The panel's names of the options the add-on passes, for the library's messages (which name
# them as Python does).
FIELD_NAMES = {
    "target_volume": "Target volume",
    "pressure": "Pressure",
    "frames": "Frames",
    "thickness": "Thickness",
    "collisions": "Collisions",
    "region_weights": "Region group",
    "region_shrink": "Region shrink",
}

# The library's warning that the explicit pressure raised vertex masses (docs/design/defaults.md,
# "Mass scaling"), which speaks of its time step `dt` and of `frames` for the same time: the
# panel has no dt, and its frames are steps of a fixed length. Read loosely, so that a change of
# the library's wording leaves its text as it is rather than losing the numbers.
_MASS_SCALING = re.compile(
    r"^(\d+) of (\d+) vertices \(([^)]*)\) are too light for the explicit pressure\b.*?"
    r"masses were raised, up to (\S+) times\b", re.S)

_KEY_AFTER_END = re.compile(
    r"^(\w+): the key at frame (\d+) comes after the last frame \((\d+)\); the run ends on "
    r"the schedule's value there, (\S+)$")


# The library's messages of a run that failed or fell short name simulation frames, and steps
# (step n makes frame n from frame n - 1): "the volume stalled ... at frame 149", "the frames ran
# out at V/V0 0.9 (frame 5)", "new self-intersecting face pairs at frame 7", "blow-up at step 9",
# "out of memory checking step 3". The panel's frames are timeline frames, start + n.
_RUN_FRAME = re.compile(r"(\bat frame|\(frame) (\d+)\b")
_RUN_STEP = re.compile(r"\b(at|checking|after) step (\d+)\b")
# A target the run fell short of: "target volume 0.3000 not reached: ...", the field's name.
_TARGET_NOT_REACHED = re.compile(r"^target volume (?=\S+ not reached\b)")


def run_frames(text, start):
    """A library message's simulation frames and steps as timeline frames (start + n)."""
    text = _RUN_FRAME.sub(lambda m: "{} {}".format(m.group(1), start + int(m.group(2))), text)
    return _RUN_STEP.sub(
        lambda m: "{} the step to frame {}".format(m.group(1), start + int(m.group(2))), text)


def addon_terms(message, start, mesh_name="", polygon_of=None, triangles=None, positions=None):
    """A message of the library (an error, a warning, or the failure of a run that ended early
    or short of its target) in the add-on's terms: the panel's field names, timeline frames
    (scene start + simulation frame, and a step as the frame it makes), rounded values; a mesh
    problem names the object's mesh, not 'input arrays', and its face numbers are the mesh's
    faces (polygons, as the Spreadsheet numbers them), not the loop triangles the run was given
    (polygon_of[t]: the polygon of triangle t), and so are its counts of faces where the text
    is rewritten (`triangles` and `positions`, the run's input, let a component's faces be
    counted). Vertex numbers are the mesh's own already."""
    text = str(message)
    m = _MASS_SCALING.match(text)
    if m:
        # What the artist can do first: the panel's fields, not the library's dt.
        return ("Pressure: set it to 0, with a Target volume, to contract without the pressure's "
                "explicit load: under it {} of {} vertices ({}) were too light, and their masses "
                "were raised, up to {} times, which changes how they move "
                "(docs/design/defaults.md, \"Mass scaling\"); more Frames do not change that (a "
                "frame is one time step of a fixed length)".format(*m.groups()))
    m = _KEY_AFTER_END.match(text)
    if m and m.group(1) in FIELD_NAMES:
        return ("{}: the key at frame {} comes after the run's last frame {}; the "
                "run ends on the way to it, at {:.4g}".format(
                    FIELD_NAMES[m.group(1)], start + int(m.group(2)), start + int(m.group(3)),
                    float(m.group(4))))
    faces = getattr(message, "faces", None)  # shellcontract.MeshError: the triangles to blame
    if polygon_of is not None and isinstance(faces, list) and faces:
        text = face_error_text(text, faces, polygon_of, mesh_name)
    else:
        if text.startswith(ARRAY_INPUT + ": "):
            text = "the mesh of {}: {}".format(mesh_name, text[len(ARRAY_INPUT) + 2:])
        if polygon_of is not None:
            # Warnings (text only) and errors without a face list: the numbers in the text.
            text = polygon_numbers(text, polygon_of, triangles, positions)
    text = _TARGET_NOT_REACHED.sub("Target volume ", run_frames(text, start))
    # A message that begins with an option's name, and the underscore names anywhere.
    head = re.match(r"^(\w+)(:| has no effect)", text)
    if head and head.group(1) in FIELD_NAMES:
        text = FIELD_NAMES[head.group(1)] + text[len(head.group(1)):]
    for name, field in FIELD_NAMES.items():
        if "_" in name:
            text = re.sub(r"\b{}\b".format(name), field, text)
    return text


ARRAY_INPUT = "input arrays"  # the library's name of a mesh given as arrays


def mesh_faces(faces, polygon_of):
    """The mesh's faces (polygons) of triangles `faces`, each once, in the order given."""
    out = []
    for t in faces:
        t = int(t)
        p = polygon_of[t] if 0 <= t < len(polygon_of) else t
        if p not in out:
            out.append(p)
    return out


def face_error_text(text, faces, polygon_of, mesh_name):
    """A MeshError's message, built from its `faces` (triangle numbers, all of them) mapped to
    the mesh's faces, not from the numbers in its text: 'the mesh of NAME: PROBLEM: face P'
    (or 'faces P1, P2'), then the library's own words, which count the run's triangles."""
    polygons = mesh_faces(faces, polygon_of)
    where = "face" if len(polygons) == 1 else "faces"
    where += " " + ", ".join(str(p) for p in polygons)
    rest = text[len(ARRAY_INPUT) + 2:] if text.startswith(ARRAY_INPUT + ": ") else text
    problem, sep, details = rest.partition(": ")
    if not sep:  # no "PROBLEM: details" form: the whole text is the library's words
        problem, details = "", rest
    head = "the mesh of {}: ".format(mesh_name) + (problem + ": " if problem else "") + where
    return "{} (the library's words, numbering the triangles the run was given: {})".format(head, details)


def component_triangles(first, triangles, positions=None):
    """The triangles of the connected part (edge-connected, as the library's components) that
    holds triangle `first`. Where the triangles as given have an open edge, the vertices at
    bitwise-identical positions count as one, as the library's seam weld makes them
    (src/mesh/seam_weld.hpp), so that a part split along UV seams is one part here too."""
    tris = [tuple(int(i) for i in t) for t in triangles]
    ids = {}

    def edges(t):
        return (tuple(sorted((t[0], t[1]))), tuple(sorted((t[1], t[2]))),
                tuple(sorted((t[2], t[0]))))

    count = {}
    for t in tris:
        for e in edges(t):
            count[e] = count.get(e, 0) + 1
    if positions is not None and any(n == 1 for n in count.values()):
        same = {}
        ids = {v: same.setdefault(struct.pack("3d", *(float(c) for c in positions[v])), v)
               for t in tris for v in t}
    by_edge = {}
    for f, t in enumerate(tris):
        for e in edges(tuple(ids.get(v, v) for v in t)):
            by_edge.setdefault(e, []).append(f)
    part, todo = {first}, [first]
    while todo:
        t = tuple(ids.get(v, v) for v in tris[todo.pop()])
        for e in edges(t):
            for g in by_edge[e]:
                if g not in part:
                    part.add(g)
                    todo.append(g)
    return part


def polygon_numbers(text, polygon_of, triangles=None, positions=None):
    """The triangle numbers of a mesh message as the mesh's face (polygon) numbers: 'face T',
    'N faces (T1, T2, ...)' and 'faces have (nearly) zero area: T1, T2, ...', with their counts
    of faces in the mesh's faces too: a list given whole is counted ('1 face has' for one); a
    cut one ('...') keeps the library's count, which is of triangles, and says so; an inside-out
    'component C (N faces, starting at face T)' counts the faces of T's part, from `triangles`
    (and `positions`, for a mesh split along seams), or says 'N triangles' without them. For the
    library's warnings, which are text only, and errors without a face list; a MeshError's faces
    come from its `faces` (face_error_text)."""
    def poly(t):
        t = int(t)
        return str(polygon_of[t]) if 0 <= t < len(polygon_of) else str(t)

    def component(m):
        first = int(m.group(3))
        if triangles is None or not 0 <= first < len(triangles):
            count = "{} triangle{}".format(m.group(2), "" if m.group(2) == "1" else "s")
        else:
            n = len({polygon_of[t] for t in component_triangles(first, triangles, positions)
                     if 0 <= t < len(polygon_of)})
            count = "{} face{}".format(n, "" if n == 1 else "s")
        return "component {} ({}, starting at face {})".format(m.group(1), count, poly(first))

    def zero_area(m):
        listed_faces = listed(m.group(3), True)
        if m.group(3).endswith("..."):
            return "{} triangle{} (nearly) zero area, in faces: {}".format(
                m.group(1), " has" if m.group(1) == "1" else "s have", listed_faces)
        n = len(listed_faces.split(", "))
        return "{} {} (nearly) zero area: {}".format(
            n, "face has" if n == 1 else "faces have", listed_faces)

    def listed(numbers, once=False):  # once: each face once (its triangles are listed apart)
        out = []
        for item in numbers.split(", "):
            p = poly(item) if item.isdigit() else item
            if not (once and p in out):
                out.append(p)
        return ", ".join(out)

    numbers = r"((?:\d+|\.\.\.)(?:, (?:\d+|\.\.\.))*)"
    # The counted forms first: their 'face T' is rewritten with them, not again below.
    text = re.sub(r"\bcomponent (\d+) \((\d+) faces?, starting at face (\d+)\)", component, text)
    text = re.sub(r"\b(\d+) (faces have|face has) \(nearly\) zero area: " + numbers, zero_area,
                  text)
    text = re.sub(r"(?<!starting at )\bface (\d+)\b", lambda m: "face " + poly(m.group(1)), text)
    text = re.sub(r"\bfaces \(" + numbers + r"\)", lambda m: "faces (" + listed(m.group(1)) + ")",
                  text)
    return text


def kept_frames(frames, step):
    """The simulation frames that become shape keys: every `step`-th, and the last."""
    kept = list(range(step, frames + 1, step))
    if not kept or kept[-1] != frames:
        kept.append(frames)
    return kept


class Job:
    """One run of shellcontract.contract, in the caller's thread (run) or a worker (start).

    progress: the last frame done; frames: {frame: positions} for the kept frames; cancel():
    the run stops after the current step (status "cancelled")."""

    def __init__(self, module, vertices, faces, options, keep, polygon_of=None):
        self.module = module
        self.vertices = vertices
        self.faces = faces
        self.polygon_of = polygon_of  # the mesh's polygon of each triangle, for messages
        self.options = options
        self.keep = set(keep)
        self.progress = 0
        self.frames = {}
        self.result = None
        self.error = None
        self.space = None  # the 3x3 map of the run's coordinates (placement.run_space), or None
        self.start_frame = None  # the scene's start frame when the run was prepared
        self.addon_warnings = []  # the add-on's own, shown with the library's
        self.interrupted = False  # stopped by Ctrl-C (interrupt.CtrlC), not by cancel()
        self.frame_count = options.get("frames")
        self._cancel = threading.Event()
        self._thread = None
        self._lines = None  # (name, seconds, stream, note) of progress_lines
        self._next_line = 0.0

    def progress_lines(self, name, seconds, stream=None, note=""):
        """Print 'ShellContract: NAME: frame N of M (NOTE)' every `seconds` during the run (to
        stdout, or `stream`): blender -b has no status bar, and a long bake was silent to its
        end."""
        self._lines = (name, seconds, stream, " ({})".format(note) if note else "")
        self._next_line = time.monotonic() + seconds

    def _on_frame(self, frame, vertices, metrics):
        self.progress = frame
        if frame in self.keep:
            self.frames[frame] = vertices.copy()
        if self._lines is not None and time.monotonic() >= self._next_line:
            name, seconds, stream, note = self._lines
            stream = stream or sys.stdout
            stream.write("ShellContract: {}: frame {} of {}{}\n".format(
                name, frame, self.frame_count, note))
            stream.flush()
            self._next_line = time.monotonic() + seconds
        return not self._cancel.is_set()

    def run(self):
        try:
            self.result = self.module.contract(self.vertices, self.faces, callback=self._on_frame,
                                               **self.options)
        except BaseException as e:  # shown to the user by the operator
            self.error = e

    def start(self):
        self._thread = threading.Thread(target=self.run, name="shellcontract", daemon=True)
        self._thread.start()

    def done(self):
        return self._thread is None or not self._thread.is_alive()

    def cancel(self):
        self._cancel.set()

    def join(self):
        if self._thread is not None:
            self._thread.join()
