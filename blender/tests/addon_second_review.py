"""A technical artist's second review of the add-on: a shape-key action shared with another
object's Key is not edited (the Key gets its own copy); a mesh with n-gons is warned about (the
shape shown differs from the run's); a re-run replaces only the keys it names itself, not a
user's "shellcontract final (keep)"; the mass-scaling warning speaks the panel's terms (no dt,
what to do first); a scale of (0, 0, 0) is refused; the messages' details (a cancelled run's
timeline frame, "1 frame", a poll message for an object that is not a mesh); and the progress
lines of a background run. Ctrl-C under blender -b is checked apart, in a Blender of its own
(run_addon_test.py, addon_ctrl_c.py): it ends that Blender with 1."""

import io
import re
import types

import bpy
import numpy as np

from addon_helpers import check, key_positions, refusal


def _ico(name, subdivisions=2):
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=subdivisions, radius=1.0)
    obj = bpy.context.active_object
    obj.name = name
    return obj


def _animation(action):
    """An action's F-curves as (data path, keyframe positions), to compare before and after."""
    out = []
    for fc in action.fcurves:
        co = np.empty(len(fc.keyframe_points) * 2)
        fc.keyframe_points.foreach_get("co", co)
        out.append((fc.data_path, tuple(co)))
    return sorted(out)


def _shown(obj, frame):
    """The positions Blender shows of the object at timeline frame `frame` (its evaluated mesh)."""
    bpy.context.scene.frame_set(frame)
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", co)
    evaluated.to_mesh_clear()
    return co


def shared_action():
    """A copy made the common scripted way (`c.data = a.data.copy()`: the Key is copied, its
    action is not) is contracted: the original's animation, and what it shows, stay as they
    were; the copy gets an action of its own with its keys' F-curves only."""
    start = bpy.context.scene.frame_start
    a = _ico("Original")
    a.shellcontract.frames = 8
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}, "the original runs")
    action = a.data.shape_keys.animation_data.action
    before = _animation(action)
    shown = [_shown(a, start + n) for n in (0, 3, 8)]
    c = a.copy()
    c.data = a.data.copy()
    c.name = "Variant"
    bpy.context.collection.objects.link(c)
    check(c.data.shape_keys.animation_data.action == action and action.users == 2,
          "the copy's Key shares the original's action")
    bpy.context.view_layer.objects.active = c
    c.shellcontract.frames, c.shellcontract.frame_step, c.shellcontract.target_volume = 4, 1, 0.3
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}, "the copy runs: " +
          c.shellcontract.status)
    mine = c.data.shape_keys.animation_data.action
    check(a.data.shape_keys.animation_data.action == action and _animation(action) == before,
          "the original's action is as it was")
    check(all(np.array_equal(s, _shown(a, start + n)) for s, n in zip(shown, (0, 3, 8))),
          "the original shows what it showed")
    paths = {fc.data_path for fc in mine.fcurves}
    keys = {'key_blocks["{}"].value'.format(kb.name) for kb in c.data.shape_keys.key_blocks[1:]}
    check(mine != action and paths == keys and len(keys) == 4,
          "the copy has an action of its own, with its own keys' F-curves only: {}".format(
              sorted(paths)))
    bpy.data.objects.remove(a)
    bpy.data.objects.remove(c)


def user_key_kept():
    """A key of the user's whose name begins as the add-on's ("shellcontract final (keep)"),
    keyed, survives a re-run with its positions and its F-curve."""
    start = bpy.context.scene.frame_start
    obj = _ico("Kept")
    obj.shellcontract.frames = 6
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}, "the first run")
    last = key_positions(obj.data.shape_keys.key_blocks[-1])
    kept = obj.shape_key_add(name="shellcontract final (keep)", from_mix=False)
    kept.data.foreach_set("co", last.ravel())
    kept.value = 0.0
    kept.keyframe_insert("value", frame=start)  # keyed, at 0: not on, so the re-run goes ahead
    obj.shellcontract.frames = 4
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}, "the re-run: " +
          obj.shellcontract.status)
    blocks = obj.data.shape_keys.key_blocks
    action = obj.data.shape_keys.animation_data.action
    check("shellcontract final (keep)" in blocks
          and np.array_equal(key_positions(blocks["shellcontract final (keep)"]), last)
          and action.fcurves.find('key_blocks["shellcontract final (keep)"].value') is not None,
          "the user's key and its F-curve are kept: {}".format([kb.name for kb in blocks]))
    results = sorted(kb.name for kb in blocks if kb.name.startswith("shellcontract 0"))
    check(results == ["shellcontract 00002", "shellcontract 00004"]
          and len(action.fcurves) == len(results) + 1,
          "the earlier run's keys and F-curves are replaced: {}".format(results))
    bpy.data.objects.remove(obj)


def ngon_warning():
    """A cylinder with n-gon caps is warned about (Blender re-triangulates them on every frame);
    with triangle-fan caps, triangles already, it is not."""
    for fill, ngons in (("NGON", 2), ("TRIFAN", 0)):
        bpy.ops.mesh.primitive_cylinder_add(vertices=16, end_fill_type=fill)
        obj = bpy.context.active_object
        obj.shellcontract.frames = 3
        check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}, "the cylinder runs")
        status = obj.shellcontract.status
        if ngons:
            check("warning: {} has {} n-gons".format(obj.name, ngons) in status
                  and "Triangulate Faces" in status and "Ctrl+T" in status,
                  "n-gon caps are warned about, with how to triangulate: " + status)
        else:
            check("n-gon" not in status, "triangle caps: no n-gon warning: " + status)
        bpy.data.objects.remove(obj)


def mass_scaling_terms():
    """The library's mass-scaling warning (the pressure's explicit load made vertices too light
    at its dt) in the panel's terms: what to do first, no dt, which the panel has not."""
    obj = _ico("Heavy")
    s = obj.shellcontract
    s.target_volume, s.pressure, s.frames = 0.0, 50.0, 2
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}, "the run: " + s.status)
    warning = s.status.partition("; warning: ")[2]
    check(warning.startswith("Pressure: set it to 0, with a Target volume")
          and re.search(r"\bdt\b", warning) is None and "Frames" in warning
          and " of {} vertices".format(len(obj.data.vertices)) in warning,
          "the mass-scaling warning speaks the panel's terms, the fix first: " + warning)
    bpy.data.objects.remove(obj)


def zero_scale():
    """docs/blender.md: a scale of 0 along an axis is refused; along all three as well."""
    obj = _ico("Flat")
    obj.scale = (0.0, 0.0, 0.0)
    bpy.context.view_layer.update()
    text = refusal()
    check("Flat is scaled to 0 along an axis" in text and obj.data.shape_keys is None,
          "a scale of (0, 0, 0) is refused: " + text)
    bpy.data.objects.remove(obj)


def message_details():
    """A cancelled run names the timeline frame; one frame is '1 frame'; an object that is not
    a mesh gets a poll message that says so."""
    from shellcontract_blender import operator as op
    scene = bpy.context.scene
    old_start = scene.frame_start
    scene.frame_start = 10
    obj = _ico("Details")
    obj.shellcontract.frames = 50
    reports = []
    stub = types.SimpleNamespace(report=lambda level, text: reports.append(text))
    obj_, job = op.OBJECT_OT_shellcontract_contract._prepare(stub, bpy.context)
    job.cancel()  # before it starts: it stops after its first frame
    job.run()
    outcome = op.OBJECT_OT_shellcontract_contract._finish(stub, bpy.context, obj_, job)
    scene.frame_start = old_start
    check(outcome == {"CANCELLED"} and job.progress >= 1
          and obj.shellcontract.status == "cancelled at frame {}".format(10 + job.progress),
          "a cancelled run names the timeline frame: " + obj.shellcontract.status)
    obj.shellcontract.frames = 1
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}
          and re.match(r"^[a-z ]+: 1 frame, V/V0", obj.shellcontract.status) is not None,
          "one frame is '1 frame': " + obj.shellcontract.status)
    bpy.data.objects.remove(obj)
    bpy.ops.object.empty_add()
    empty = bpy.context.active_object
    text = refusal()
    check("is not a mesh (Empty): select a mesh object" in text,
          "an Empty gets a poll message: " + text)
    bpy.data.objects.remove(empty)
    bpy.context.view_layer.objects.active = None
    text = refusal()
    check("no active object: select a mesh object" in text, "no active object: " + text)


def progress_lines():
    """A background run's progress lines: 'ShellContract: NAME: frame N of M' (here one per
    frame; the operator prints one every PROGRESS_SECONDS)."""
    from shellcontract_blender import runner
    shellcontract = runner.import_shellcontract()
    obj = _ico("Lines", 1)
    co = np.empty(len(obj.data.vertices) * 3)
    obj.data.vertices.foreach_get("co", co)
    obj.data.calc_loop_triangles()
    faces = np.empty(len(obj.data.loop_triangles) * 3, dtype=np.int64)
    obj.data.loop_triangles.foreach_get("vertices", faces)
    job = runner.Job(shellcontract, co.reshape(-1, 3), faces.reshape(-1, 3), {"frames": 3},
                     keep=[])
    out = io.StringIO()
    job.progress_lines("Lines", 0.0, out)
    job.run()
    lines = out.getvalue().splitlines()
    check(job.error is None and [line.split(" (")[0] for line in lines] ==
          ["ShellContract: Lines: frame {} of 3".format(n) for n in (1, 2, 3)],
          "progress lines: {}".format(lines))
    bpy.data.objects.remove(obj)


def second_review():
    shared_action()
    user_key_kept()
    ngon_warning()
    mass_scaling_terms()
    zero_scale()
    message_details()
    progress_lines()
