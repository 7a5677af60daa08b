"""The operator's runs in background mode: a run at target 0.6 on a UV sphere with a UV map and a
vertex group (its keys, volume, UVs and self-intersections), a keyframed target, the runs it
refuses or warns about, the UI's threaded run, and the import of a CLI .glb."""

import time

import bpy
import numpy as np

from addon_helpers import check, key_positions, triangles, uv_sphere, volume_of


def contract_sphere(shellcontract):
    """A run at target 0.6 with the vertex group as its region; returns the sphere's rest
    positions and triangles (the threaded run's input)."""
    obj = uv_sphere()
    check(len(obj.data.uv_layers) == 1, "the sphere has a UV map")
    uv_before = np.empty(len(obj.data.uv_layers[0].data) * 2)
    obj.data.uv_layers[0].data.foreach_get("uv", uv_before)
    rest = np.empty(len(obj.data.vertices) * 3)
    obj.data.vertices.foreach_get("co", rest)
    rest = rest.reshape(-1, 3)
    faces = triangles(obj)
    before_pairs = {tuple(p) for p in shellcontract.check(rest, faces)["self_intersections"]}

    s = obj.shellcontract
    s.target_volume = 0.6
    s.frames = 120
    s.region_group = "spot"
    result = bpy.ops.object.shellcontract_contract()
    check(result == {"FINISHED"}, "the operator runs to the end in background mode: " + s.status)
    check(obj["shellcontract_regions"] == 1, "the vertex group's weights made one region")
    # The defaults set nothing that has no effect: no warning (the pressure is left out with a
    # target volume, as the CLI's --target-volume 0.6 alone leaves -p out).
    check(s.status.startswith("ok:") and "warning" not in s.status,
          "a run at the default settings has no warning: " + s.status)

    keys = obj.data.shape_keys
    check(keys is not None and len(keys.key_blocks) > 10, "shape keys were written ({})".format(
        len(keys.key_blocks) if keys else 0))
    fcurves = keys.animation_data.action.fcurves if keys.animation_data else []
    check(len(fcurves) == len(keys.key_blocks) - 1 and all(len(fc.keyframe_points) >= 2
                                                             for fc in fcurves),
          "every result key has timeline keys")
    last = keys.key_blocks[-1]
    # The timeline's last frame shows the last key alone.
    bpy.context.scene.frame_set(bpy.context.scene.frame_start + s.frames)
    check(abs(last.value - 1.0) < 1e-9 and all(abs(kb.value) < 1e-9 for kb in keys.key_blocks[1:-1]),
          "at the last frame only the last key is on")
    ratio = volume_of(obj, key_positions(last)) / volume_of(obj, rest)
    check(abs(ratio - 0.6) <= 0.005, "the last key's V/V0 (bmesh) {:.4f} is within 0.005 of 0.6"
          .format(ratio))
    uv_after = np.empty(len(obj.data.uv_layers[0].data) * 2)
    obj.data.uv_layers[0].data.foreach_get("uv", uv_after)
    check(np.array_equal(uv_before, uv_after), "the UVs are unchanged")
    after_pairs = {tuple(p) for p in shellcontract.check(key_positions(last), faces)
                   ["self_intersections"]}
    check(not (after_pairs - before_pairs), "no new self-intersecting pair ({} new)".format(
        len(after_pairs - before_pairs)))
    return rest, faces


def keyed_target():
    """A keyframed target (1 -> 0.6 -> 0.9) becomes a schedule; returns the object, which the
    checks of settings and refusals go on with."""
    # 1 at the start, 0.6 at frame +40, 0.9 at frame +80.
    obj2 = uv_sphere()
    start = bpy.context.scene.frame_start
    for frame, value in ((start, 1.0), (start + 40, 0.6), (start + 80, 0.9)):
        obj2.shellcontract.target_volume = value
        obj2.keyframe_insert('shellcontract.target_volume', frame=frame)
    obj2.shellcontract.frames = 100
    obj2.shellcontract.region_group = ""
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}
          and "warning" not in obj2.shellcontract.status,
          "a keyframed target runs, without a warning: " + obj2.shellcontract.status)
    rest2 = np.empty(len(obj2.data.vertices) * 3)
    obj2.data.vertices.foreach_get("co", rest2)
    kb = obj2.data.shape_keys.key_blocks
    by_frame = {int(k.name.split()[-1]): k for k in kb[1:]}
    v0 = volume_of(obj2, rest2.reshape(-1, 3))
    for frame, value in ((40, 0.6), (100, 0.9)):
        r = volume_of(obj2, key_positions(by_frame[frame])) / v0
        check(abs(r - value) <= 0.005, "keyed target: V/V0 {:.4f} at frame {} (key {})".format(
            r, frame, value))
    return obj2


def refused_runs(obj2):
    """A missing vertex group, an empty one, a run that fails at its first step and Edit Mode:
    each is refused or warned about, and the earlier keys are kept."""
    # An error report of an operator called from a script is a RuntimeError with its text.
    obj2.shellcontract.region_group = "no such group"
    keys_before = len(obj2.data.shape_keys.key_blocks)
    try:
        bpy.ops.object.shellcontract_contract()
        refused = ""
    except RuntimeError as e:
        refused = str(e)
    check("no such group" in refused and "vertex group" in refused
          and len(obj2.data.shape_keys.key_blocks) == keys_before,
          "a missing vertex group is refused, naming it, and nothing changes")
    check(obj2.shellcontract.status.startswith("error: ") and "no such group" in obj2.shellcontract.status,
          "the status says why a run was refused: " + obj2.shellcontract.status)

    # A vertex group without weights makes no region: a success, but not a silent one.
    obj2.vertex_groups.new(name="empty")
    obj2.shellcontract.region_group = "empty"
    obj2.shellcontract.frames = 5
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}
          and "warning" in obj2.shellcontract.status and "every weight is 0" in obj2.shellcontract.status,
          "an empty vertex group runs with a warning in the status: " + obj2.shellcontract.status)
    keys_before = len(obj2.data.shape_keys.key_blocks)

    # A run that fails at its first step keys nothing and keeps the earlier result.
    obj2.shellcontract.region_group = ""
    obj2.animation_data_clear()  # the target's keys (the result's keys are on the mesh's Key)
    obj2.shellcontract.target_volume = 0.0
    obj2.shellcontract.pressure = -1e6
    try:
        bpy.ops.object.shellcontract_contract()
        refused = ""
    except RuntimeError as e:
        refused = str(e)
    check("no frame was run" in refused and len(obj2.data.shape_keys.key_blocks) == keys_before,
          "a run that fails at its first step is an error and keeps the earlier keys: " + refused)
    obj2.shellcontract.pressure = 4.0

    # Edit Mode keeps its own mesh: contracting there is refused, and the keys survive it.
    bpy.ops.object.mode_set(mode="EDIT")
    try:
        bpy.ops.object.shellcontract_contract()
        refused = ""
    except RuntimeError as e:
        refused = str(e)
    bpy.ops.object.mode_set(mode="OBJECT")
    check("Edit Mode" in refused and len(obj2.data.shape_keys.key_blocks) == keys_before
          and "Edit Mode" in obj2.shellcontract.status,
          "contracting in Edit Mode is refused, the status says so and the keys are kept: " + refused)


def threaded_run(shellcontract, runner, rest, faces):
    """The UI's path: the run in a worker thread while this (Blender's) thread goes on, and a
    cancel that stops it after the current step, leaving the object alone."""
    job = runner.Job(shellcontract, rest, faces, {"frames": 5000, "target_volume": 0.6}, keep=[])
    job.start()
    # start() returned while the run goes on (5000 frames take far longer than this line): it
    # runs in a thread. Whether this loop looks before or after frame 3 is up to the scheduler,
    # so nothing is asserted about how often it looked.
    running_after_start = not job.done()
    while job.progress < 3 and not job.done():
        time.sleep(0.01)
    reported = job.progress
    job.cancel()
    job.join()
    check(job.error is None and job.result.status == "cancelled" and running_after_start
          and 3 <= reported <= job.progress < 5000,
          "a threaded run reports progress and cancels (frame {})".format(job.progress))


def glb_import(path):
    """The CLI's .glb imports (the numpy.bool shim) with its keys from frame 0."""
    bpy.ops.import_scene.gltf(filepath=path)
    imported = [o for o in bpy.context.selected_objects if o.type == "MESH"]
    check(imported and imported[0].data.shape_keys is not None,
          "the CLI's .glb imports with its morph targets as shape keys")
    # docs/blender.md: its keys are at frames 0..N (the add-on's at scene start + n).
    ad = imported[0].data.shape_keys.animation_data
    first = min(kp.co[0] for fc in ad.action.fcurves for kp in fc.keyframe_points)
    check(first == 0.0, "the .glb's keys start at frame 0 ({:g})".format(first))
    check(imported[0].data.attributes.get("region") is None and not imported[0].vertex_groups,
          "a .glb without regions imports without a region attribute or groups")


def glb_regions(path, regions_file):
    """A regions run's .glb imports with each face's region (gltf_regions.py, the importer's
    hook): the face attribute `region` holds, on each polygon, the line of the --regions file
    that lists that face (polygon i is the mesh's face i: one primitive), -1 on the others, and
    a vertex group `region N` holds the vertices of region N's faces."""
    expected = {}
    with open(regions_file) as f:
        lines = [line.split(":")[-1].split() for line in f]
    for r, ids in enumerate(line for line in lines if line):
        for face in ids:
            expected[int(face)] = r
    bpy.ops.object.select_all(action="DESELECT")
    bpy.ops.import_scene.gltf(filepath=path)
    obj = [o for o in bpy.context.selected_objects if o.type == "MESH"][0]
    attribute = obj.data.attributes.get("region")
    check(attribute is not None and attribute.domain == "FACE" and attribute.data_type == "INT",
          "a regions run's .glb imports with the face attribute 'region'")
    got = [item.value for item in attribute.data]
    want = [expected.get(face, -1) for face in range(len(obj.data.polygons))]
    check(got == want, "each polygon's region is its face's line in the --regions file ({} of {} "
          "differ)".format(sum(g != w for g, w in zip(got, want)), len(want)))
    for r in sorted(set(expected.values())):
        group = obj.vertex_groups.get("region {}".format(r))
        members = {v.index for v in obj.data.vertices
                   if group is not None and any(g.group == group.index for g in v.groups)}
        faces_vertices = {v for p in obj.data.polygons if want[p.index] == r for v in p.vertices}
        check(group is not None and members == faces_vertices,
              "vertex group 'region {}' holds the vertices of its faces".format(r))


def edited_during_run(shellcontract, runner, rest, faces):
    """A threaded run whose mesh was edited meanwhile (a modifier applied, vertices deleted):
    the result is not written and the object is left as it was (before, its keys were removed
    and foreach_set failed on the new vertex count, the object half changed)."""
    from shellcontract_blender.operator import OBJECT_OT_shellcontract_contract as Op

    class Reports:  # the operator's report(), which _finish calls, outside an invocation
        def __init__(self):
            self.lines = []

        def report(self, level, text):
            self.lines.append(text)

    job = runner.Job(shellcontract, rest, faces, {"frames": 3}, keep=[])
    job.run()
    bpy.ops.mesh.primitive_cube_add()  # another vertex count than the sphere the job ran on
    cube = bpy.context.active_object
    cube.shellcontract.frames = 3
    reports = Reports()
    outcome = Op._finish(reports, bpy.context, cube, job)
    check(outcome == {"CANCELLED"} and cube.data.shape_keys is None
          and "edited during the run" in cube.shellcontract.status
          and any("8 vertices now" in line for line in reports.lines),
          "a mesh edited during a threaded run is left unchanged: " + "; ".join(reports.lines))
    bpy.data.objects.remove(cube)

    # A run ended by a KeyboardInterrupt, which has no text (before, the report was
    # "ShellContract: " and the status "error: "): where a script set Python's own SIGINT handler
    # (signal.default_int_handler). Under blender -b Blender's handler takes Ctrl-C, and the
    # add-on's own takes it during a run (interrupt.py; addon_ctrl_c.py checks it).
    sphere = bpy.data.objects.get("Sphere") or bpy.context.view_layer.objects.active
    interrupted = runner.Job(shellcontract, rest, faces, {"frames": 3}, keep=[])
    interrupted.error = KeyboardInterrupt()
    reports = Reports()
    outcome = Op._finish(reports, bpy.context, sphere, interrupted)
    at = "interrupted (Ctrl-C) at frame {}".format(bpy.context.scene.frame_start)
    check(outcome == {"CANCELLED"} and sphere.shellcontract.status == at
          and reports.lines == ["ShellContract: {}; the object is unchanged".format(at)],
          "a run ended by Ctrl-C says so: " + "; ".join(reports.lines))
