"""bpy.ops.object.shellcontract_contract: the run of the active mesh, written as shape keys."""

import re

import bpy
import numpy as np

from . import curves, interrupt, placement, runner

KEY_PREFIX = "shellcontract "
# The names the add-on gives its keys, "shellcontract 00042" (the simulation frame, 5 digits or
# more), and their F-curves' paths: only these are the add-on's to replace. A key of the user's
# whose name merely begins the same way (a result kept as "shellcontract final (keep)") is theirs.
_RESULT_KEY = re.compile(re.escape(KEY_PREFIX) + r"\d{5,}")
_RESULT_FCURVE = re.compile(r'key_blocks\["' + _RESULT_KEY.pattern + r'"\]\..+')


def is_result_key(name):
    """Whether a shape key's name is one the add-on gives its result keys."""
    return _RESULT_KEY.fullmatch(name) is not None

# The runs in progress, by object (run_key) -> Job: kept here, not on the object, so that a file
# saved (or a Blender that crashed) during a run does not come back with a run that no longer
# exists.
RUNNING = {}


def run_key(obj):
    """The key of the object's run in RUNNING: the object's address, not its name, so that a
    rename during a run neither loses the result nor lets a second run start."""
    return obj.as_pointer()


def object_of(key):
    """The object of a run_key, or None when it is gone (deleted)."""
    for obj in bpy.data.objects:
        if obj.as_pointer() == key:
            return obj
    return None


# Under blender -b a run prints its progress every this many seconds (a short run prints nothing).
PROGRESS_SECONDS = 10.0

# Edit Mode keeps its own copy of the mesh: the module would read the positions from before the
# edits, and shape keys written now are replaced by the edit copy's (without them) when it ends.
EDIT_MODE = ("the object is in Edit Mode; switch to Object Mode (Tab) first: shape keys written in "
             "Edit Mode are lost when it ends")


def _preferences(context):
    addon = context.preferences.addons.get(__package__)
    return addon.preferences if addon else None


def _default(settings, prop):
    """The property's default, as declared in properties.py."""
    return settings.bl_rna.properties[prop].default


def mesh_arrays(obj):
    """Vertices (local coordinates, the base shape's) and triangles of the object's mesh: the
    loop triangles, so quads and n-gons stay as they are in Blender, and the shape keys move the
    mesh's own vertices; and the polygon of each triangle (the library's messages number the
    triangles, the add-on's the mesh's faces).

    With shape keys the base is the reference key (the first, the Basis), not mesh.vertices:
    Blender shows the reference key's positions, the result keys are relative to it, and the two
    can differ (a key moved to the top of the list becomes the reference without the vertices
    changing; a script may set vertices.co under existing keys)."""
    mesh = obj.data
    vertices = np.empty(len(mesh.vertices) * 3, dtype=np.float64)
    if mesh.shape_keys is not None and len(mesh.shape_keys.key_blocks) > 0:
        mesh.shape_keys.reference_key.data.foreach_get("co", vertices)
    else:
        mesh.vertices.foreach_get("co", vertices)
    mesh.calc_loop_triangles()
    faces = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int64)
    mesh.loop_triangles.foreach_get("vertices", faces)
    polygon_of = np.empty(len(mesh.loop_triangles), dtype=np.int64)
    mesh.loop_triangles.foreach_get("polygon_index", polygon_of)
    return vertices.reshape(-1, 3), faces.reshape(-1, 3), polygon_of.tolist()


def _value_animation(keys, kb):
    """How the key's value is animated: 'driven' (a driver that plays), 'keyed' (an F-curve
    that plays and leaves 0 somewhere: a key, or modifiers that may), 'keyed to 0' (played, 0 at
    every key), or '' (not animated: the slider's value is what plays). The active action and
    the actions of NLA tracks that play are read: Blender plays them all."""
    ad = keys.animation_data
    if ad is None:
        return ""
    path = 'key_blocks["{}"].value'.format(bpy.utils.escape_identifier(kb.name))
    for d in ad.drivers:
        if d.data_path == path and not d.mute:
            return "driven"
    actions = [ad.action] if ad.action is not None else []
    actions += [strip.action for track in ad.nla_tracks if not track.mute
                for strip in track.strips if not strip.mute and strip.action is not None]
    found = ""
    for action in actions:
        fc = action.fcurves.find(path)
        if fc is None or fc.mute:
            continue
        if len(fc.modifiers) > 0 or any(kp.co[1] != 0.0 for kp in fc.keyframe_points):
            return "keyed"
        found = "keyed to 0"
    return found


def active_shape_keys(obj):
    """The object's shape keys that change what Blender shows over the Basis (the reference
    key) during the animation, as "'Name' (value)" or "'Name' (keyed)"/"(driven)". Not counted:
    the add-on's own keys (is_result_key: a new run replaces them), muted keys, keys at 0 that are
    not animated off it, and keys whose positions are those of their Relative To key (a key
    relative to itself adds nothing at any value)."""
    keys = obj.data.shape_keys
    if keys is None:
        return []
    blocks = keys.key_blocks
    out = []
    for kb in blocks[1:]:
        if is_result_key(kb.name) or kb.mute:
            continue
        animated = _value_animation(keys, kb)
        if animated == "keyed to 0" or (not animated and kb.value == 0.0):
            continue
        relative = kb.relative_key
        if relative == kb:
            continue
        co = np.empty(len(kb.data) * 3)
        kb.data.foreach_get("co", co)
        base = np.empty(len(relative.data) * 3)
        relative.data.foreach_get("co", base)
        if np.array_equal(co, base):
            continue
        out.append("'{}' ({})".format(kb.name, animated or runner.float32_text(kb.value)))
    return out


def shape_key_refusal(obj):
    """Why the run's keys would not show as the run made them, or ''. The run contracts the
    Basis and writes absolute positions as keys relative to it, so anything else Blender mixes in
    (another key that is on, absolute keys, the pin that shows one key alone) would make the
    shown shape, and its volume, differ from the run's and from the V/V0 it reports."""
    keys = obj.data.shape_keys
    if obj.show_only_shape_key:
        shown = obj.active_shape_key.name if obj.active_shape_key else "the Basis"
        return ("{} shows only the shape key '{}' (Shape Keys panel, the pin 'Shape Key Lock'), "
                "so the run's keys would not show; unpin it first".format(obj.name, shown))
    if keys is None:
        return ""
    if not keys.use_relative:
        return ("{}'s shape keys are absolute (Shape Keys panel, 'Relative' off): the run's keys "
                "are relative to the Basis; turn 'Relative' on first".format(obj.name))
    active = active_shape_keys(obj)
    if not active:
        return ""
    basis = keys.reference_key.name
    return ("shape key{} {} {} on: the run contracts the Basis ('{}') and {} would add on top "
            "of the run's keys, so the shape shown would not be the run's; set {} to 0, mute "
            "{}, or apply {} to the mesh first (Shape Keys panel > Shape Key Specials > Apply "
            "All Shape Keys, at the scene's start frame)".format(
                "s" if len(active) > 1 else "", ", ".join(active),
                "are" if len(active) > 1 else "is", basis,
                "they" if len(active) > 1 else "it", *(["them" if len(active) > 1 else "it"] * 3)))


def ngon_warning(obj):
    """The warning for a mesh with n-gons (faces of 5 or more corners), or ''. The run is given
    Blender's triangles of the mesh at rest, but Blender triangulates every n-gon again on every
    frame, from the shape the keys give it, and an n-gon's fan of long, thin triangles often
    comes out with other diagonals: the shape shown, and its volume, then differ from the run's
    far more than a quad's other diagonal makes them (a cylinder's caps)."""
    sizes = np.empty(len(obj.data.polygons), dtype=np.int64)
    obj.data.polygons.foreach_get("loop_total", sizes)
    ngons = int(np.count_nonzero(sizes >= 5))
    if ngons == 0:
        return ""
    return ("{} has {} n-gon{} (faces of 5 or more corners): Blender re-triangulates them on "
            "every frame, so the shape shown, and its volume, will differ from the run's and from "
            "the V/V0 reported; for a faithful result triangulate them first (Edit Mode, select "
            "all, Face > Triangulate Faces, Ctrl+T) and run again".format(
                obj.name, ngons, "" if ngons == 1 else "s"))


def modifier_hint(obj):
    """For a mesh the library refuses: the run contracts the mesh as stored, before the object's
    modifiers (they stay, on top of the animation), so a mesh that is closed only with them (half
    a mesh and a Mirror modifier) is refused as open with faces the user does not see missing. ''
    when the object has no modifier. It goes first in the message: the panel shows the status on
    one line, cut at the sidebar's width, and the library's text after it lists faces."""
    names = [m.name for m in obj.modifiers]
    if not names:
        return ""
    return ("the run takes {}'s mesh without its modifiers ({}): to contract what they make, "
            "apply them first (Object > Apply); ".format(obj.name, ", ".join(names)))


def vertex_group_weights(obj, name):
    group = obj.vertex_groups.get(name)
    if group is None:
        raise runner.AddonError("Region group '{}': {} has no such vertex group (it has: {})".format(
            name, obj.name, ", ".join(g.name for g in obj.vertex_groups) or "none"))
    weights = np.zeros(len(obj.data.vertices), dtype=np.float64)
    for v in obj.data.vertices:
        for g in v.groups:
            if g.group == group.index:
                weights[v.index] = g.weight
    return weights


def run_options(context, obj, start=None, warnings=None):
    """The contract() options of the object's settings, with keyframed settings as schedules
    (start: simulation frame 0, the scene's start frame unless given); the add-on's warnings
    about them go to `warnings`."""
    start = context.scene.frame_start if start is None else start
    warnings = [] if warnings is None else warnings
    s = obj.shellcontract
    options = {"frames": s.frames, "thickness": float(runner.float32_text(s.thickness)),
               "collisions": s.collisions}
    volume_curve = curves.fcurve_of(obj, "target_volume")
    if volume_curve is not None:
        options["target_volume"] = curves.target_volume_option(volume_curve, start, s.frames,
                                                              warnings)
    elif runner.unkeyed_target_volume(s.target_volume) > 0.0:
        options["target_volume"] = runner.unkeyed_target_volume(s.target_volume)
    # With a target volume (a number or keys) the volume constraint decides the volume and the
    # pressure only changes the way there (docs/math/volume-control.md). Passed only where the
    # user asked for it: keyed, set off its default, or with the target off, where it decides. The
    # default is the library's own (checked in addon_in_blender.py), so leaving it out at the
    # default runs the same.
    pressure_curve = curves.fcurve_of(obj, "pressure")
    target_on = "target_volume" in options
    if pressure_curve is not None:
        options["pressure"] = curves.pressure_option(pressure_curve, start, s.frames, warnings)
    elif not target_on or s.pressure != _default(s, "pressure"):
        options["pressure"] = float(runner.float32_text(s.pressure))
    if s.region_group:
        options["region_weights"] = vertex_group_weights(obj, s.region_group)
        options["region_shrink"] = float(runner.float32_text(s.region_shrink))
    return options


def write_shape_keys(context, obj, job, start):
    """One shape key per kept frame, keyed so that timeline frame start + n shows simulation
    frame n (linear blends between neighbouring keys); start is the scene's start frame when the
    run was prepared, which its schedules were read from. Earlier results of the add-on are
    replaced; the Basis and the object's other keys stay.

    An action that has other users (another object's Key: a mesh copied by a script, `c.data =
    a.data.copy()`, or Shift+D without Preferences > Editing > Duplicate Data > Action; an NLA
    strip; a fake user) is not edited: its F-curves play for them too, so this Key gets a copy of
    it first, and their animation stays as it was."""
    if obj.data.shape_keys is None:
        obj.shape_key_add(name="Basis", from_mix=False)
    keys = obj.data.shape_keys
    if keys.animation_data is None:
        keys.animation_data_create()
    ad = keys.animation_data
    if ad.action is None:
        ad.action = bpy.data.actions.new(obj.name + "ShellContract")
    elif ad.action.users > 1:
        ad.action = ad.action.copy()
    action = ad.action
    for kb in [kb for kb in keys.key_blocks if is_result_key(kb.name)]:
        obj.shape_key_remove(kb)
    # Removing a key leaves its F-curves behind.
    for fc in [fc for fc in action.fcurves if _RESULT_FCURVE.fullmatch(fc.data_path)]:
        action.fcurves.remove(fc)
    frames = sorted(job.frames)
    times = [start] + [start + n for n in frames]  # start: the rest state, the Basis
    for i, n in enumerate(frames):
        kb = obj.shape_key_add(name="{}{:05d}".format(KEY_PREFIX, n), from_mix=False)
        co = placement.from_run(job.space, job.frames[n])  # back to the mesh's coordinates
        kb.data.foreach_set("co", np.ascontiguousarray(co, dtype=np.float64).ravel())
        kb.value = 0.0
        points = [(times[i], 0.0), (times[i + 1], 1.0)]
        if i + 2 < len(times):
            points.append((times[i + 2], 0.0))
        fc = action.fcurves.new('key_blocks["{}"].value'.format(kb.name))
        fc.keyframe_points.add(len(points))
        fc.keyframe_points.foreach_set("co", [c for p in points for c in p])
        for kp in fc.keyframe_points:
            kp.interpolation = "LINEAR"
        fc.update()
    context.scene.frame_end = max(context.scene.frame_end, times[-1])
    obj.data.update()


class OBJECT_OT_shellcontract_contract(bpy.types.Operator):
    """Contract the active mesh like a thin elastic shell; the result becomes shape keys"""

    bl_idname = "object.shellcontract_contract"
    bl_label = "Contract"
    bl_options = {"REGISTER", "UNDO"}

    _timer = None
    _job = None

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        # Said, not Blender's bare "context is incorrect" (a script's RuntimeError, the tooltip).
        if obj is None:
            cls.poll_message_set("no active object: select a mesh object")
            return False
        if obj.type != "MESH":
            kind = obj.bl_rna.properties["type"].enum_items[obj.type].name  # "Empty", "Camera"
            cls.poll_message_set("{} is not a mesh ({}): select a mesh object".format(
                obj.name, kind))
            return False
        if run_key(obj) in RUNNING:
            cls.poll_message_set("{} is being contracted (Esc cancels the run)".format(obj.name))
            return False
        # Linked data cannot keep the run's keys; the reason shows in the button's tooltip and
        # in a script's error, as for Blender's own shape-key operators.
        refused = placement.library_refusal(obj)
        if refused:
            cls.poll_message_set(refused)
            return False
        return True

    def _prepare(self, context):
        obj = context.active_object
        refused = placement.library_refusal(obj)
        if refused:
            raise runner.AddonError(refused)
        if obj.mode == "EDIT":
            raise runner.AddonError(EDIT_MODE)
        refused = shape_key_refusal(obj)
        if refused:
            raise runner.AddonError(refused)
        prefs = _preferences(context)
        module = runner.import_shellcontract(prefs.module_path if prefs else "")
        space = placement.run_space(obj)
        vertices, faces, polygon_of = mesh_arrays(obj)
        start = context.scene.frame_start
        warnings = []
        options = run_options(context, obj, start, warnings)
        keep = runner.kept_frames(obj.shellcontract.frames, obj.shellcontract.frame_step)
        job = runner.Job(module, placement.to_run(space, vertices), faces, options, keep,
                         polygon_of)
        job.space = space  # the result is mapped back to the mesh's coordinates
        job.start_frame = start  # the schedules' frame 0; the keys are written from it
        job.addon_warnings = [w for w in [ngon_warning(obj)] + warnings if w]
        return obj, job

    def _refuse(self, context, error):
        """A run refused before it starts: the panel's status says why, as for a failed run, so
        that it does not keep showing the previous run's result (not on linked data, which
        cannot be changed)."""
        obj = context.active_object
        if obj.library is None:
            obj.shellcontract.status = "error: {}".format(error)
        self.report({"ERROR"}, "ShellContract: {}".format(error))
        return {"CANCELLED"}

    def _finish(self, context, obj, job):
        s = obj.shellcontract
        RUNNING.pop(run_key(obj), None)
        start = job.start_frame if job.start_frame is not None else context.scene.frame_start

        def terms(message):  # the library's message in the add-on's terms
            return runner.addon_terms(message, start, obj.name, job.polygon_of, job.faces,
                                      job.vertices)

        # Ctrl-C under blender -b (interrupt.CtrlC), or a KeyboardInterrupt from a handler of
        # Python's own (it has no text).
        if job.interrupted or isinstance(job.error, KeyboardInterrupt):
            s.status = "interrupted (Ctrl-C) at frame {}".format(start + job.progress)
            self.report({"WARNING"}, "ShellContract: {}; the object is unchanged".format(s.status))
            return {"CANCELLED"}
        if job.error is not None:
            error = terms(job.error) or type(job.error).__name__
            if isinstance(job.error, job.module.MeshError):
                error = modifier_hint(obj) + error
            s.status = "error: {}".format(error)
            self.report({"ERROR"}, "ShellContract: {}".format(error))
            return {"CANCELLED"}
        result = job.result
        if result.status == "cancelled":
            s.status = "cancelled at frame {}".format(start + job.progress)  # timeline frame
            self.report({"WARNING"}, "ShellContract: cancelled; the object is unchanged")
            return {"CANCELLED"}
        if result.summary["frames_run"] < 1:  # failed at its first step: nothing to key
            s.status = "no frame was run"
            self.report({"ERROR"}, "ShellContract: no frame was run ({}); the object is unchanged".format(
                terms(result.summary.get("failure") or result.status)))
            return {"CANCELLED"}
        if obj.mode == "EDIT":  # entered during a threaded run
            s.status = "not written: the object is in Edit Mode"
            self.report({"ERROR"}, "ShellContract: the result was not written: " + EDIT_MODE)
            return {"CANCELLED"}
        if len(obj.data.vertices) != len(result.vertices):  # edited during a threaded run
            s.status = "not written: the mesh was edited during the run"
            self.report({"ERROR"}, "ShellContract: the result was not written: the mesh has {} "
                        "vertices now, the run had {}; the object is unchanged".format(
                            len(obj.data.vertices), len(result.vertices)))
            return {"CANCELLED"}
        # The last frame is the result's own positions (a run may end early: a stall, a failure).
        job.frames[result.summary["frames_run"]] = result.vertices
        job.frames = {n: v for n, v in job.frames.items() if n <= result.summary["frames_run"]}
        write_shape_keys(context, obj, job, start)
        # The library's warnings (e.g. a vertex group whose weights are all 0: no region) go with
        # the status, so that an ineffective setting is not reported as a plain success.
        warnings = job.addon_warnings + [terms(w) for w in result.summary.get("warnings", [])]
        run = result.summary["frames_run"]
        s.status = "{}: {} frame{}, V/V0 {:.4f}".format(
            result.status, run, "" if run == 1 else "s",
            result.summary["final_volume_ratio"]) + "".join("; warning: " + w for w in warnings)
        obj["shellcontract_final_volume_ratio"] = result.summary["final_volume_ratio"]
        obj["shellcontract_regions"] = result.summary["regions"]
        level = {"INFO"} if result.status == "ok" and not warnings else {"WARNING"}
        self.report(level, "ShellContract: " + s.status +
                    ("" if result.status == "ok" else " ({})".format(
                        terms(result.summary["failure"]))))
        return {"FINISHED"}

    def execute(self, context):
        # Scripts and background mode (blender -b): the whole run, then the shape keys.
        try:
            obj, job = self._prepare(context)
        except (runner.AddonError, ValueError, TypeError) as e:
            return self._refuse(context, e)
        if not bpy.app.background:
            job.run()
            return self._finish(context, obj, job)
        # No window, no Esc, no status bar: Ctrl-C cancels (Blender's own handler would swallow
        # it) and a long run says how far it is on stdout.
        with interrupt.CtrlC(job.cancel) as ctrl_c:
            job.progress_lines(obj.name, PROGRESS_SECONDS,
                               note="Ctrl-C stops the run" if ctrl_c.active else "")
            job.run()
        job.interrupted = ctrl_c.interrupted
        return self._finish(context, obj, job)

    def invoke(self, context, event):
        if bpy.app.background:
            return self.execute(context)
        try:
            obj, job = self._prepare(context)
        except (runner.AddonError, ValueError, TypeError) as e:
            return self._refuse(context, e)
        self._obj_key = run_key(obj)
        self._obj_name = obj.name  # for the report when it is gone
        self._job = job
        RUNNING[self._obj_key] = job
        job.start()
        wm = context.window_manager
        wm.progress_begin(0, obj.shellcontract.frames)
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        obj = object_of(self._obj_key)
        job = self._job
        if event.type == "ESC" and event.value == "PRESS":
            job.cancel()
            return {"RUNNING_MODAL"}
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        wm = context.window_manager
        wm.progress_update(job.progress)
        frames = obj.shellcontract.frames if obj else 0
        context.workspace.status_text_set(
            "ShellContract: frame {} of {} (Esc cancels)".format(job.progress, frames))
        for area in context.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()
        if not job.done():
            return {"RUNNING_MODAL"}
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        if obj is None:  # deleted during the run (or an undo put another object in its place)
            RUNNING.pop(self._obj_key, None)
            self.report({"WARNING"}, "ShellContract: {} is gone (deleted during the run, or "
                        "replaced by an undo); the result was not written".format(self._obj_name))
            return {"CANCELLED"}
        return self._finish(context, obj, job)
