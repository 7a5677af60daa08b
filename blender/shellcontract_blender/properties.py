"""The add-on's settings: per object (object.shellcontract) and the add-on preferences."""

import bpy


class ShellContractPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    module_path: bpy.props.StringProperty(
        name="Module path",
        description="Folder that holds the shellcontract Python package (the project's "
                    "build/python); empty: sys.path and SHELLCONTRACT_PYTHONPATH",
        subtype="DIR_PATH",
        default="",
    )

    def draw(self, context):
        self.layout.prop(self, "module_path")


class ShellContractSettings(bpy.types.PropertyGroup):
    # Animatable (Blender's default for properties): keys on target_volume and pressure become
    # the run's schedules, timeline frame = scene start + simulation frame.
    target_volume: bpy.props.FloatProperty(
        name="Target volume",
        description="V/V0 to reach and hold, below 1 (0 = off: the pressure decides). "
                    "Keyframed, it deflates and re-inflates over time: keys above 0 and up to "
                    "2, 1 at the scene's start frame",
        # The range is the keys' (0, 2] with the unkeyed 0 = off; an unkeyed value is below 1,
        # checked when Contract runs (runner.unkeyed_target_volume), as one property has one range.
        default=0.6, min=0.0, max=2.0, soft_max=1.0, precision=3,
    )
    frames: bpy.props.IntProperty(
        name="Frames", description="Simulation frames (one per timeline frame)",
        default=120, min=1, max=100000,
    )
    thickness: bpy.props.FloatProperty(
        name="Thickness",
        description="Shell thickness, as a fraction of the mesh's bounding-box diagonal "
                    "(thinner wrinkles finer)",
        default=0.002, min=1e-6, max=0.5, precision=4, step=0.01,
    )
    pressure: bpy.props.FloatProperty(
        name="Pressure",
        description="Net outside over-pressure at the rest volume (> 0 compresses, < 0 "
                    "inflates); keyframable",
        default=4.0, min=-1e6, max=1e6,
    )
    collisions: bpy.props.BoolProperty(
        name="Collisions", description="The shell never passes through itself", default=True,
    )
    region_group: bpy.props.StringProperty(
        name="Region group",
        description="Vertex group whose weights (0..1) are the local contraction's strength: "
                    "the weighted faces sink in; empty = no regions",
        default="",
    )
    region_shrink: bpy.props.FloatProperty(
        name="Region shrink",
        description="Strength of the local contraction at weight 1", default=0.7, min=0.0, max=1.0,
    )
    frame_step: bpy.props.IntProperty(
        name="Key every",
        description="One shape key every this many simulation frames (and the last one)",
        default=2, min=1, max=1000,
    )
    # Read-only outcome of the last run, shown in the panel.
    status: bpy.props.StringProperty(name="Status", default="")
