"""The run, apart from Blender's data: finding the module, the schedules of keyframed settings,
and a job that runs shellcontract.contract in a thread and keeps the frames for the shape keys.
No bpy here, so that it can be read and tested on its own."""

import os
import sys
import threading


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


def schedule_text(keys, start, name):
    """'F:V, ...' for the keyframes (timeline frame, value) of a setting, simulation frame =
    timeline frame - start. A key before the start has no simulation frame: AddonError."""
    parts = []
    for frame, value in sorted(keys):
        sim_frame = int(round(frame - start))
        if sim_frame < 0:
            raise AddonError("{}: the key at frame {:g} comes before the scene's start frame {} "
                             "(simulation frame 0)".format(name, frame, start))
        parts.append("{}:{!r}".format(sim_frame, float(value)))
    return ", ".join(parts)


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

    def __init__(self, module, vertices, faces, options, keep):
        self.module = module
        self.vertices = vertices
        self.faces = faces
        self.options = options
        self.keep = set(keep)
        self.progress = 0
        self.frames = {}
        self.result = None
        self.error = None
        self._cancel = threading.Event()
        self._thread = None

    def _on_frame(self, frame, vertices, metrics):
        self.progress = frame
        if frame in self.keep:
            self.frames[frame] = vertices.copy()
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
