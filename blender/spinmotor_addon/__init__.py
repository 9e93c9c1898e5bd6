"""spinmotor for Blender: the pose-keeping conformal cleanup, the conformal snap, Q colours and motor posing
with surface harmonic coordinates, through the spinmotor Python module (python/ of the repository).

Install: build the module (python/README.md), zip this folder (or point Blender's script path at blender/),
enable "spinmotor" in Preferences > Add-ons and set the module's folder there if Blender does not find it.
Use: 3D Viewport > Sidebar (N) > Spinmotor, or the operators bpy.ops.spinmotor.bake_cleanup, .snap,
.q_colors, .add_handle, .pose_handles, .pins_to_group.
"""
bl_info = {
    "name": "spinmotor",
    "author": "spinmotor authors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D Viewport > Sidebar > Spinmotor",
    "description": "Conformal cleanup of posed meshes (corrective shape keys), conformal snap of sculpted keys, "
                   "Q colours, motor handles (spinmotor Python module)",
    "category": "Mesh",
}

if "bpy" in locals():  # F8 / script reload: reload the submodules too
    import importlib
    loader = importlib.reload(loader)  # noqa: F821
    meshdata = importlib.reload(meshdata)  # noqa: F821
    ops = importlib.reload(ops)  # noqa: F821
    ui = importlib.reload(ui)  # noqa: F821
else:
    from . import loader, meshdata, ops, ui  # noqa: F401

import bpy  # noqa: E402

_classes = ops.classes + ui.classes


def register():
    for c in _classes:
        bpy.utils.register_class(c)
    ui.register_settings()


def unregister():
    ui.unregister_settings()
    for c in reversed(_classes):
        bpy.utils.unregister_class(c)
