"""README pictures of the add-on, rendered headless by Blender itself (Cycles on the CPU):

    blender -b --factory-startup --python blender/render_readme.py -- [--module-dir build/python] [--out docs/gallery]

The two-bone arm of tests/blender/test_addon.py (capsule r = 1, elbow bent 90 degrees by an Armature
modifier with smoothstep weights), twice: on the left Blender's armature (linear blend skinning), on the
right the same rig with the corrective shape key baked by bpy.ops.spinmotor.bake_cleanup. Writes
blender-cleanup-checker.png (a checker in rest-space coordinates: squares stay squares where the map is
conformal) and blender-cleanup-q.png (the add-on's Q colours, 1 blue ... 1.5 red).
"""
import math
import os
import sys

import addon_utils
import bpy
import numpy as np
from mathutils import Quaternion, Vector

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def arg(name, default):
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    return os.path.abspath(argv[argv.index(name) + 1]) if name in argv else default


def make_arm(sm, name, y):
    m = sm.capsule(1.0, 6.0, 93, 64)
    V, F = m.V, m.F
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(v) for v in V.tolist()], [], [tuple(f) for f in F.tolist()])
    me.update()
    for p in me.polygons:
        p.use_smooth = True
    rest = me.attributes.new("rest", 'FLOAT_VECTOR', 'POINT')  # rest positions ride along the deformation
    rest.data.foreach_set("vector", V.astype(np.float32).ravel())
    ob = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(ob)
    t = np.clip((V[:, 2] - 2.0) / 2.0, 0.0, 1.0)
    w = t * t * (3 - 2 * t)
    for bone, ws in (("upper", 1 - w), ("lower", w)):
        vg = ob.vertex_groups.new(name=bone)
        for i in np.flatnonzero(ws > 0):
            vg.add([int(i)], float(ws[i]), 'REPLACE')
    arm = bpy.data.armatures.new(name + "_rig")
    rig = bpy.data.objects.new(name + "_rig", arm)
    bpy.context.scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode='EDIT')
    up = arm.edit_bones.new("upper")
    up.head, up.tail = (0, 0, -1), (0, 0, 3)
    lo = arm.edit_bones.new("lower")
    lo.head, lo.tail = (0, 0, 3), (0, 0, 7)
    lo.parent, lo.use_connect = up, True
    bpy.ops.object.mode_set(mode='OBJECT')
    ob.modifiers.new("Armature", 'ARMATURE').object = rig
    pb = rig.pose.bones["lower"]
    pb.rotation_mode = 'QUATERNION'
    pb.rotation_quaternion = Quaternion((1, 0, 0), math.radians(90))
    ob.location = rig.location = (0, y, 0)
    rig.hide_render = True
    bpy.context.view_layer.objects.active = ob
    return ob


def material(kind):
    mat = bpy.data.materials.new(kind)
    mat.use_nodes = True
    nt = mat.node_tree
    bsdf = nt.nodes["Principled BSDF"]
    bsdf.inputs["Roughness"].default_value = 0.6
    if kind == "checker":
        a = nt.nodes.new("ShaderNodeAttribute")
        a.attribute_name = "rest"
        c = nt.nodes.new("ShaderNodeTexChecker")
        c.inputs["Scale"].default_value = 2.5
        c.inputs["Color1"].default_value = (0.80, 0.16, 0.02, 1)
        c.inputs["Color2"].default_value = (0.92, 0.90, 0.85, 1)
        nt.links.new(a.outputs["Vector"], c.inputs["Vector"])
        nt.links.new(c.outputs["Color"], bsdf.inputs["Base Color"])
    else:
        a = nt.nodes.new("ShaderNodeVertexColor")
        a.layer_name = "spinmotor_Q"
        nt.links.new(a.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def main():
    sys.path.insert(0, os.path.join(REPO, "blender"))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("spinmotor_addon", default_set=True)
    bpy.context.preferences.addons["spinmotor_addon"].preferences.module_dir = arg(
        "--module-dir", os.path.join(REPO, "build", "python"))
    import spinmotor_addon
    sm = spinmotor_addon.ops.spinmotor_module(bpy.context)
    out = arg("--out", os.path.join(REPO, "docs", "gallery"))
    scene = bpy.context.scene
    scene.frame_set(1)
    lbs = make_arm(sm, "lbs", 0.0)
    clean = make_arm(sm, "cleanup", 7.5)
    bpy.context.view_layer.objects.active = clean
    bpy.ops.spinmotor.bake_cleanup(threshold=0.999, margin=0.5, frame_start=1, frame_end=1)
    for ob in (lbs, clean):
        bpy.context.view_layer.objects.active = ob
        bpy.ops.spinmotor.q_colors(q_max=1.5)

    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(cam)
    scene.camera = cam
    cam.data.type = 'ORTHO'
    cam.data.ortho_scale = 14.5
    target = Vector((0, 2.4, 2.2))
    cam.location = target + Vector((20, -5, 7))
    cam.rotation_euler = (target - cam.location).to_track_quat('-Z', 'Y').to_euler()
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", 'SUN'))
    sun.data.energy = 3.5
    sun.rotation_euler = (math.radians(40), math.radians(10), math.radians(60))
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("world")
    world.color = (1, 1, 1)
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (1, 1, 1, 1)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.6
    scene.world = world

    r = scene.render
    r.engine = 'CYCLES'
    scene.cycles.device = 'CPU'
    scene.cycles.samples = 64
    scene.cycles.use_denoising = False
    r.resolution_x, r.resolution_y, r.resolution_percentage = 540, 300, 100
    r.film_transparent = True
    r.image_settings.file_format = 'PNG'
    r.image_settings.color_mode = 'RGBA'
    r.image_settings.compression = 100
    scene.view_settings.view_transform = 'Standard'
    for kind in ("checker", "q"):
        mat = material(kind)
        for ob in (lbs, clean):
            ob.data.materials.clear()
            ob.data.materials.append(mat)
        r.filepath = os.path.join(out, f"blender-cleanup-{kind}.png")
        bpy.ops.render.render(write_still=True)
        print("wrote", r.filepath)


main()
