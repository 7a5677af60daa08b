"""The regions of a CLI run's .glb in Blender: a hook of Blender's glTF importer.

A run with regions writes each face's region as the custom attribute ``_REGION`` (every corner of
a face holds its id, -1 for none; docs/design/export.md, "Regions"), which Blender's glTF importer
does not read (it imports no custom attribute). The importer calls the hooks of an enabled add-on's
``glTF2ImportUserExtension``: after the mesh is made, this one puts the ids on it as the integer
face attribute ``region``, and after its object is made, a vertex group ``region N`` per region
(weight 1 on the vertices of its faces), which the add-on's Region group can take.
"""

ATTRIBUTE = "_REGION"
FACE_ATTRIBUTE = "region"


def face_regions(gltf, pymesh):
    """Per triangle of the mesh, in the order the importer makes its polygons (primitive by
    primitive, each one's triangles in order), its region id; None when the mesh has no
    ``_REGION`` or a primitive that is not triangles."""
    from io_scene_gltf2.io.imp.gltf2_io_binary import BinaryData

    ids = []
    for prim in pymesh.primitives:
        if ATTRIBUTE not in prim.attributes or (prim.mode is not None and prim.mode != 4):
            return None
        values = BinaryData.decode_accessor(gltf, prim.attributes[ATTRIBUTE]).reshape(-1)
        if prim.indices is not None:
            corners = BinaryData.decode_accessor(gltf, prim.indices).reshape(-1)
        else:
            corners = range(len(values))
        # A face's three corners hold its id: its first one gives it.
        ids.extend(int(round(float(values[c]))) for c in corners[::3])
    return ids


class glTF2ImportUserExtension:
    """The importer's hooks (io_scene_gltf2.io.imp.gltf2_io_user_extensions)."""

    def gather_import_mesh_after_hook(self, pymesh, mesh, gltf):
        ids = face_regions(gltf, pymesh)
        # The polygons are the triangles in order unless the importer dropped some (validate()
        # removes a degenerate face): then the ids would land on other faces, so none are put.
        if not ids or len(ids) != len(mesh.polygons):
            return
        attribute = mesh.attributes.new(FACE_ATTRIBUTE, "INT", "FACE")
        attribute.data.foreach_set("value", ids)

    def gather_import_node_after_hook(self, vnode, gltf_node, obj, gltf):
        mesh = getattr(obj, "data", None)
        attribute = getattr(mesh, "attributes", {}).get(FACE_ATTRIBUTE) if mesh else None
        if attribute is None or attribute.domain != "FACE" or attribute.data_type != "INT":
            return
        members = {}
        for polygon, item in zip(mesh.polygons, attribute.data):
            if item.value >= 0:
                members.setdefault(item.value, set()).update(polygon.vertices)
        for region in sorted(members):
            name = "region {}".format(region)
            if obj.vertex_groups.get(name) is None:
                obj.vertex_groups.new(name=name).add(sorted(members[region]), 1.0, "REPLACE")
