"""A technical artist's review of the add-on (blender/tests, the add-on's acceptance): a linked
or overridden mesh is refused before the run (its keys would be lost on save); the run follows
the Target volume's F-curve as the timeline shows it (linear keys, a Cycles modifier), and the
default two Bezier keys still give the library the keys alone; an unapplied non-uniform scale
deflates as the same mesh with its scale applied; a rename during a threaded run neither loses
the result nor lets a second run start, a deleted object is reported, and the keys start from
the start frame read when the run began."""

import os
import tempfile
import types

import bpy
import numpy as np

from addon_helpers import check, key_positions, refusal, volume_of


def _sphere(name, segments=16, rings=8):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=segments, ring_count=rings, radius=1.0)
    obj = bpy.context.active_object
    obj.name = name
    return obj


def linked_meshes():
    """A sphere written to a library file, linked back, and overridden: both are refused, naming
    the library and Make Local, and no shape key is written."""
    lib_obj = _sphere("LibSphere")
    path = os.path.join(tempfile.mkdtemp(), "lib.blend")
    bpy.data.libraries.write(path, {lib_obj})
    bpy.data.objects.remove(lib_obj)
    with bpy.data.libraries.load(path, link=True) as (src, dst):
        dst.objects = ["LibSphere"]
    linked = dst.objects[0]
    bpy.context.collection.objects.link(linked)
    bpy.context.view_layer.objects.active = linked
    text = refusal()
    check("LibSphere is linked from lib.blend" in text and "Make Local" in text
          and linked.data.shape_keys is None,
          "a linked object is refused before the run, naming the library: " + text)
    override = linked.override_create(remap_local_usages=True)
    bpy.context.view_layer.objects.active = override
    text = refusal()
    check("the mesh of {} is linked from lib.blend".format(override.name) in text
          and "Make Local" in text and override.data.shape_keys is None,
          "a library override (its mesh linked) is refused before the run: " + text)
    # The mesh overridden as well: shape keys are not among an override's saved properties.
    override.data = override.data.override_create(remap_local_usages=False)
    text = refusal()
    check("the mesh of {} is a library override of lib.blend".format(override.name) in text
          and "Make Local" in text and override.data.shape_keys is None,
          "an overridden mesh is refused before the run: " + text)
    bpy.data.objects.remove(override)
    bpy.data.objects.remove(linked)


def _shown_ratios(obj, rest):
    """{simulation frame: V/V0 of its key} (frame_step 1)."""
    v0 = volume_of(obj, rest)
    return {int(kb.name.split()[-1]): volume_of(obj, key_positions(kb)) / v0
            for kb in obj.data.shape_keys.key_blocks[1:]}


def _keyed(obj, points, interpolation=None):
    start = bpy.context.scene.frame_start
    obj.animation_data_clear()
    for frame, value in points:
        obj.shellcontract.target_volume = value
        obj.keyframe_insert("shellcontract.target_volume", frame=start + frame)
    fc = obj.animation_data.action.fcurves.find("shellcontract.target_volume")
    if interpolation:
        for kp in fc.keyframe_points:
            kp.interpolation = interpolation
    return fc


def fcurve_shape():
    """The run's target follows the F-curve the timeline shows."""
    from shellcontract_blender import operator
    obj = _sphere("Curve")
    rest = np.array([v.co[:] for v in obj.data.vertices])
    s = obj.shellcontract
    s.frames, s.frame_step = 40, 1
    start = bpy.context.scene.frame_start
    # Two Bezier keys at Blender's default handles are the library's own smoothstep: the keys
    # alone are passed, as before, so the run is unchanged.
    _keyed(obj, [(0, 1.0), (20, 0.6)])
    check(operator.run_options(bpy.context, obj)["target_volume"] == "0:1, 20:0.6",
          "two default Bezier keys give the library the keys alone")
    # Linear keys: at frame 5 the curve is 0.9 (the smoothstep through the keys: 0.9375).
    _keyed(obj, [(0, 1.0), (20, 0.6)], "LINEAR")
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}, "linear keys run: " + s.status)
    r = _shown_ratios(obj, rest)
    check(abs(r[5] - 0.9) <= 0.01 and abs(r[20] - 0.6) <= 0.01,
          "linear keys: V/V0 {:.4f} at frame 5 (curve 0.9), {:.4f} at 20 (0.6)".format(r[5], r[20]))
    s.frames = 10
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}
          and "the key at frame {} comes after the run's last frame {}".format(start + 20,
                                                                            start + 10) in s.status,
          "a key after the last frame of a sampled curve is warned about: " + s.status)
    s.frames = 40
    # A handle pulled below 0: the curve leaves the field's range between keys in range.
    fc = _keyed(obj, [(0, 1.0), (10, 0.6), (20, 0.6)])
    kp = fc.keyframe_points[1]
    kp.handle_right_type = "FREE"
    kp.handle_right = (start + 13, -2.0)
    text = refusal()
    check("Target volume: the curve is" in text and "a keyed Target volume is a V/V0 above 0" in text,
          "a curve that leaves the range between keys is refused, naming the frame: " + text)
    # Breathing: 1, 0.7, 1 repeated by a Cycles modifier; at frame 30 the curve is 0.7 again.
    fc = _keyed(obj, [(0, 1.0), (10, 0.7), (20, 1.0)])
    fc.modifiers.new("CYCLES")
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"},
          "a cycled curve runs: " + s.status)
    r = _shown_ratios(obj, rest)
    check(abs(r[30] - 0.7) <= 0.01 and abs(r[10] - 0.7) <= 0.01,
          "a Cycles modifier: V/V0 {:.4f} at frame 30 (curve 0.7)".format(r[30]))
    bpy.context.scene.frame_set(start)
    bpy.data.objects.remove(obj)


def _world_z_extent(obj, co):
    z = (np.c_[co, np.ones(len(co))] @ np.array(obj.matrix_world).T)[:, 2]
    return z.max() - z.min()


def object_scale():
    """A sphere scaled (1, 1, 3), unapplied, deflates as the same sphere with its scale applied."""
    results = []
    for apply in (False, True):
        obj = _sphere("Scaled" + str(apply), 24, 12)
        obj.scale = (1.0, 1.0, 3.0)
        bpy.context.view_layer.update()
        if apply:
            bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
        rest = np.array([v.co[:] for v in obj.data.vertices])
        obj.shellcontract.frames, obj.shellcontract.target_volume = 30, 0.6
        check(bpy.ops.object.shellcontract_contract() == {"FINISHED"},
              "the scaled sphere runs (applied: {}): {}".format(apply, obj.shellcontract.status))
        last = key_positions(obj.data.shape_keys.key_blocks[-1])
        ratio = volume_of(obj, last) / volume_of(obj, rest)
        results.append((_world_z_extent(obj, last), ratio))
        bpy.data.objects.remove(obj)
    (z_unapplied, r_unapplied), (z_applied, r_applied) = results
    check(abs(z_unapplied - z_applied) <= 0.02 * 6.0 and abs(r_unapplied - 0.6) <= 0.005,
          "unapplied scale: world height {:.3f}, applied {:.3f}; V/V0 {:.4f}".format(
              z_unapplied, z_applied, r_unapplied))


def _modal_stub():
    reports = []
    from shellcontract_blender import operator as op
    stub = types.SimpleNamespace(report=lambda level, text: reports.append(text), _timer=None)
    stub._finish = lambda context, obj, job: op.OBJECT_OT_shellcontract_contract._finish(
        stub, context, obj, job)
    wm = types.SimpleNamespace(progress_update=lambda *a: None, progress_end=lambda: None,
                               event_timer_remove=lambda t: None)
    ctx = types.SimpleNamespace(window_manager=wm, scene=bpy.context.scene,
                                workspace=types.SimpleNamespace(status_text_set=lambda t: None),
                                screen=types.SimpleNamespace(areas=[]))
    return stub, ctx, reports


def _start_modal(stub, obj):
    """invoke() without a window: _prepare, then what invoke keeps for modal()."""
    from shellcontract_blender import operator as op
    bpy.context.view_layer.objects.active = obj
    obj_, job = op.OBJECT_OT_shellcontract_contract._prepare(stub, bpy.context)
    stub._obj_key, stub._obj_name, stub._job = op.run_key(obj_), obj_.name, job
    op.RUNNING[stub._obj_key] = job
    job.start()
    return job


def renamed_during_run():
    """A threaded run (the UI's modal path, with stubs: headless Blender has no window)."""
    from shellcontract_blender import operator as op
    Op = op.OBJECT_OT_shellcontract_contract
    tick = types.SimpleNamespace(type="TIMER", value="NOTHING")
    scene = bpy.context.scene
    old_start = scene.frame_start
    obj = _sphere("Renamed")
    obj.shellcontract.frames = 20
    stub, ctx, reports = _modal_stub()
    job = _start_modal(stub, obj)
    obj.name = "Balloon"
    check(not Op.poll(bpy.context), "no second run on the renamed object while the first runs")
    job.join()
    outcome = Op.modal(stub, ctx, tick)
    check(outcome == {"FINISHED"} and obj.data.shape_keys is not None
          and obj.shellcontract.status.startswith("ok") and Op.poll(bpy.context),
          "a run renamed during the run writes its keys to the renamed object: {} {}".format(
              outcome, obj.shellcontract.status))
    # The scene's start frame changed during a run: the keys start where the run's schedules
    # were read from, the start frame when it began.
    stub, ctx, reports = _modal_stub()
    job = _start_modal(stub, obj)
    scene.frame_start = old_start + 4
    job.join()
    outcome = Op.modal(stub, ctx, tick)
    keys = obj.data.shape_keys
    first = min(kp.co[0] for fc in keys.animation_data.action.fcurves
                for kp in fc.keyframe_points) if keys else None
    scene.frame_start = old_start
    check(outcome == {"FINISHED"} and first == old_start,
          "the keys start at the start frame read when the run began ({} vs {})".format(
              first, old_start))
    # Deleted during the run: said, not silent.
    other = _sphere("Deleted")
    other.shellcontract.frames = 5
    stub, ctx, reports = _modal_stub()
    job = _start_modal(stub, other)
    job.join()
    bpy.data.objects.remove(other)
    outcome = Op.modal(stub, ctx, tick)
    check(outcome == {"CANCELLED"} and any("Deleted is gone (deleted during the run" in r for r in reports)
          and not op.RUNNING, "a run whose object was deleted says so: {}".format(reports))
    bpy.data.objects.remove(obj)


def review():
    linked_meshes()
    fcurve_shape()
    object_scale()
    renamed_during_run()
