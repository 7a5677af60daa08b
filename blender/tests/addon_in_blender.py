"""The add-on's acceptance inside Blender, run by run_addon_test.py as
    blender -b --factory-startup --python-exit-code 1 --python addon_in_blender.py -- ARGS
ARGS: --addon-dir DIR (the folder holding shellcontract_blender), --glb FILE (a CLI --gltf result
to import). The shellcontract module comes from SHELLCONTRACT_PYTHONPATH (the add-on's own
lookup). Any failed check raises, and Blender exits with 1.

Checks: the add-on enables from the source tree; docs/blender.md gives the settings' defaults
of properties.py and its scripting example runs as written; on a UV sphere with a UV map and a
vertex group, bpy.ops.object.shellcontract_contract() at target 0.6 runs to the end in
background mode and leaves shape keys and timeline keys; the last key's V/V0, measured with bmesh (not the module's
number), is within 0.005 of 0.6; the UVs are unchanged; the project's own check
(shellcontract.check) finds no self-intersecting pair that the input lacks; a keyframed target
(1 -> 0.6 -> 0.9) becomes a schedule the last key of which is 0.9; a run at the defaults and
the keyed one end without a warning (the pressure is passed only where it has an effect or was
asked for); the Target volume's refusals and the library's messages speak the panel's terms
(field names, timeline frames, float32-rounded values); a missing vertex group is refused; the
threaded run of the UI reports progress and cancels; an open mesh's message names the mesh's
own face, taken from the MeshError's `faces`; and the CLI's .glb imports (the numpy.bool shim) with its keys from frame 0."""

import argparse
import sys

import addon_utils
import bmesh
import bpy
import numpy as np


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--addon-dir", required=True)
    p.add_argument("--glb", default="")
    return p.parse_args(argv)


def check(condition, message):
    if not condition:
        raise AssertionError(message)
    print("ok:", message)


def volume_of(obj, co):
    """|V| of the object's mesh with vertex positions `co` (N by 3), by bmesh."""
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    for v in bm.verts:
        v.co = co[v.index]
    vol = abs(bm.calc_volume(signed=True))
    bm.free()
    return vol


def key_positions(kb):
    co = np.empty(len(kb.data) * 3)
    kb.data.foreach_get("co", co)
    return co.reshape(-1, 3)


def triangles(obj):
    mesh = obj.data
    mesh.calc_loop_triangles()
    f = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int64)
    mesh.loop_triangles.foreach_get("vertices", f)
    return f.reshape(-1, 3)


def uv_sphere():
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12, radius=1.0,
                                         calc_uvs=True)
    obj = bpy.context.active_object
    group = obj.vertex_groups.new(name="spot")
    # A patch around the +x equator point, weights falling off from 1 to 0.
    for v in obj.data.vertices:
        w = max(0.0, (v.co.x - 0.75) / 0.25)
        if w > 0.0:
            group.add([v.index], min(w, 1.0), "REPLACE")
    return obj


def pressure_combinations(shellcontract, obj):
    """The pressure goes to the run only where it has an effect or the user asked for it: not
    with a target volume (a number or keys) at its default, which is the library's own."""
    from shellcontract_blender import operator
    s = obj.shellcontract
    default = s.bl_rna.properties["pressure"].default
    library = [o.default for o in shellcontract.options() if o.name == "pressure"]
    check(library and float(library[0]) == default,
          "the Pressure field's default {} is the library's ({}): leaving it out runs the same"
          .format(default, library))
    ctx = bpy.context

    def given(setup):
        obj.animation_data_clear()
        s.target_volume, s.pressure = 0.6, default
        setup()
        return operator.run_options(ctx, obj)

    def key(prop, values):
        for frame, value in values:
            setattr(s, prop, value)
            obj.keyframe_insert("shellcontract." + prop, frame=ctx.scene.frame_start + frame)

    cases = [
        ("target 0.6, default pressure", lambda: None, False),
        ("keyed target, default pressure", lambda: key("target_volume", [(0, 1.0), (20, 0.7)]),
         False),
        ("target off: the pressure decides", lambda: setattr(s, "target_volume", 0.0), True),
        ("target 0.6, pressure set to 8 (warned: no effect)", lambda: setattr(s, "pressure", 8.0),
         True),
        ("target 0.6, keyed pressure (warned: no effect)",
         lambda: key("pressure", [(0, 4.0), (20, 8.0)]), True),
        ("keyed target and keyed pressure (warned)",
         lambda: (key("target_volume", [(0, 1.0), (20, 0.7)]),
                  key("pressure", [(0, 4.0), (20, 8.0)])), True),
        ("target off, keyed pressure", lambda: (key("pressure", [(0, 4.0), (20, 8.0)]),
                                                setattr(s, "target_volume", 0.0)), True),
    ]
    for name, setup, passed in cases:
        options = given(setup)
        check(("pressure" in options) == passed, "{}: pressure {}".format(
            name, "given ({})".format(options.get("pressure")) if passed else "left out"))
    given(lambda: setattr(s, "pressure", 8.0))
    s.frames = 3
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}
          and "has no effect" in s.status,
          "a pressure set off its default with a target volume is warned about: " + s.status)
    obj.animation_data_clear()
    s.target_volume, s.pressure = 0.6, default


def refusal():
    """The text of the RuntimeError the operator raises when it reports an error, or ''."""
    try:
        bpy.ops.object.shellcontract_contract()
    except RuntimeError as e:
        return str(e)
    return ""


def target_volume_messages(obj):
    """The Target volume's rules, refused before the run in the panel's terms: field names,
    timeline frames, values as Blender shows them (float32 rounded), no CLI syntax."""
    from shellcontract_blender import operator
    s = obj.shellcontract
    start = bpy.context.scene.frame_start

    def cli_free(text):
        return ("target_volume" not in text and "00000" not in text and "0:1" not in text
                and "[0, 1)" not in text)

    obj.animation_data_clear()
    s.frames = 5
    for value in (1.0, 1.2):
        s.target_volume = value
        text = refusal()
        check("Target volume {:g}".format(value) in text and "keyframe" in text and cli_free(text)
              and s.status.startswith("error: "),
              "an unkeyed Target volume {:g} is refused in the panel's terms: {}".format(
                  value, text))
    s.target_volume = 0.6
    obj.keyframe_insert("shellcontract.target_volume", frame=start)
    text = refusal()
    check("Target volume" in text and "frame {}".format(start) in text and " 0.6" in text
          and cli_free(text),
          "a first key other than 1 at the start frame is refused by its timeline frame: " + text)
    obj.animation_data_clear()
    for frame, value in ((0, 1.0), (20, 0.0)):
        s.target_volume = value
        obj.keyframe_insert("shellcontract.target_volume", frame=start + frame)
    text = refusal()
    check("frame {} is 0".format(start + 20) in text and cli_free(text),
          "a key of 0 is refused by its timeline frame: " + text)
    obj.animation_data_clear()
    for frame, value in ((0, 1.0), (10.2, 0.8), (10.4, 0.7)):
        s.target_volume = value
        obj.keyframe_insert("shellcontract.target_volume", frame=start + frame)
    text = refusal()
    check("frames {:g} and {:g}".format(start + 10.2, start + 10.4) in text and cli_free(text),
          "two keys on one frame are refused by their timeline frames: " + text)
    obj.animation_data_clear()
    for frame, value in ((0, 1.0), (40, 0.6), (80, 0.9)):
        s.target_volume = value
        obj.keyframe_insert("shellcontract.target_volume", frame=start + frame)
    check(operator.run_options(bpy.context, obj)["target_volume"] == "0:1, 40:0.6, 80:0.9",
          "the keys go to the run as the values Blender shows: {}".format(
              operator.run_options(bpy.context, obj)["target_volume"]))
    check(bpy.ops.object.shellcontract_contract() == {"FINISHED"}
          and "the key at frame {} comes after the run's last frame {}".format(
              start + 80, start + 5) in s.status and cli_free(s.status),
          "a key after the last frame is warned about in timeline frames: " + s.status)
    obj.animation_data_clear()
    s.target_volume = 0.6


def muted_keys():
    """Keys Blender does not play are not the run's: a muted F-curve of the Target volume leaves
    the field's own value."""
    from shellcontract_blender import operator
    obj = uv_sphere()
    s = obj.shellcontract
    start = bpy.context.scene.frame_start
    for frame, value in ((0, 1.0), (40, 0.6), (80, 0.9)):
        s.target_volume = value
        obj.keyframe_insert("shellcontract.target_volume", frame=start + frame)
    s.target_volume = 0.7
    keyed = operator.run_options(bpy.context, obj)["target_volume"]
    check(keyed == "0:1, 40:0.6, 80:0.9", "the keys are read while they play: {}".format(keyed))
    fc = obj.animation_data.action.fcurves.find("shellcontract.target_volume")
    fc.mute = True
    unkeyed = operator.run_options(bpy.context, obj)["target_volume"]
    check(unkeyed == 0.7 or str(unkeyed) == "0.7",
          "a muted F-curve is not read as keys: {!r}".format(unkeyed))
    bpy.data.objects.remove(obj)


def mesh_messages():
    """A mesh the library refuses: the message names the object's mesh (not 'input arrays') and
    its face numbers are the mesh's faces (polygons), not the loop triangles the run was given."""
    import re
    from shellcontract_blender import runner
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8)
    obj = bpy.context.active_object
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bm.faces.ensure_lookup_table()
    bm.faces.remove(bm.faces[len(bm.faces) // 2])  # a quad of the middle: triangle n != face n
    bm.to_mesh(obj.data)
    bm.free()
    text = refusal()
    face = re.search(r"the mesh of {}: open boundary: face (\d+) ".format(re.escape(obj.name)), text)
    edge = re.search(r"edge \((\d+), (\d+)\) of face", text)
    polygons = obj.data.polygons
    check(face is not None and edge is not None and "input arrays" not in text
          and int(face.group(1)) < len(polygons)
          and {int(edge.group(1)), int(edge.group(2))} <= set(polygons[int(face.group(1))].vertices),
          "an open mesh is refused naming the mesh's face that has the open edge: " + text)
    # Two cubes that share one corner (the second is the first mirrored through its corner 7): the
    # pinch is a MeshError whose faces are the six quads around vertex 7, each named once.
    corners = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    second = list(range(8, 15)) + [7]  # the mirror's corner i; mirrored, so its quads are flipped
    faces = quads + [tuple(second[i] for i in reversed(q)) for q in quads]
    obj = bpy.data.objects.new("Pinched", bpy.data.meshes.new("pinched"))
    obj.data.from_pydata(corners + [(2 - x, 2 - y, 2 - z) for (x, y, z) in corners[:7]], [], faces)
    bpy.context.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    text = refusal()
    named = re.search(r"the mesh of Pinched: non-manifold vertex: faces ([\d, ]+) \(", text)
    check(named is not None and [int(n) for n in named.group(1).split(", ")] == [1, 3, 5, 7, 9, 11]
          and re.search(r": vertex 7: its \d+ faces form several fans", text) is not None,
          "a pinched mesh is refused naming the faces around the vertex: " + text)
    # A MeshError's faces are its `faces` (triangles) as the mesh's faces, not numbers read
    # from its text: a message without numbers still names them.
    import shellcontract
    polygon_of = [0, 0, 1, 2, 2, 3]
    error = shellcontract.MeshError("input arrays: non-manifold edge: somewhere")
    error.faces = [1, 3, 4, 5]
    text = runner.addon_terms(error, 1, "Cube", polygon_of)
    check(text.startswith("the mesh of Cube: non-manifold edge: faces 0, 2, 3 (")
          and text.endswith(": somewhere)"),
          "a MeshError names the mesh's faces of its `faces`: " + text)
    error = shellcontract.MeshError("input arrays: open boundary: edge (1, 2) of face 99 ...")
    error.faces = [2]
    text = runner.addon_terms(error, 1, "Cube", polygon_of)
    check(text.startswith("the mesh of Cube: open boundary: face 1 ("),
          "the face comes from `faces`, not from the text's 'face 99': " + text)
    # Warnings (text only), and errors without `faces`: the library's lists of faces, by
    # triangle, read from the text as the mesh's faces.
    for before, after in (
            ("edge (1, 2) is shared by 3 faces (1, 3, 5), at most 2 allowed",
             "edge (1, 2) is shared by 3 faces (0, 2, 3), at most 2 allowed"),
            ("2 faces have (nearly) zero area: 3, 4", "2 faces have (nearly) zero area: 2"),
            ("1 face has (nearly) zero area: 4", "1 face has (nearly) zero area: 2"),
            ("component 0 (6 faces, starting at face 2) was inside-out",
             "component 0 (6 faces, starting at face 1) was inside-out")):
        check(runner.polygon_numbers(before, polygon_of) == after,
              "'{}' reads '{}'".format(before, runner.polygon_numbers(before, polygon_of)))


def doc_path(addon_dir):
    import os
    return os.path.join(os.path.dirname(os.path.abspath(addon_dir)), "docs", "blender.md")


def doc_section(doc, title):
    """The lines of docs/blender.md's section '## title' (to the next '## ')."""
    lines = doc.split("\n")
    start = lines.index("## " + title) + 1
    end = next((i for i in range(start, len(lines)) if lines[i].startswith("## ")), len(lines))
    return lines[start:end]


def doc_example_runs(addon_dir):
    """The scripting example of docs/blender.md runs as written (its first indented block), in
    the factory scene where it starts (the default cube active), and writes its result."""
    import textwrap
    with open(doc_path(addon_dir)) as f:
        section = doc_section(f.read(), "Scripting and background mode")
    first = next(i for i, line in enumerate(section) if line.startswith("    "))
    end = next((i for i in range(first, len(section))
                if section[i] and not section[i].startswith("    ")), len(section))
    code = textwrap.dedent("\n".join(section[first:end]))
    namespace = {}
    exec(compile(code, "docs/blender.md (Scripting)", "exec"), namespace)
    obj = bpy.context.active_object
    keys = obj.data.shape_keys
    check(obj.shellcontract.status.startswith("ok:") and keys is not None
          and len(keys.key_blocks) > 1 and "except RuntimeError" in code,
          "the scripting example of docs/blender.md runs as written, catching a refusal: " +
          obj.shellcontract.status)


def doc_defaults(addon_dir):
    """docs/blender.md's table of settings gives each one's default as properties.py has it."""
    from shellcontract_blender import properties, runner
    with open(doc_path(addon_dir)) as f:
        section = doc_section(f.read(), "Use")
    header = next(line for line in section if line.startswith("| setting"))
    columns = [c.strip() for c in header.strip("|").split("|")]
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in section
            if line.startswith("| ") and line is not header and not line.startswith("| ---")]
    rna = properties.ShellContractSettings.bl_rna.properties
    shown = {}
    for row in rows:
        prop = row[1].strip("`").split(".")[-1]
        shown[prop] = row[columns.index("default")] if "default" in columns else None
    for prop in shown:
        p = rna[prop]
        expected = {"FLOAT": lambda: runner.float32_text(p.default),
                    "INT": lambda: str(p.default),
                    "BOOLEAN": lambda: "on" if p.default else "off",
                    "STRING": lambda: p.default or "empty"}[p.type]()
        check(shown[prop] == expected, "docs/blender.md gives {}'s default as {} ({})".format(
            prop, expected, shown[prop]))
    check(len(shown) == 8, "docs/blender.md's table has the 8 settings of the panel")


def main():
    a = args()
    sys.path.insert(0, a.addon_dir)
    mod = addon_utils.enable("shellcontract_blender", default_set=True, handle_error=None)
    check(mod is not None and hasattr(bpy.types.Object, "shellcontract"),
          "the add-on enables from the source tree")
    from shellcontract_blender import runner
    shellcontract = runner.import_shellcontract()  # the add-on's own lookup
    doc_defaults(a.addon_dir)
    doc_example_runs(a.addon_dir)

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

    # A keyframed target: 1 at the start, 0.6 at frame +40, 0.9 at frame +80.
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

    pressure_combinations(shellcontract, obj2)
    target_volume_messages(obj2)

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

    # The UI's path: the run in a worker thread while this (Blender's) thread goes on, and a
    # cancel that stops it after the current step, leaving the object alone.
    import time
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

    muted_keys()
    mesh_messages()

    if a.glb:
        bpy.ops.import_scene.gltf(filepath=a.glb)
        imported = [o for o in bpy.context.selected_objects if o.type == "MESH"]
        check(imported and imported[0].data.shape_keys is not None,
              "the CLI's .glb imports with its morph targets as shape keys")
        # docs/blender.md: its keys are at frames 0..N (the add-on's at scene start + n).
        ad = imported[0].data.shape_keys.animation_data
        first = min(kp.co[0] for fc in ad.action.fcurves for kp in fc.keyframe_points)
        check(first == 0.0, "the .glb's keys start at frame 0 ({:g})".format(first))


main()
print("ALL ADD-ON CHECKS PASSED")
