"""The object's own shape keys: the run contracts the Basis (the reference key) and its keys are
relative to it, so a key of the user's that is on would add on top of them and the shape shown
would not be the run's. Such a run is refused naming the keys; the keys that add nothing (at 0,
muted, keyed to 0, relative to themselves, the add-on's own from an earlier run) are not counted,
and where the run goes ahead the V/V0 it reports is the one Blender shows."""

import bmesh
import bpy

from addon_helpers import check, refusal


def shown_volume(obj, frame):
    """|V| of what Blender shows of the object at timeline frame `frame` (its evaluated mesh:
    shape keys mixed, pin, Relative; there are no modifiers here)."""
    bpy.context.scene.frame_set(frame)
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    bm = bmesh.new()
    bm.from_mesh(mesh)
    vol = abs(bm.calc_volume(signed=True))
    bm.free()
    evaluated.to_mesh_clear()
    return vol


def fat_sphere(value=1.0):
    """The review's scene: a 16 by 8 UV sphere with keys 'Basis' and 'Fat' (every vertex x1.5)
    at `value`, Frames 10."""
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8)
    obj = bpy.context.active_object
    obj.shape_key_add(name="Basis", from_mix=False)
    fat = obj.shape_key_add(name="Fat", from_mix=False)
    for d in fat.data:
        d.co = d.co * 1.5
    fat.value = value
    obj.shellcontract.frames = 10
    return obj, fat


def runs_as_shown(obj, what):
    """The run finishes and the V/V0 it reports is the one Blender shows: the last frame's
    volume over the start frame's."""
    start = bpy.context.scene.frame_start
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"},
          "{}: the run goes ahead: {}".format(what, obj.shellcontract.status))
    reported = obj["shellcontract_final_volume_ratio"]
    shown = shown_volume(obj, start + obj.shellcontract.frames) / shown_volume(obj, start)
    check(abs(shown - reported) <= 1e-3,
          "{}: the V/V0 shown {:.4f} is the one reported {:.4f}".format(what, shown, reported))


def refused(obj, words, what):
    keys_before = len(obj.data.shape_keys.key_blocks) if obj.data.shape_keys else 0
    text = refusal()
    keys_after = len(obj.data.shape_keys.key_blocks) if obj.data.shape_keys else 0
    check(all(w in text for w in words) and obj.shellcontract.status.startswith("error: ")
          and keys_after == keys_before,
          "{}: refused, naming {} (no key written): {}".format(what, words, text))


def shape_keys():
    start = bpy.context.scene.frame_start
    # The review's scenario: 'Fat' at 1.0 added on top of the result (a V/V0 of 0.6 reported
    # while Blender showed another).
    obj, fat = fat_sphere(1.0)
    refused(obj, ["'Fat' (1)", "Basis", "mute", "Apply All Shape Keys"], "a key that is on")
    # Keys that add nothing: the run goes ahead, and shows what it reports.
    fat.value = 0.0
    runs_as_shown(obj, "a key at 0")
    # The earlier run's keys are on now (mid-animation), and are replaced, not counted.
    bpy.context.scene.frame_set(start + 5)
    runs_as_shown(obj, "a rerun over the add-on's own keys")
    fat.value, fat.mute = 1.0, True
    runs_as_shown(obj, "a muted key at 1")
    fat.mute, fat.relative_key = False, fat
    runs_as_shown(obj, "a key relative to itself at 1")
    fat.relative_key = obj.data.shape_keys.reference_key
    # Animated values: what plays counts, not the slider's value now.
    fat.value = 0.0
    fat.keyframe_insert("value", frame=start)
    fat.value = 1.0
    fat.keyframe_insert("value", frame=start + 5)
    bpy.context.scene.frame_set(start)
    refused(obj, ["'Fat' (keyed)"], "a key at 0 now, keyed on later")
    for kp in obj.data.shape_keys.animation_data.action.fcurves.find(
            'key_blocks["Fat"].value').keyframe_points:
        kp.co[1] = 0.0
    runs_as_shown(obj, "a key keyed to 0 throughout")
    obj.data.shape_keys.animation_data.action.fcurves.remove(
        obj.data.shape_keys.animation_data.action.fcurves.find('key_blocks["Fat"].value'))
    fat.driver_add("value")
    refused(obj, ["'Fat' (driven)"], "a driven key")
    fat.driver_remove("value")
    fat.value = 0.0
    # The pin shows the active key alone, and absolute keys play through the list: neither
    # shows the run's keys.
    obj.show_only_shape_key = True
    refused(obj, ["Shape Key Lock", "unpin"], "the pinned key")
    obj.show_only_shape_key = False
    obj.data.shape_keys.use_relative = False
    refused(obj, ["Relative"], "absolute shape keys")
    obj.data.shape_keys.use_relative = True
    # 'Fat' moved to the top is the reference key, which Blender shows, while the mesh's
    # vertices stay the old Basis: the run contracts the reference key.
    obj.active_shape_key_index = 1
    bpy.ops.object.shape_key_move(type="TOP")
    check(obj.data.shape_keys.reference_key.name == "Fat", "'Fat' is the reference key now")
    runs_as_shown(obj, "a reference key that is not the mesh's vertices")
    bpy.data.objects.remove(obj)
