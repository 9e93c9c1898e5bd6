"""Preferences (where the spinmotor module is), the per-scene panel settings and the sidebar panel
(3D Viewport > Sidebar > Spinmotor)."""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

from . import loader, ops


class SpinmotorPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    module_dir: StringProperty(
        name="spinmotor module folder", subtype='DIR_PATH', default="",
        description="The folder that contains the spinmotor package (e.g. <build>/python, or the target of "
                    "pip install --target); used when Blender's Python does not find it by itself")

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "module_dir")
        ok, text = loader.status(self.module_dir)
        layout.label(text=text if ok else "Not found: restart Blender after setting the folder",
                     icon='CHECKMARK' if ok else 'ERROR')


class SpinmotorSettings(bpy.types.PropertyGroup):
    pin_group: StringProperty(name="Pin group", default="",
                              description="Pin this vertex group's vertices instead of choosing pins from bone weights")
    threshold: FloatProperty(name="Threshold", default=ops.RIG_DEFAULTS["threshold"], min=0.5, max=1.0, precision=4,
                             description="Pin vertices whose dominant bone weight is at least this")
    per_bone_margin: BoolProperty(name="Per-bone margin", default=True,
                                  description="The library's default room for the joints: per bone, a quarter of the "
                                              "widest blend band of its joints (off: the Margin distance)")
    margin: FloatProperty(name="Margin", default=0.0, min=0.0, unit='LENGTH',
                          description="With Per-bone margin off: pins lie farther than this from every blended vertex")
    pose_weight: FloatProperty(name="Pose weight", default=ops.RIG_DEFAULTS["pose_weight"], min=0.0,
                               description="Hold the soft parts near the armature pose (0 = the pins only)")
    frame_start: IntProperty(name="Start", default=1)
    frame_end: IntProperty(name="End", default=1)
    keep: EnumProperty(name="Keep", items=ops.KEEP_ITEMS, default=ops.RIG_DEFAULTS["keep"])
    output: EnumProperty(name="Output", items=ops.OUTPUT_ITEMS, default="SHAPE_KEY")
    tradeoff: FloatProperty(name="Trade-off", default=1.0, min=0.0, max=1.0, subtype='FACTOR',
                            description="Snap: 0 follows the edit, 1 is conformal")
    q_max: FloatProperty(name="Q max", default=1.5, min=1.001, description="Q shown red")
    pose_snap: FloatProperty(name="Snap", default=0.0, min=0.0, max=1.0, subtype='FACTOR',
                             description="Pose by handles, then snap (0 = no snap)")


class SPINMOTOR_PT_panel(bpy.types.Panel):
    bl_label = "Spinmotor"
    bl_idname = "SPINMOTOR_PT_panel"
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "Spinmotor"

    def draw(self, context):
        layout = self.layout
        s = context.scene.spinmotor
        obj = context.active_object
        ok, text = loader.status(ops.prefs_dir(context))
        if not ok:
            layout.label(text="spinmotor module not found:", icon='ERROR')
            layout.label(text="set its folder in Preferences > Add-ons")

        box = layout.box()
        box.label(text="Conformal cleanup (keeps the pose)")
        if obj is not None and obj.type == 'MESH':
            box.prop_search(s, "pin_group", obj, "vertex_groups")
        if not s.pin_group:
            box.prop(s, "threshold")
            row = box.row(align=True)
            row.prop(s, "per_bone_margin")
            if not s.per_bone_margin:
                row.prop(s, "margin")
        box.prop(s, "pose_weight")
        row = box.row(align=True)
        row.prop(s, "frame_start")
        row.prop(s, "frame_end")
        box.prop(s, "keep")
        box.prop(s, "output")
        op = box.operator(ops.SPINMOTOR_OT_bake_cleanup.bl_idname, icon='SHAPEKEY_DATA')
        for name in ("pin_group", "threshold", "per_bone_margin", "margin", "pose_weight", "frame_start", "frame_end",
                     "keep", "output"):
            setattr(op, name, getattr(s, name))
        if not s.pin_group:
            op = box.operator(ops.SPINMOTOR_OT_pins_to_group.bl_idname, icon='GROUP_VERTEX')
            op.threshold, op.per_bone_margin, op.margin = s.threshold, s.per_bone_margin, s.margin

        box = layout.box()
        box.label(text="Sculpted shape key")
        box.prop(s, "tradeoff", slider=True)
        box.operator(ops.SPINMOTOR_OT_snap.bl_idname, icon='MOD_SMOOTH').tradeoff = s.tradeoff

        box = layout.box()
        box.label(text="Texture stretch")
        box.prop(s, "q_max")
        box.operator(ops.SPINMOTOR_OT_q_colors.bl_idname, icon='COLOR').q_max = s.q_max

        box = layout.box()
        box.label(text="Motor handles")
        box.operator(ops.SPINMOTOR_OT_add_handle.bl_idname, icon='EMPTY_AXIS')
        box.prop(s, "pose_snap", slider=True)
        box.operator(ops.SPINMOTOR_OT_pose_handles.bl_idname, icon='ARMATURE_DATA').tradeoff = s.pose_snap


classes = (SpinmotorPreferences, SpinmotorSettings, SPINMOTOR_PT_panel)


def register_settings():
    bpy.types.Scene.spinmotor = PointerProperty(type=SpinmotorSettings)


def unregister_settings():
    del bpy.types.Scene.spinmotor
