"""The sidebar panel of the active mesh (3D view, N, tab ShellContract)."""

import bpy

from . import operator, placement


class VIEW3D_PT_shellcontract(bpy.types.Panel):
    bl_label = "ShellContract"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "ShellContract"

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH"

    def draw(self, context):
        obj = context.active_object
        s = obj.shellcontract
        layout = self.layout
        layout.use_property_split = True
        col = layout.column()
        col.prop(s, "target_volume")  # keyframable: I over the field, or its context menu
        col.prop(s, "pressure")
        col.prop(s, "frames")
        col.prop(s, "thickness")
        col.prop(s, "collisions")
        col.prop_search(s, "region_group", obj, "vertex_groups")
        sub = col.column()
        sub.active = bool(s.region_group)
        sub.prop(s, "region_shrink")
        col.prop(s, "frame_step")
        row = layout.row()
        job = operator.RUNNING.get(operator.run_key(obj))
        refused = placement.library_refusal(obj)
        if refused:  # the button would be greyed out: say why, the fix first
            box = layout.box()
            box.label(text="Make it local first (Object > Relations > Make Local)", icon="ERROR")
            box.label(text=refused)
        if job is not None:
            row.label(text="Frame {} of {} (Esc cancels)".format(job.progress, s.frames))
        else:
            row.operator("object.shellcontract_contract", icon="MOD_SOFT")
        if s.status:
            layout.label(text=s.status)
