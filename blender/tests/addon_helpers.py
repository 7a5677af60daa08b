"""What the add-on's checks in Blender share (addon_in_blender.py runs them): the check that
prints what passed and raises on what failed, bmesh volumes, shape-key positions, the mesh's
triangles, the UV sphere the runs start from, and the operator's refusal text."""

import bmesh
import bpy
import numpy as np


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


def refusal():
    """The text of the RuntimeError the operator raises when it reports an error, or ''."""
    try:
        bpy.ops.object.shellcontract_contract()
    except RuntimeError as e:
        return str(e)
    return ""
