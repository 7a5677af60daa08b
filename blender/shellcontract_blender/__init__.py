"""ShellContract for Blender: deflate or shrivel the active mesh like a thin elastic shell.

The panel (3D view sidebar, tab "ShellContract") holds the settings, stored on the object as
``object.shellcontract`` (target_volume, frames, thickness, pressure, collisions, region_group,
region_shrink); target volume and pressure can be keyframed like any property. "Contract"
(``bpy.ops.object.shellcontract_contract()``) runs the ``shellcontract`` Python module in
Blender's own process and writes the result as shape keys with keyframed values on the same
object, so UVs, materials and modifiers stay and the animation plays on the timeline.

The module is found on sys.path, in the add-on preference "Module path" or in the environment
variable SHELLCONTRACT_PYTHONPATH (the folder that holds the ``shellcontract`` package, e.g. the
project's build/python). docs/blender.md.
"""

bl_info = {
    "name": "ShellContract",
    "author": "ShellContract",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > ShellContract",
    "description": "Deflate or shrivel a closed mesh like a thin elastic shell (shape keys)",
    "category": "Animation",
}

from . import compat

# Before anything imports the glTF importer: Debian's Blender 3.4 with numpy >= 1.24.
compat.restore_numpy_bool()

if "bpy" in locals():  # a reload from Blender's F3 "Reload Scripts"
    import importlib

    importlib.reload(compat)

import bpy  # noqa: E402

from . import operator, panel, properties  # noqa: E402
# Blender's glTF importer calls the hooks of an enabled add-on's glTF2ImportUserExtension: a CLI
# .glb's region ids become a face attribute and vertex groups (gltf_regions.py).
from .gltf_regions import glTF2ImportUserExtension  # noqa: E402,F401

_classes = (
    properties.ShellContractPreferences,
    properties.ShellContractSettings,
    operator.OBJECT_OT_shellcontract_contract,
    panel.VIEW3D_PT_shellcontract,
)


def register():
    compat.restore_numpy_bool()
    for cls in _classes:
        bpy.utils.register_class(cls)
    bpy.types.Object.shellcontract = bpy.props.PointerProperty(type=properties.ShellContractSettings)


def unregister():
    del bpy.types.Object.shellcontract
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
