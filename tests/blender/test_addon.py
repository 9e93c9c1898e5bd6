"""Headless test of the Blender add-on (blender/spinmotor_addon):

    blender -b --factory-startup --python-exit-code 1 --python tests/blender/test_addon.py -- [--module-dir DIR]

DIR holds the spinmotor package (default: $SPINMOTOR_PYTHONPATH, else <repo>/build/python); it is set as the
add-on's preference, the way an artist would. scripts/ci-blender runs this (CI, after the Python tests).

The two-bone arm is the C++ test's (tests/spin/test_pinned_cleanup.cpp): a capsule of radius 1 with its
cylinder on z in [0, 6], 93 rings x 64 sides, the lower bone's weight a smoothstep over z in [2, 4], an
Armature modifier whose lower bone turns 90 degrees about x at the elbow (0, 0, 3). Blender's armature
result is checked against the closed-form linear blend skinning, then the add-on's bake against the C++
test's figures (pins to 1e-9 of the diagonal, Q_mean <= 1.06 and below the armature's, Q_max <= 1.5,
volume ratio >= 0.93 and equal to the library's measure ratio), against a direct call of the module on the
same arrays (1e-12) and through Blender's float32 storage (the corrective key reproduces the cleanup
through the armature). Bad inputs give an error report and leave the object as it was.

The add-on cleans through spinmotor.RigCleanup on the mesh welded by rest position: a mesh of loose triangles
(split seams, as the glTF importer leaves the Fox) gives the welded mesh's result at every copy; a bake of two
meshes on one armature writes keys on the deformed one and none on a rigid one (and nothing on either when one
fails); the per-bone default margin (the armature's rest bones in the mesh's space) gives RigCleanup's own pins;
each frame's edit is the armature's pose at that frame, without the previous frame's correction.
"""
import math
import os
import sys
import time
import traceback

try:
    import bpy
except ImportError:
    print("SKIP: tests/blender/test_addon.py runs inside Blender: blender -b --factory-startup --python ...")
    sys.exit(0)
import addon_utils
import numpy as np
from mathutils import Matrix, Quaternion, Vector

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))


def module_dir():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if "--module-dir" in argv:
        return os.path.abspath(argv[argv.index("--module-dir") + 1])
    env = os.environ.get("SPINMOTOR_PYTHONPATH", "")
    return os.path.abspath(env.split(os.pathsep)[0]) if env else os.path.join(REPO, "build", "python")


# ---- independent measures (numpy, not the add-on's) ---------------------------------------------------------


def quality(V0, F, V):
    """Area-weighted (rest areas) mean and max of Q = sigma_max / sigma_min per triangle, computed from the
    2x2 Gram matrix of the map in an orthonormal frame of each rest triangle (the C++ test's formula)."""
    qs, ws, collapsed = [], [], 0
    P0, P1, P2 = V0[F[:, 0]], V0[F[:, 1]], V0[F[:, 2]]
    Q0, Q1, Q2 = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    for f in range(len(F)):
        u, w = P1[f] - P0[f], P2[f] - P0[f]
        x = u / np.linalg.norm(u)
        y = w - w.dot(x) * x
        y /= np.linalg.norm(y)
        P = np.array([[u.dot(x), w.dot(x)], [u.dot(y), w.dot(y)]])
        J = np.column_stack([Q1[f] - Q0[f], Q2[f] - Q0[f]]) @ np.linalg.inv(P)
        s = np.linalg.svd(J, compute_uv=False)
        if s[1] <= 1e-12 * s[0]:
            collapsed += 1
            continue
        qs.append(s[0] / s[1])
        ws.append(0.5 * np.linalg.norm(np.cross(u, w)))
    qs, ws = np.array(qs), np.array(ws)
    return float((qs * ws).sum() / ws.sum()), float(qs.max()), collapsed


def volume(V, F):
    return float(sum(np.dot(V[a], np.cross(V[b], V[c])) for a, b, c in F) / 6.0)


def diag(V):
    return float(np.linalg.norm(V.max(0) - V.min(0)))


def smoothstep_weights(V):
    t = np.clip((V[:, 2] - 2.0) / 2.0, 0.0, 1.0)
    w = t * t * (3 - 2 * t)
    return np.column_stack([1 - w, w])


def rot_x(deg):
    a = math.radians(deg)
    return np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])


def arm_lbs(V, W, bend):
    elbow = np.array([0.0, 0.0, 3.0])
    moved = (V - elbow) @ rot_x(bend).T + elbow
    return W[:, :1] * V + W[:, 1:] * moved


# ---- reading Blender data independently of the add-on --------------------------------------------------------


def read_co(collection, n):
    a = np.empty(3 * n, np.float32)
    collection.foreach_get("co", a)
    return a.reshape(n, 3).astype(np.float64)


def evaluated(ob):
    dg = bpy.context.evaluated_depsgraph_get()
    oe = ob.evaluated_get(dg)
    me = oe.to_mesh()
    V = read_co(me.vertices, len(me.vertices))
    oe.to_mesh_clear()
    return V


def loop_triangles(me):
    me.calc_loop_triangles()
    F = np.empty(3 * len(me.loop_triangles), np.int32)
    me.loop_triangles.foreach_get("vertices", F)
    return F.reshape(-1, 3).astype(np.int64)


def snapshot(ob):
    """Everything an operator could leave behind on the object."""
    me = ob.data
    keys = me.shape_keys
    return {
        "co": read_co(me.vertices, len(me.vertices)),
        "keys": [(kb.name, kb.mute, kb.value, read_co(kb.data, len(me.vertices)).tobytes())
                 for kb in keys.key_blocks] if keys else None,
        "active_key": ob.active_shape_key_index,
        "groups": [g.name for g in ob.vertex_groups],
        "attributes": sorted(a.name for a in me.attributes),
        "frame": bpy.context.scene.frame_current,
        "objects": sorted(o.name for o in bpy.data.objects),
        "meshes": len(bpy.data.meshes),
    }


def same_snapshot(a, b):
    return (np.array_equal(a["co"], b["co"]) and a["keys"] == b["keys"] and
            all(a[k] == b[k] for k in ("active_key", "groups", "attributes", "frame", "objects", "meshes")))


def expect_error(op, fragment, ob, **kw):
    """The operator reports an ERROR containing `fragment` (bpy.ops raises it as RuntimeError) and leaves `ob`
    and the file as they were."""
    before = snapshot(ob)
    try:
        op(**kw)
    except RuntimeError as e:
        msg = str(e)
    else:
        raise AssertionError(f"{op.idname()}({kw}) succeeded, expected an error with '{fragment}'")
    assert fragment in msg, f"expected '{fragment}' in the report, got: {msg}"
    assert same_snapshot(before, snapshot(ob)), f"{op.idname()}({kw}) changed the object: {msg}"
    print(f"  error reported, object unchanged: {msg.strip()[:150]}")


# ---- scene building ---------------------------------------------------------------------------------------


def link(ob):
    bpy.context.scene.collection.objects.link(ob)
    return ob


def activate(ob):
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)


def mesh_object(name, V, F):
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(v) for v in V.tolist()], [], [tuple(f) for f in F.tolist()])
    me.update()
    return link(bpy.data.objects.new(name, me))


ARM_BONES = [("upper", None, (0.0, 0.0, -1.0), (0.0, 0.0, 3.0)), ("lower", 0, (0.0, 0.0, 3.0), (0.0, 0.0, 7.0))]


def make_arm(sm, name, rings=93, sides=64, split=False, turned=False):
    """The two-bone arm: the capsule weighted by smoothstep_weights, an Armature modifier on a two-bone rig whose
    bones are ARM_BONES in the mesh's space. split=True gives every triangle its own three vertices (as an
    importer leaves a mesh whose corners all have their own texture coordinates: the Fox arrives so): returns the
    capsule's V, F all the same, the copies in order (vertex 3f + c is corner c of triangle f). turned=True turns
    the armature object 90 degrees about x and its bones back (along its local y), so that its bones' head_local
    and tail_local differ from the mesh-space bones."""
    V, F = sm.capsule(1.0, 6.0, rings, sides)
    Vm, Fm = (V[F].reshape(-1, 3), np.arange(3 * len(F)).reshape(-1, 3)) if split else (V, F)
    ob = mesh_object(name, Vm, Fm)
    W = smoothstep_weights(Vm)
    for c, bone in enumerate(("upper", "lower")):
        vg = ob.vertex_groups.new(name=bone)
        for i in np.flatnonzero(W[:, c] > 0):
            vg.add([int(i)], float(W[i, c]), 'REPLACE')
    arm = bpy.data.armatures.new(name + "_rig")
    rig = link(bpy.data.objects.new(name + "_rig", arm))
    local = (lambda p: (p[0], p[2], -p[1])) if turned else (lambda p: p)  # rot_x(-90): mesh space -> armature's
    if turned:
        rig.rotation_euler = (math.radians(90), 0, 0)
    activate(rig)
    bpy.ops.object.mode_set(mode='EDIT')
    up = arm.edit_bones.new("upper")
    up.head, up.tail, up.roll = local(ARM_BONES[0][2]), local(ARM_BONES[0][3]), 0.0
    lo = arm.edit_bones.new("lower")
    lo.head, lo.tail, lo.roll = local(ARM_BONES[1][2]), local(ARM_BONES[1][3]), 0.0
    lo.parent, lo.use_connect = up, True
    bpy.ops.object.mode_set(mode='OBJECT')
    mod = ob.modifiers.new("Armature", 'ARMATURE')
    mod.object = rig
    activate(ob)
    return ob, rig, V, F


def pose_elbow(rig, degrees):
    pb = rig.pose.bones["lower"]
    pb.rotation_mode = 'QUATERNION'
    pb.rotation_quaternion = Quaternion((1, 0, 0), math.radians(degrees))
    bpy.context.view_layer.update()


# ---- tests --------------------------------------------------------------------------------------------------------


def test_module_missing(addon):
    """Before the module's folder is set (and when Python does not find it by itself) every operator reports
    where it looked, and changes nothing."""
    import importlib.util
    if importlib.util.find_spec("spinmotor") is not None:
        print("  (spinmotor is importable without the preference, e.g. installed system-wide: skipped)")
        return
    saved = addon.loader.REPO_BUILD_DIR, os.environ.pop("SPINMOTOR_PYTHONPATH", None)
    addon.loader.REPO_BUILD_DIR = os.path.join(REPO, "no-such-build", "python")  # as if installed from a zip
    me = bpy.data.meshes.new("tmp")
    me.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], [], [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)])
    ob = link(bpy.data.objects.new("tmp", me))
    activate(ob)
    for op in (bpy.ops.spinmotor.bake_cleanup, bpy.ops.spinmotor.pose_handles):
        expect_error(op, "spinmotor Python module was not found", ob)
    ob.shape_key_add(name="Basis", from_mix=False)
    ob.shape_key_add(name="edit", from_mix=False)
    ob.active_shape_key_index = 1
    expect_error(bpy.ops.spinmotor.snap, "Preferences > Add-ons > spinmotor", ob)
    assert bpy.ops.spinmotor.q_colors() == {'FINISHED'}  # numpy only: works without the module
    addon.loader.REPO_BUILD_DIR = saved[0]
    if saved[1] is not None:
        os.environ["SPINMOTOR_PYTHONPATH"] = saved[1]
    bpy.data.objects.remove(ob)
    bpy.data.meshes.remove(me)


def test_bake_cleanup(sm, addon):
    t0 = time.time()
    ob, rig, Vc, Fc = make_arm(sm, "arm")
    n = len(Vc)
    V0 = read_co(ob.data.vertices, n)  # float32-rounded capsule: the rest mesh Blender has
    F = loop_triangles(ob.data)
    assert np.array_equal(F, Fc), "Blender kept the capsule's triangles"
    assert np.abs(V0 - Vc).max() < 1e-6
    W32 = np.zeros((n, 2))
    for v in ob.data.vertices:
        for g in v.groups:
            W32[v.index, g.group] = g.weight
    pose_elbow(rig, 90)
    E = evaluated(ob)
    # Blender's armature is the C++ test's linear blend skinning (float32 data): the same edit.
    ref = arm_lbs(V0, W32, 90)
    lbs_err = np.abs(E - ref).max() / diag(ref)
    print(f"  arm: {n} vertices, {len(F)} triangles; Blender armature vs closed-form LBS: {lbs_err:.2e} of the "
          "diagonal")
    assert lbs_err < 1e-6, lbs_err

    before = snapshot(ob)
    res = bpy.ops.spinmotor.bake_cleanup(threshold=0.999, per_bone_margin=False, margin=0.5, frame_start=1, frame_end=1)
    assert res == {'FINISHED'}, res
    after = snapshot(ob)  # the mesh, its groups and the frame as they were; only the key is new
    assert all(np.array_equal(before[k], after[k]) for k in ("co", "groups", "frame", "objects", "attributes"))
    L = addon.ops.LAST["bake_cleanup"]
    r = L["frames"][1]
    V = r["V"]
    # The add-on read the same arrays as this test did.
    assert np.array_equal(L["V0"], V0) and np.array_equal(L["F"], F) and np.array_equal(r["V_edit"], E)
    # Pins: the library's selection on Blender's weights; the C++ test's rule (z < 1.55 or z > 4.45).
    pins = np.asarray(sm.pins_from_weights(V0, W32, 0.999, 0.5))
    assert np.array_equal(np.sort(L["pins"]), np.sort(pins)), "pins differ from pins_from_weights"
    z = V0[pins, 2]
    assert np.all((z < 1.55) | (z > 4.45)), "a pin inside the blend band"
    # The direct module call on the same arrays, with the rig defaults (pose attraction γ = 10, weights from
    # the bones), gives the same result.
    # (the add-on's threshold is a Blender float property: 0.999 rounded to float32)
    attraction = sm.pin_attraction_from_weights(addon.meshdata.bone_weights(ob)[0], float(np.float32(0.999)))
    direct = sm.PinnedCleanup(V0, F, pins, pose_weight=10.0, attraction=attraction).cleanup(E, full=True)
    d = diag(E)
    dev = np.abs(direct["V"] - V).max() / d
    assert dev <= 1e-12, f"add-on vs direct call: {dev:.3e}"
    # ...which is what the library's rig cleanup (the add-on's door) does on one piece with these pins.
    W = addon.meshdata.bone_weights(ob)[0]
    rc = sm.RigCleanup(V0, F, W, bones=ARM_BONES, threshold=float(np.float32(0.999)), margin=0.5)
    assert np.array_equal(np.asarray(rc.pins), np.sort(pins))
    dev_rc = np.abs(rc.cleanup(E) - V).max() / d
    assert dev_rc <= 1e-12, f"add-on vs RigCleanup: {dev_rc:.3e}"
    assert L["piece_counts"] == {"cleaned": 1} and not L["unchanged"], (L["piece_counts"], L["unchanged"])
    # The attraction holds the pose: nearer the armature's result than the pins-only cleanup.
    pins_only = sm.PinnedCleanup(V0, F, pins).cleanup(E)
    assert np.linalg.norm(V - E) < 0.8 * np.linalg.norm(pins_only - E), (np.linalg.norm(V - E),
                                                                         np.linalg.norm(pins_only - E))
    pin_err = np.linalg.norm(V[pins] - E[pins], axis=1).max() / d
    assert pin_err <= 1e-9, pin_err
    q_lbs, qmax_lbs, _ = quality(V0, F, E)
    q_c, qmax_c, collapsed = quality(V0, F, V)
    vol0 = volume(V0, F)
    ve, vc = volume(E, F) / vol0, volume(V, F) / vol0
    print(f"  bend 90: LBS Q_mean {q_lbs:.4f} Q_max {qmax_lbs:.4g} vol {ve:.4f} | cleanup Q_mean {q_c:.4f} "
          f"Q_max {qmax_c:.4f} vol {vc:.4f} | pins {len(pins)}, pin error {pin_err:.1e}, "
          f"{r['iterations']} iterations; add-on vs direct PinnedCleanup {dev:.1e}, RigCleanup {dev_rc:.1e}")
    assert collapsed == 0
    assert q_c < q_lbs and q_c <= 1.06 and qmax_c <= 1.5, (q_c, q_lbs, qmax_c)
    assert vc >= 0.93, vc
    assert abs(r["measure_ratio"] - vc) <= 1e-9 * vc, (r["measure_ratio"], vc)
    assert abs(r["metrics"]["q_mean"] - q_c) <= 1e-9 and abs(r["metrics_edit"]["q_mean"] - q_lbs) <= 1e-9
    # Written: one key, relative to the basis, keyframed 0/1/0 around frame 1; through the armature it gives
    # the cleanup up to float32.
    key = ob.data.shape_keys
    names = [kb.name for kb in key.key_blocks]
    assert names == ["Basis", "spinmotor_cleanup_0001"], names
    assert np.array_equal(read_co(key.reference_key.data, n), V0), "the basis is the rest mesh"
    kb = key.key_blocks["spinmotor_cleanup_0001"]
    fc = key.animation_data.action.fcurves.find('key_blocks["spinmotor_cleanup_0001"].value')
    assert [tuple(p.co) for p in fc.keyframe_points] == [(0.0, 0.0), (1.0, 1.0), (2.0, 0.0)]
    assert bpy.context.scene.frame_current == 1 and kb.value == 1.0 and not kb.mute
    Eb = evaluated(ob)
    key_err = np.abs(Eb - V).max() / d
    pin32 = np.abs(Eb[pins] - E[pins]).max() / d
    print(f"  key through the armature vs cleanup: {key_err:.1e} (pins {pin32:.1e}) of the diagonal "
          f"(float32 storage); Newton residual {r['key_residual']:.1e}")
    assert key_err <= 2e-6 and pin32 <= 2e-6, (key_err, pin32)
    q32, _, _ = quality(V0, F, Eb)
    assert abs(q32 - q_c) <= 1e-4
    # Other frames: the key is off and the armature result is back.
    bpy.context.scene.frame_set(5)
    assert np.abs(evaluated(ob) - E).max() / d < 1e-6
    bpy.context.scene.frame_set(1)

    # Re-bake the same frame: the key is overwritten (no duplicate), the earlier bake is not part of the edit.
    bpy.ops.spinmotor.bake_cleanup(threshold=0.999, per_bone_margin=False, margin=0.5, frame_start=1, frame_end=1)
    assert [kb.name for kb in key.key_blocks] == names
    assert np.array_equal(addon.ops.LAST["bake_cleanup"]["frames"][1]["V_edit"], E)
    assert np.abs(addon.ops.LAST["bake_cleanup"]["frames"][1]["V"] - V).max() <= 1e-12 * d

    # The pins as a vertex group, then used as the pin group: the same cleanup.
    assert bpy.ops.spinmotor.pins_to_group(threshold=0.999, per_bone_margin=False, margin=0.5) == {'FINISHED'}
    assert np.array_equal(addon.meshdata.group_members(ob, "spinmotor_pins"), np.sort(pins))
    bpy.ops.spinmotor.bake_cleanup(pin_group="spinmotor_pins")
    assert np.abs(addon.ops.LAST["bake_cleanup"]["frames"][1]["V"] - V).max() <= 1e-12 * d
    ob.vertex_groups.remove(ob.vertex_groups["spinmotor_pins"])

    # Errors: each reported, nothing written.
    op = bpy.ops.spinmotor.bake_cleanup
    expect_error(op, "no vertex group named 'nope'", ob, pin_group="nope")
    ob.vertex_groups.new(name="empty")
    expect_error(op, "no pinned vertex", ob, pin_group="empty")  # the library's message
    for b in rig.data.bones:
        b.use_deform = False
    expect_error(op, "no vertex group is named after a deform bone", ob)
    for b in rig.data.bones:
        b.use_deform = True
    expect_error(op, "frame range", ob, frame_start=3, frame_end=2)
    ob.vertex_groups.remove(ob.vertex_groups["empty"])
    print(f"  bake test {time.time() - t0:.1f} s")
    return ob, rig, V0, F, E, V


def test_frame_range(sm, addon):
    """Two frames with different poses: two keys, each the cleanup of its own frame's pose; a failure in the
    last frame leaves no key and no basis behind."""
    ob, rig, Vc, F = make_arm(sm, "arm2", 40, 24)
    pb = rig.pose.bones["lower"]
    pb.rotation_mode = 'QUATERNION'
    for f, deg in ((1, 45), (2, 90)):
        pb.rotation_quaternion = Quaternion((1, 0, 0), math.radians(deg))
        pb.keyframe_insert("rotation_quaternion", frame=f)
    bpy.context.scene.frame_set(1)
    # Failure first: a Subdivision modifier changes the vertex count; nothing may stay (not even a basis).
    sub = ob.modifiers.new("Subdivision", 'SUBSURF')
    expect_error(bpy.ops.spinmotor.bake_cleanup, "vertex count", ob, threshold=0.999, margin=0.5, frame_start=1,
                 frame_end=2)
    assert ob.data.shape_keys is None
    ob.modifiers.remove(sub)
    bpy.ops.spinmotor.bake_cleanup(threshold=0.999, per_bone_margin=False, margin=0.5, frame_start=1, frame_end=2)
    L = addon.ops.LAST["bake_cleanup"]
    V0 = read_co(ob.data.vertices, len(Vc))
    # The reference: the rig defaults (attraction from the bone weights, the add-on's float32 threshold) and
    # the warm start, the frames cleaned in order as the add-on does.
    a = sm.pin_attraction_from_weights(addon.meshdata.bone_weights(ob)[0], float(np.float32(0.999)))
    ref_cleanup = sm.PinnedCleanup(V0, F, L["pins"], pose_weight=10.0, attraction=a, warm_start=True)
    # Each frame's edit is the armature's own pose at that frame (the keys muted): not the previous frame's
    # corrective key on top of it (the bake's scratch key is cleared between frames).
    keys = ob.data.shape_keys.key_blocks
    for kb in keys[1:]:
        kb.mute = True
    for f in (1, 2):
        bpy.context.scene.frame_set(f)
        edit_err = np.abs(L["frames"][f]["V_edit"] - evaluated(ob)).max() / diag(Vc)
        print(f"  frame {f}: the bake's edit vs the armature pose without keys {edit_err:.1e}")
        assert edit_err <= 1e-12, (f, edit_err)
    for kb in keys[1:]:
        kb.mute = False
    for f in (1, 2):
        bpy.context.scene.frame_set(f)
        Vf = L["frames"][f]["V"]
        Ef = L["frames"][f]["V_edit"]
        ref = ref_cleanup.cleanup(Ef)
        assert np.abs(ref - Vf).max() <= 1e-12 * diag(Ef)
        got = evaluated(ob)
        err = np.abs(got - Vf).max() / diag(Vf)
        assert err <= 2e-6, (f, err)
        print(f"  frame {f}: Q_mean {L['frames'][f]['metrics_edit']['q_mean']:.4f} -> "
              f"{L['frames'][f]['metrics']['q_mean']:.4f}, key through armature vs cleanup {err:.1e}")
    assert [kb.name for kb in ob.data.shape_keys.key_blocks] == ["Basis", "spinmotor_cleanup_0001",
                                                                  "spinmotor_cleanup_0002"]
    # Output as new objects.
    nobj = len(bpy.data.objects)
    activate(ob)
    bpy.ops.spinmotor.bake_cleanup(threshold=0.999, per_bone_margin=False, margin=0.5, frame_start=2, frame_end=2,
                                   output='OBJECT')
    assert len(bpy.data.objects) == nobj + 1
    new = bpy.data.objects["arm2_cleanup_0002"]
    got = read_co(new.data.vertices, len(Vc))
    assert np.abs(got - addon.ops.LAST["bake_cleanup"]["frames"][2]["V"]).max() <= 1e-6 * diag(got)
    bpy.context.scene.frame_set(1)


def test_bad_meshes(sm, addon):
    # Non-manifold: a fin (three triangles on one edge), pinned by a group: the library's check message.
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1.0]])
    ob = mesh_object("fin", V, np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]]))
    vg = ob.vertex_groups.new(name="pins")
    vg.add([0, 1], 1.0, 'REPLACE')
    activate(ob)
    expect_error(bpy.ops.spinmotor.bake_cleanup, "non-manifold edge", ob, pin_group="pins")
    # No armature and no pin group.
    V, F = sm.icosphere(2)
    ob2 = mesh_object("ball", V, F)
    activate(ob2)
    expect_error(bpy.ops.spinmotor.bake_cleanup, "no Armature modifier", ob2)
    # Quads are triangulated by Blender (loop triangles): a cube with a pinned face bakes. Undeformed, the cleanup
    # leaves it as it is: no key (not even a basis); twisted by a modifier, it gets its key.
    bpy.ops.mesh.primitive_cube_add(size=2)
    cube = bpy.context.active_object
    vg = cube.vertex_groups.new(name="top")
    vg.add([v.index for v in cube.data.vertices if v.co.z > 0], 1.0, 'REPLACE')
    assert bpy.ops.spinmotor.bake_cleanup(pin_group="top") == {'FINISHED'}
    assert cube.data.shape_keys is None, [kb.name for kb in cube.data.shape_keys.key_blocks]
    L = addon.ops.LAST["bake_cleanup"]
    assert L["unchanged"] and L["keys"] == [] and L["frames"][1]["change"] <= 1e-9, L["frames"][1]["change"]
    twist = cube.modifiers.new("Twist", 'SIMPLE_DEFORM')
    twist.deform_method, twist.angle, twist.deform_axis = 'TWIST', math.radians(40), 'Z'
    assert bpy.ops.spinmotor.bake_cleanup(pin_group="top") == {'FINISHED'}
    assert [kb.name for kb in cube.data.shape_keys.key_blocks] == ["Basis", "spinmotor_cleanup_0001"]
    # A component without a pin (and no attraction): the library names it; nothing written.
    V1, F1 = sm.icosphere(1)
    both = mesh_object("two", np.vstack([V1, V1 + [3, 0, 0]]), np.vstack([F1, F1 + len(V1)]))
    vg = both.vertex_groups.new(name="pins")
    vg.add([0, 1, 2], 1.0, 'REPLACE')
    activate(both)
    # (with a pose weight, the uniform attraction of a mesh without bone weights anchors it: the pins alone here)
    expect_error(bpy.ops.spinmotor.bake_cleanup, "has no pinned vertex", both, pin_group="pins", pose_weight=0.0)
    # Edit mode: the operator is not available (poll), nothing happens.
    bpy.ops.object.mode_set(mode='EDIT')
    try:
        bpy.ops.spinmotor.bake_cleanup(pin_group="pins")
        raise AssertionError("bake ran in edit mode")
    except RuntimeError as e:
        assert "poll" in str(e) or "context" in str(e), e
    bpy.ops.object.mode_set(mode='OBJECT')


def test_snap(sm, addon):
    V, F = sm.capsule(0.5, 3.0, 40, 24)
    ob = mesh_object("sculpt", V, F)
    activate(ob)
    expect_error(bpy.ops.spinmotor.snap, "make the sculpted shape key active", ob)
    ob.shape_key_add(name="Basis", from_mix=False)
    expect_error(bpy.ops.spinmotor.snap, "make the sculpted shape key active", ob)
    kb = ob.shape_key_add(name="bulge", from_mix=False)
    V0 = read_co(ob.data.vertices, len(V))
    E = V0.copy()
    # A sculpted bulge: push the vertices near the middle outward along their radius.
    r = np.linalg.norm(E[:, :2], axis=1)
    bump = 0.25 * np.exp(-((E[:, 2] - 1.5) / 0.4) ** 2) * (E[:, 0] > 0)
    E[:, :2] *= (1 + bump / np.maximum(r, 1e-9))[:, None]
    kb.data.foreach_set("co", E.astype(np.float32).ravel())
    kb.value = 1.0
    ob.active_shape_key_index = 1
    E = read_co(kb.data, len(V))
    assert bpy.ops.spinmotor.snap(tradeoff=1.0) == {'FINISHED'}
    L = addon.ops.LAST["snap"]
    Ft = loop_triangles(ob.data)
    direct = sm.ConformalSnap(V0, Ft).snap(E, tradeoff=1.0)
    dev = np.abs(direct - L["V"]).max() / diag(E)
    assert dev <= 1e-12, dev
    q_e, _, _ = quality(V0, Ft, E)
    q_s, _, _ = quality(V0, Ft, L["V"])
    print(f"  snap: sculpted bulge Q_mean {q_e:.4f} -> {q_s:.4f}; add-on vs direct {dev:.1e}")
    assert q_s - 1 < (q_e - 1) / 3, (q_e, q_s)  # two thirds of the excess Q gone (measured 73%)
    keys = ob.data.shape_keys.key_blocks
    assert keys["bulge"].mute and not keys["bulge_snap"].mute and keys["bulge_snap"].value == 1.0
    got = evaluated(ob)
    assert np.abs(got - L["V"]).max() <= 1e-6 * diag(got)
    # The trade-off slider: toward 0 the result follows the edit (t = 0 is the edit's own similarity field,
    # integrated: near the edit, not equal to it), and the key is overwritten, not duplicated.
    dev = {}
    for t in (1.0, 0.5, 0.0):
        ob.active_shape_key_index = 1
        bpy.ops.spinmotor.snap(tradeoff=t)
        Vt = addon.ops.LAST["snap"]["V"]
        assert np.abs(Vt - sm.ConformalSnap(V0, Ft).snap(E, tradeoff=t)).max() <= 1e-12 * diag(E)
        dev[t] = np.sqrt(((Vt - E) ** 2).sum(1).mean()) / diag(E)
    print("  snap RMS distance to the edit by trade-off: " + ", ".join(f"{t:g}: {v:.2e}" for t, v in dev.items()))
    assert dev[0.0] < dev[0.5] < dev[1.0], dev
    assert [kb.name for kb in ob.data.shape_keys.key_blocks] == ["Basis", "bulge", "bulge_snap"]
    return ob


def test_q_colors(sm, addon, ob, V0, F, V_clean):
    activate(ob)
    bpy.context.scene.frame_set(5)  # the cleanup key is off: the armature's result
    assert bpy.ops.spinmotor.q_colors(q_max=1.5) == {'FINISHED'}
    L = addon.ops.LAST["q_colors"]
    m = sm.metrics(V0, L["V"], F)
    # The add-on's per-face Q (numpy) against the library's Q_mean.
    assert abs(L["q_mean"] - m["q_mean"]) <= 1e-9, (L["q_mean"], m["q_mean"])
    attr = ob.data.color_attributes["spinmotor_Q"]
    assert attr.domain == 'CORNER' and len(attr.data) == len(ob.data.loops)
    cols = np.empty(4 * len(attr.data), np.float32)
    attr.data.foreach_get("color", cols)
    cols = cols.reshape(-1, 4)
    # Triangles in the rigid parts are blue, the worst is the deep red.
    qv = np.empty(len(ob.data.polygons), np.float32)
    ob.data.attributes["spinmotor_Q_value"].data.foreach_get("value", qv)
    blue = np.array([49, 54, 149]) / 255  # the colour map's Q = 1, sRGB; the attribute holds linear values
    blue = np.where(blue <= 0.04045, blue / 12.92, ((blue + 0.055) / 1.055) ** 2.4)
    p_rigid = int(np.argmin(qv))
    assert abs(qv[p_rigid] - 1) < 1e-5
    assert np.abs(cols[ob.data.polygons[p_rigid].loop_start, :3] - blue).max() < 1e-3
    bpy.context.scene.frame_set(1)  # with the cleanup key
    bpy.ops.spinmotor.q_colors(q_max=1.5)
    q_after = addon.ops.LAST["q_colors"]["q_mean"]
    print(f"  Q colours: Q_mean armature {m['q_mean']:.4f} (library {L['q_mean']:.4f}), with the cleanup key "
          f"{q_after:.4f}")
    assert q_after < m["q_mean"]


def test_handles(sm, addon):
    V, F = sm.capsule(0.5, 3.0, 40, 24)
    ob = mesh_object("handled", V, F)
    ob.location = (5, 0, 0)
    base = np.flatnonzero(V[:, 2] < -0.2)
    tip = np.flatnonzero(V[:, 2] > 3.2)
    for name, idx in (("base", base), ("tip", tip)):
        vg = ob.vertex_groups.new(name=name)
        vg.add([int(i) for i in idx], 1.0, 'REPLACE')
    activate(ob)
    expect_error(bpy.ops.spinmotor.pose_handles, "no handle", ob)
    for name in ("base", "tip"):
        ob.vertex_groups.active_index = ob.vertex_groups[name].index
        assert bpy.ops.spinmotor.add_handle() == {'FINISHED'}
        activate(ob)
    expect_error(bpy.ops.spinmotor.add_handle, "already has the handle", ob)
    V0 = read_co(ob.data.vertices, len(V))
    c = V0[tip].mean(axis=0)
    e = bpy.data.objects["handled.tip"]
    assert (Vector(e.matrix_world.translation) - (ob.matrix_world @ Vector(c.tolist()))).length < 1e-5
    # Turn the tip empty 70 degrees about x around its own centre.
    e.matrix_world = e.matrix_world @ Matrix.Rotation(math.radians(70), 4, 'X')
    bpy.context.view_layer.update()
    assert bpy.ops.spinmotor.pose_handles() == {'FINISHED'}
    L = addon.ops.LAST["pose_handles"]
    Ft = loop_triangles(ob.data)
    ref = sm.SurfaceHarmonicDeformer(V0, Ft, handles=[("base", base.tolist()), ("tip", tip.tolist())]).pose(
        [sm.Motor(), sm.Motor.from_rotation((1, 0, 0), 70, about=tuple(c))])
    dev = np.abs(L["V"] - ref).max() / diag(ref)
    print(f"  handles: add-on pose vs direct SurfaceHarmonicDeformer with the exact motor {dev:.1e} (float32 empties)")
    assert dev <= 1e-6, dev
    assert np.abs(L["V"][base] - V0[base]).max() <= 1e-12
    got = evaluated(ob)
    assert np.abs(got - L["V"]).max() <= 1e-6 * diag(got)
    # A scaled empty is not a rigid motion: reported, nothing written.
    e.scale = (2, 2, 2)
    bpy.context.view_layer.update()
    activate(ob)
    expect_error(bpy.ops.spinmotor.pose_handles, "handle 'handled.tip'", ob)


def test_split_seams(sm, addon):
    """A mesh whose triangles are all loose (every corner its own vertex, as the Fox arrives from the glTF
    importer: 1728 vertices for 290 positions) bakes, and gives the welded mesh's result at every copy: the
    add-on welds equal rest positions before the cleanup and maps the result back."""
    t0 = time.time()
    ob_w, rig_w, Vc, Fc = make_arm(sm, "armw", 40, 24)
    pose_elbow(rig_w, 90)
    assert bpy.ops.spinmotor.bake_cleanup() == {'FINISHED'}
    Lw = addon.ops.LAST["bake_cleanup"]
    ob_s, rig_s, _, _ = make_arm(sm, "arms", 40, 24, split=True)
    pose_elbow(rig_s, 90)
    n_split = len(ob_s.data.vertices)
    assert n_split == 3 * len(Fc)
    assert bpy.ops.spinmotor.bake_cleanup() == {'FINISHED'}
    Ls = addon.ops.LAST["bake_cleanup"]
    assert Ls["object"] == "arms" and Ls["weld"].k == len(Vc), (Ls["weld"].k, len(Vc))
    assert Ls["piece_counts"] == {"cleaned": 1}, Ls["piece_counts"]
    assert len(Ls["pins_welded"]) == len(Lw["pins"]) and len(Ls["pins"]) == int(np.isin(Fc.ravel(), Lw["pins"]).sum())
    Vw, Vs = Lw["frames"][1]["V"], Ls["frames"][1]["V"]
    d = diag(Vw)
    dev = np.abs(Vs - Vw[Fc.ravel()]).max() / d  # copy 3f + c is the welded mesh's vertex Fc[f, c]
    key_err = np.abs(evaluated(ob_s) - Vs).max() / d
    q_w, q_s = Lw["frames"][1]["metrics"]["q_mean"], Ls["frames"][1]["metrics"]["q_mean"]
    # Without the weld, each loose triangle would be a piece of its own.
    W = addon.meshdata.bone_weights(ob_s)[0]
    loose = sm.RigCleanup(read_co(ob_s.data.vertices, n_split), loop_triangles(ob_s.data), W, bones=ARM_BONES)
    counts = {}
    for p in loose.pieces:
        counts[p["status"]] = counts.get(p["status"], 0) + 1
    print(f"  split seams: {n_split} loose vertices welded to {Ls['weld'].k}; vs the welded mesh's bake {dev:.1e} of "
          f"the diagonal, Q_mean {q_s:.4f} (welded {q_w:.4f}); key through the armature {key_err:.1e}; unwelded "
          f"the library would see {len(loose.pieces)} pieces {counts} ({time.time() - t0:.1f} s)")
    assert dev <= 1e-9, dev
    assert abs(q_s - q_w) <= 1e-9 and q_s < Lw["frames"][1]["metrics_edit"]["q_mean"]
    assert key_err <= 2e-6, key_err
    assert len(loose.pieces) == len(Fc)


def test_multi_object(sm, addon):
    """Two meshes on one armature: the deformed arm gets its keys, a rigid helmet (every vertex on one bone) none.
    The armature object is turned and its bones turned back, so the rest bones the add-on passes to the library
    (per-bone default margin) must be converted to the mesh's space; the pins equal spinmotor.RigCleanup's on the
    same arrays with the mesh-space bones, and differ from those of bones taken in the armature's own axes."""
    t0 = time.time()
    ob, rig, Vc, Fc = make_arm(sm, "arm3", 40, 24, turned=True)
    Vh, Fh = sm.icosphere(2)
    helmet = mesh_object("helmet", 0.8 * Vh + np.array([0.0, 0.0, 7.0]), Fh)
    helmet.vertex_groups.new(name="lower").add(list(range(len(Vh))), 1.0, 'REPLACE')
    mod = helmet.modifiers.new("Armature", 'ARMATURE')
    mod.object = rig
    pose_elbow(rig, 60)
    # The per-bone margin default is the library's: the same pins as a direct RigCleanup on the same arrays.
    V0 = read_co(ob.data.vertices, len(Vc))
    F = loop_triangles(ob.data)
    W = addon.meshdata.bone_weights(ob)[0]
    t32 = float(np.float32(0.999))
    ref = sm.RigCleanup(V0, F, W, bones=ARM_BONES, threshold=t32, warm_start=True)
    axes = [(n, p, (h[0], h[2], -h[1]), (t[0], t[2], -t[1])) for n, p, h, t in ARM_BONES]  # armature-space bones
    wrong = sm.RigCleanup(V0, F, W, bones=axes, threshold=t32)
    assert not np.array_equal(np.asarray(ref.pins), np.asarray(wrong.pins)), "the test cannot see the conversion"
    activate(ob)
    assert bpy.ops.spinmotor.pins_to_group() == {'FINISHED'}
    assert np.array_equal(addon.meshdata.group_members(ob, "spinmotor_pins"), np.asarray(ref.pins))
    ob.vertex_groups.remove(ob.vertex_groups["spinmotor_pins"])
    # Both selected (the arm active): one bake for both.
    activate(ob)
    helmet.select_set(True)
    before_h = snapshot(helmet)
    assert bpy.ops.spinmotor.bake_cleanup() == {'FINISHED'}
    L = addon.ops.LAST["bake_cleanup"]
    assert sorted(L["objects"]) == ["arm3", "helmet"], sorted(L["objects"])
    La, Lh = L["objects"]["arm3"], L["objects"]["helmet"]
    assert np.array_equal(La["pins"], np.asarray(ref.pins)), (len(La["pins"]), len(ref.pins))
    # (float32 bones turned by float32 matrices: the axes agree to ~1e-7)
    margin_dev = np.abs(La["margins"] - np.asarray(ref.margins)).max()
    assert margin_dev <= 1e-6 * np.max(ref.margins), (La["margins"], ref.margins)
    E = La["frames"][1]["V_edit"]
    dev = np.abs(ref.cleanup(E) - La["frames"][1]["V"]).max() / diag(E)
    assert dev <= 1e-12, dev
    assert [kb.name for kb in ob.data.shape_keys.key_blocks] == ["Basis", "spinmotor_cleanup_0001"]
    assert La["keys"] == ["spinmotor_cleanup_0001"] and not La["unchanged"]
    # The helmet: one piece on one bone, left as the armature put it; no key, no basis, nothing else changed.
    Eh = evaluated(helmet)
    change = np.abs(Lh["frames"][1]["V"] - Eh).max() / diag(Eh)
    assert Lh["unchanged"] and Lh["keys"] == [] and helmet.data.shape_keys is None
    assert sum(Lh["piece_counts"].values()) == 1 and set(Lh["piece_counts"]) <= {"rigid", "pinned"}, Lh["piece_counts"]
    assert change <= 1e-9, change
    assert same_snapshot(before_h, snapshot(helmet))
    key_err = np.abs(evaluated(ob) - La["frames"][1]["V"]).max() / diag(E)
    assert key_err <= 2e-6, key_err
    print(f"  multi-object: arm3 {La['piece_counts']} {len(La['pins'])} pins (per-bone margin "
          f"{La['margins'][0]:.4f}; bones in the armature's axes would give {len(wrong.pins)}), vs direct RigCleanup "
          f"{dev:.1e}, key {key_err:.1e}; helmet {Lh['piece_counts']}, change {change:.1e}: no key")
    # The armature active (nothing selected): every mesh with an Armature modifier on it; the key is overwritten.
    activate(rig)
    rig.select_set(False)
    assert bpy.ops.spinmotor.bake_cleanup() == {'FINISHED'}
    L2 = addon.ops.LAST["bake_cleanup"]
    assert sorted(L2["objects"]) == ["arm3", "helmet"]
    assert np.abs(L2["objects"]["arm3"]["frames"][1]["V"] - La["frames"][1]["V"]).max() <= 1e-12 * diag(E)
    assert [kb.name for kb in ob.data.shape_keys.key_blocks] == ["Basis", "spinmotor_cleanup_0001"]
    assert helmet.data.shape_keys is None
    # One object fails (a Subdivision modifier on the helmet): nothing is written on the other either.
    helmet.modifiers.new("Subdivision", 'SUBSURF')
    expect_error(bpy.ops.spinmotor.bake_cleanup, "vertex count", ob, frame_start=2, frame_end=2)
    assert helmet.data.shape_keys is None
    print(f"  multi-object test {time.time() - t0:.1f} s")



class FakeLayout:
    """Stands in for a UILayout in background mode (no window to draw): checks that every property and operator
    property the panel names exists."""

    def __init__(self):
        self.calls = []

    def box(self):
        return self

    def row(self, align=False):
        return self

    def label(self, text="", icon='NONE'):
        self.calls.append(("label", text))

    def prop(self, data, name, **kw):
        assert name in data.bl_rna.properties, f"no property {name} on {data}"
        self.calls.append(("prop", name))

    def prop_search(self, data, name, search_data, search_name, **kw):
        assert name in data.bl_rna.properties and search_name in search_data.bl_rna.properties
        self.calls.append(("prop_search", name))

    def operator(self, idname, **kw):
        group, name = idname.split(".")
        rna = getattr(getattr(bpy.ops, group), name).get_rna_type()
        self.calls.append(("operator", idname))

        class Props:
            def __setattr__(self, key, value):
                assert key in rna.properties, f"{idname} has no property {key}"
                prop = rna.properties[key]
                if prop.type == 'ENUM':
                    assert value in prop.enum_items.keys(), (idname, key, value)
        return Props()


def test_ui(addon):
    """The panel and the preferences draw without error, with only existing properties and operators."""
    layout = FakeLayout()
    panel = addon.ui.SPINMOTOR_PT_panel
    panel.draw(type("P", (), {"layout": layout})(), bpy.context)
    ops = [c[1] for c in layout.calls if c[0] == "operator"]
    assert ops == ["spinmotor.bake_cleanup", "spinmotor.pins_to_group", "spinmotor.snap", "spinmotor.q_colors",
                   "spinmotor.add_handle", "spinmotor.pose_handles"], ops
    layout = FakeLayout()
    prefs = bpy.context.preferences.addons["spinmotor_addon"].preferences
    addon.ui.SpinmotorPreferences.draw(type("P", (), {"layout": layout, "module_dir": prefs.module_dir,
                                                      "bl_rna": prefs.bl_rna})(),
                                       bpy.context)
    assert any(c[0] == "label" and c[1].startswith("spinmotor 0.1") for c in layout.calls), layout.calls


def test_defaults(sm, addon):
    """The add-on's property defaults are the library's rig defaults (scene::RigCleanupOptions), on the
    operator and on the panel's settings."""
    lib = sm.RIG_CLEANUP_DEFAULTS
    for k, v in addon.ops.RIG_DEFAULTS.items():
        assert lib[k] == v, (k, v, lib[k])
    props = bpy.ops.spinmotor.bake_cleanup.get_rna_type().properties
    settings = bpy.context.scene.spinmotor.bl_rna.properties
    for k in ("threshold", "pose_weight", "keep", "max_iterations"):
        assert props[k].default == near(lib[k]), (k, props[k].default, lib[k])
    for k in ("threshold", "pose_weight", "keep"):
        assert settings[k].default == near(lib[k]), (k, settings[k].default, lib[k])


def near(v):
    """Blender stores float properties in single precision: compare floats to that."""
    class Near:
        def __eq__(self, other):
            return abs(other - v) <= 1e-6 * max(1.0, abs(v)) if isinstance(v, float) else other == v
    return Near()


def test_gltf_import(sm):
    """Blender's own glTF importer reads the morph-target animation the project bakes (rig pose --out .glb,
    Rig.bake, write_gltf_morph_animation): one shape key per frame, holding the frame's positions (float32).
    Debian's Blender 3.4 importer still uses numpy.bool, removed in numpy 1.24: aliased here for the
    importer (a packaging problem of Blender 3.4, not of the file)."""
    import tempfile
    if "bool" not in vars(np):
        np.bool = bool
    V0, F = sm.capsule(0.5, 3.0, 20, 12)
    frames = []
    for k in range(3):
        a = math.radians(30 * k)
        R = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
        frames.append(V0 @ R.T + np.array([0.1 * k, 0, 0]))
    path = os.path.join(tempfile.mkdtemp(), "baked.glb")
    sm.write_gltf_morph_animation(path, V0, F, np.stack(frames), [0.0, 0.5, 1.0], name="baked")
    before = set(bpy.data.objects)
    assert bpy.ops.import_scene.gltf(filepath=path) == {'FINISHED'}
    new = [o for o in bpy.data.objects if o not in before and o.type == 'MESH']
    assert len(new) == 1, new
    me = new[0].data
    keys = me.shape_keys.key_blocks
    assert len(keys) == 1 + len(frames), [k.name for k in keys]
    assert len(me.vertices) == len(V0), (len(me.vertices), len(V0))  # no UVs: no seam copies
    # The importer converts glTF's Y-up to Blender's Z-up: (x, y, z) -> (x, -z, y).
    for k, Vk in enumerate(frames):
        co = read_co(keys[k + 1].data, len(V0))
        co = np.column_stack([co[:, 0], co[:, 2], -co[:, 1]])
        err = np.abs(co - Vk).max() / diag(Vk)
        assert err < 1e-6, (k, err)
    print(f"  Blender imports the baked glb: {len(keys) - 1} shape keys, {len(me.vertices)} vertices")


def enable_addon():
    """From the zip, as an artist installs it, when $BLENDER_USER_SCRIPTS is a scratch folder (scripts/ci-blender
    sets one: the install writes there), else from blender/ on sys.path."""
    user = os.environ.get("BLENDER_USER_SCRIPTS", "")
    if os.environ.get("SPINMOTOR_TEST_ZIP_INSTALL") and user:
        import zipfile
        zpath = os.path.join(user, "spinmotor_addon.zip")
        src = os.path.join(REPO, "blender", "spinmotor_addon")
        with zipfile.ZipFile(zpath, "w") as z:
            for f in sorted(os.listdir(src)):
                if f.endswith(".py"):
                    z.write(os.path.join(src, f), f"spinmotor_addon/{f}")
        assert bpy.ops.preferences.addon_install(filepath=zpath) == {'FINISHED'}
        print("add-on installed from", zpath)
    else:
        sys.path.insert(0, os.path.join(REPO, "blender"))
    mod = addon_utils.enable("spinmotor_addon", default_set=True, handle_error=None)
    assert mod is not None, "the add-on did not load"
    return mod


def main():
    t0 = time.time()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    enable_addon()
    import spinmotor_addon as addon
    print("add-on registered:", addon.bl_info["name"], addon.bl_info["version"], "from", addon.__file__)
    print("test_module_missing")
    test_module_missing(addon)
    d = module_dir()
    bpy.context.preferences.addons["spinmotor_addon"].preferences.module_dir = d
    sm = addon.ops.spinmotor_module(bpy.context)
    print("spinmotor module:", sm.__file__)
    print("test_ui")
    test_ui(addon)
    print("test_defaults")
    test_defaults(sm, addon)
    print("test_bake_cleanup")
    ob, rig, V0, F, E, V = test_bake_cleanup(sm, addon)
    print("test_frame_range")
    test_frame_range(sm, addon)
    print("test_bad_meshes")
    test_bad_meshes(sm, addon)
    print("test_split_seams")
    test_split_seams(sm, addon)
    print("test_multi_object")
    test_multi_object(sm, addon)
    print("test_snap")
    test_snap(sm, addon)
    print("test_q_colors")
    test_q_colors(sm, addon, ob, V0, F, V)
    print("test_handles")
    test_handles(sm, addon)
    print("test_gltf_import")
    test_gltf_import(sm)
    addon_utils.disable("spinmotor_addon", default_set=True)
    assert not hasattr(bpy.types.Scene, "spinmotor") and not hasattr(bpy.types, "SPINMOTOR_OT_bake_cleanup")
    assert "spinmotor_addon" not in bpy.context.preferences.addons
    print(f"OK: Blender add-on tests passed in {time.time() - t0:.1f} s")


try:
    main()
except Exception:
    traceback.print_exc()
    sys.exit(1)
