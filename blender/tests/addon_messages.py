"""The library's mesh messages in the add-on's terms: an open or pinched mesh is refused naming
the object's mesh and its own faces (polygons), not the triangles the run was given."""

import bmesh
import bpy

from addon_helpers import check, refusal


def edited_sphere(edit):
    """The scene's only object: a UV sphere whose mesh edit(bm) has changed (a bmesh)."""
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8)
    obj = bpy.context.active_object
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    edit(bm)
    bm.to_mesh(obj.data)
    bm.free()
    return obj


def mesh_messages():
    """A mesh the library refuses: the message names the object's mesh (not 'input arrays') and
    its face numbers are the mesh's faces (polygons), not the loop triangles the run was given."""
    import re
    from shellcontract_blender import runner
    hole = set()

    def remove_a_quad(bm):
        bm.faces.ensure_lookup_table()
        removed = bm.faces[len(bm.faces) // 2]  # a quad of the middle: triangle n != face n
        hole.update(v.index for v in removed.verts)
        bm.faces.remove(removed)

    obj = edited_sphere(remove_a_quad)
    text = refusal()
    # Every face with an open edge, as the mesh's faces: the removed quad's four neighbours.
    faces = re.search(r"the mesh of {}: open boundary: faces? ([\d, ]+) ".format(re.escape(obj.name)), text)
    edge = re.search(r"edge \((\d+), (\d+)\) of face", text)
    polygons = obj.data.polygons
    named = [int(n) for n in faces.group(1).split(", ")] if faces else []
    # The faces around the hole, from the mesh itself: those sharing an edge (two corners) with it.
    around = sorted(p.index for p in polygons if len(set(p.vertices) & hole) >= 2)
    check(faces is not None and edge is not None and "input arrays" not in text
          and sorted(named) == around and len(around) >= 3
          and any({int(edge.group(1)), int(edge.group(2))} <= set(polygons[n].vertices) for n in named),
          "an open mesh is refused naming the mesh's faces that have an open edge ({} around the "
          "hole): {}".format(around, text))
    check("modifiers" not in text, "an object without modifiers gets no word of them: " + text)
    # Half a sphere closed by a Mirror modifier: the run takes the mesh as stored (open), so the
    # refusal says that the modifiers are left out and how to contract what they make.
    obj = edited_sphere(lambda bm: bmesh.ops.delete(
        bm, geom=[v for v in bm.verts if v.co.x < -1e-6], context="VERTS"))
    obj.modifiers.new("Mirror", "MIRROR")
    text = refusal()
    check("open boundary" in text and "without its modifiers (Mirror)" in text
          and "Object > Apply" in text,
          "a half mesh closed by a Mirror modifier is refused with the modifiers named: " + text)
    # The hint is what the artist acts on, and the panel's one-line status is cut at the sidebar's
    # width: it comes first, before the library's list of faces.
    check(obj.shellcontract.status.startswith("error: the run takes {}'s mesh without its "
                                              "modifiers (Mirror)".format(obj.name)),
          "the status begins with the modifiers' hint: " + obj.shellcontract.status[:80])
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
            # Counts are of the mesh's faces where the list is whole, of triangles (and said
            # so) where the library cut it.
            ("2 faces have (nearly) zero area: 3, 4", "1 face has (nearly) zero area: 2"),
            ("1 face has (nearly) zero area: 4", "1 face has (nearly) zero area: 2"),
            ("3 faces have (nearly) zero area: 0, 1, ...",
             "3 triangles have (nearly) zero area, in faces: 0, ..."),
            # Without the triangles a component's faces cannot be counted: its triangles are.
            ("component 0 (6 faces, starting at face 2) was inside-out",
             "component 0 (6 triangles, starting at face 1) was inside-out"),
            # Beyond ten components the library lists them on one line, each in the same words.
            ("11 components were inside-out; their faces were flipped: component 0 (6 faces, "
             "starting at face 2) of signed volume -1, and 10 more",
             "11 components were inside-out; their faces were flipped: component 0 (6 "
             "triangles, starting at face 1) of signed volume -1, and 10 more")):
        check(runner.polygon_numbers(before, polygon_of) == after,
              "'{}' reads '{}'".format(before, runner.polygon_numbers(before, polygon_of)))
    inside_out_counts()


def inside_out_counts():
    """The inside-out warning counts the part's faces as the mesh has them (a cube's 6 quads,
    not the 12 triangles the run was given), also where the part is split along seams (every
    edge of the cube split: 24 vertices, which the library welds back for the run)."""
    import re
    for split in (False, True):
        bpy.ops.object.select_all(action="SELECT")
        bpy.ops.object.delete()
        bpy.ops.mesh.primitive_cube_add()
        obj = bpy.context.active_object
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.mesh.select_all(action="SELECT")
        bpy.ops.mesh.flip_normals()
        if split:
            bpy.ops.mesh.edge_split(type="EDGE")
        bpy.ops.object.mode_set(mode="OBJECT")
        obj.shellcontract.frames = 3
        check(bpy.ops.object.shellcontract_contract() == {"FINISHED"},
              "the inside-out cube runs: " + obj.shellcontract.status)
        named = re.search(r"warning: component 0 \((\d+) faces, starting at face (\d+)\) was "
                          r"inside-out", obj.shellcontract.status)
        check(named is not None and int(named.group(1)) == len(obj.data.polygons) == 6
              and int(named.group(2)) < 6 and len(obj.data.vertices) == (24 if split else 8),
              "an inside-out cube{} is warned about as its 6 faces: {}".format(
                  " split along every edge" if split else "", obj.shellcontract.status))
        bpy.data.objects.remove(obj)
