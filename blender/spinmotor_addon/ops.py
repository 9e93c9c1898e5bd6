"""The add-on's operators: bake the pose-keeping cleanup as corrective shape keys, snap a sculpted shape key
to the nearest spin transformation, Q colours, and motor posing by surface harmonic coordinates.

Every operator reads everything, computes everything, and only then writes: an error (from the library,
spinmotor.Error, or from the Blender side) is reported in Blender's report area and leaves the object
as it was (no shape key, no attribute, frame and key states restored).
"""
import contextlib
import hashlib
import sys
import traceback

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from . import loader
from . import meshdata as md
from .meshdata import CLEANUP_PREFIX, AddonError

# The last result of each operator, in float64 before Blender's float32 storage (for scripts and tests):
# LAST["bake_cleanup"], LAST["snap"], LAST["q_colors"], LAST["pose_handles"].
LAST = {}
# Bound solvers per object (name, kind), reused while the rest mesh and options are unchanged.
_CACHE = {}

KEEP_ITEMS = [
    ("auto", "Auto", "The rest volume if the mesh is closed, else its area"),
    ("volume", "Volume", "Keep the rest volume (closed meshes)"),
    ("area", "Area", "Keep the rest surface area"),
    ("none", "None", "No measure constraint"),
]
OUTPUT_ITEMS = [
    ("SHAPE_KEY", "Corrective shape key",
     "A rest-space shape key per frame: with it at value 1 the modifier stack (the armature) produces the cleaned "
     "mesh"),
    ("OBJECT", "New object", "A new mesh object per frame with the cleaned positions (no modifiers)"),
]
HANDLE_PROPS = ("spinmotor_mesh", "spinmotor_group", "spinmotor_rest")
# The library's rig cleanup defaults (spinmotor.RIG_CLEANUP_DEFAULTS, scene::RigCleanupOptions), the one
# home of the properties' defaults here: the module is loaded only after registration, from the folder
# the preferences name, so they are written out; tests/blender/test_addon.py checks they are the library's.
RIG_DEFAULTS = {"threshold": 0.999, "pose_weight": 10.0, "keep": "auto", "max_iterations": 100}


def prefs_dir(context):
    addon = context.preferences.addons.get(__package__)
    prefs = getattr(addon, "preferences", None) if addon is not None else None
    return getattr(prefs, "module_dir", "") if prefs is not None else ""


def spinmotor_module(context):
    return loader.load(prefs_dir(context))


def run_reported(op, fn):
    """Runs fn(); errors become an ERROR report (the library's message as is) and CANCELLED."""
    try:
        return fn()
    except Exception as e:  # noqa: BLE001 - every error is reported, none reaches Blender as a crash
        sm = sys.modules.get("spinmotor")
        if isinstance(e, (AddonError, loader.ModuleMissing)) or (sm is not None and isinstance(e, sm.Error)):
            op.report({'ERROR'}, str(e))
        else:
            traceback.print_exc()
            op.report({'ERROR'}, f"spinmotor add-on: unexpected {type(e).__name__}: {e}")
        return {'CANCELLED'}


class MeshOperator:
    """Mixin: operators on the active mesh object in Object Mode."""

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        ok = obj is not None and obj.type == 'MESH' and obj.mode == 'OBJECT'
        if not ok:
            cls.poll_message_set("Needs an active mesh object in Object Mode")
        return ok


def active_mesh(context):
    obj = context.active_object
    if obj is None or obj.type != 'MESH':
        raise AddonError("spinmotor: the active object must be a mesh")
    if obj.mode != 'OBJECT':
        raise AddonError(f"{obj.name}: switch to Object Mode first (edit-mode changes are not in the mesh yet)")
    return obj


def _fingerprint(*arrays, extra=()):
    h = hashlib.blake2b(digest_size=16)
    for a in arrays:
        a = np.ascontiguousarray(a)
        h.update(str(a.shape).encode())
        h.update(a.tobytes())
    h.update(repr(extra).encode())
    return h.hexdigest()


def cached(obj, kind, fingerprint, make):
    k = (obj.name, kind)
    hit = _CACHE.get(k)
    if hit is not None and hit[0] == fingerprint:
        return hit[1]
    value = make()
    _CACHE[k] = (fingerprint, value)
    return value


def rest_mesh(sm, obj):
    """V0 (basis), F (triangulation), triangle -> polygon; the library's error if the mesh cannot be used."""
    me = obj.data
    if len(me.polygons) == 0:
        raise AddonError(f"{obj.name}: the mesh has no faces")
    V0 = md.rest_positions(obj)
    F, tri_poly = md.triangles(me)
    md.check_mesh(sm, obj, V0, F, tri_poly)
    return V0, F, tri_poly


def key_by_name(obj, name):
    key = obj.data.shape_keys
    return key.key_blocks.get(name) if key is not None else None


def write_key(obj, name, V, relative_key=None):
    """Creates (or overwrites) the relative shape key `name` with coordinates V; returns it."""
    kb = key_by_name(obj, name)
    if kb is None:
        kb = obj.shape_key_add(name=name, from_mix=False)
    kb.relative_key = relative_key if relative_key is not None else obj.data.shape_keys.reference_key
    md.set_key_co(kb, V)
    kb.mute = False
    md.tag_key_update(obj)
    return kb


class KeyState:
    """Shape-key state during a bake: earlier cleanup keys muted (they must not be in the edit), a scratch
    key for the corrective solve (and a basis if the mesh had none). On exit everything is restored; a
    basis created here is removed again if the bake failed or wrote no key to the object; keys named in
    `written` stay unmuted."""

    def __init__(self, obj, scratch):
        self.obj, self.scratch, self.tmp, self.written, self.active_name = obj, scratch, None, set(), None

    def __enter__(self):
        obj = self.obj
        key = obj.data.shape_keys
        if key is not None and not key.use_relative:
            raise AddonError(f"{obj.name}: its shape keys are absolute (Relative off); the cleanup keys are relative")
        self.created_basis = self.scratch and key is None
        self.show_only = obj.show_only_shape_key
        self.active = obj.active_shape_key_index
        obj.show_only_shape_key = False
        if self.created_basis:
            obj.shape_key_add(name="Basis", from_mix=False)
        key = obj.data.shape_keys
        self.muted = {}
        if key is not None:
            for kb in key.key_blocks:
                if kb.name.startswith(CLEANUP_PREFIX):
                    self.muted[kb.name] = kb.mute
                    kb.mute = True
        if self.scratch:
            self.tmp = obj.shape_key_add(name="spinmotor_scratch", from_mix=False)
            self.tmp.relative_key = key.reference_key
            self.tmp.value = 1.0
        md.tag_key_update(obj)
        return self

    def clear_scratch(self, basis):
        """The scratch key back to the basis (no offset): the next evaluation is the stack's own result."""
        if self.tmp is not None:
            md.set_key_co(self.tmp, basis)
            md.tag_key_update(self.obj)

    def __exit__(self, exc_type, exc, tb):
        obj = self.obj
        if self.tmp is not None:
            obj.shape_key_remove(self.tmp)
            self.tmp = None
        if self.created_basis and (exc_type is not None or not self.written):
            obj.shape_key_clear()
        else:
            for name, mute in self.muted.items():
                kb = key_by_name(obj, name)
                if kb is not None and name not in self.written:
                    kb.mute = mute
            key = obj.data.shape_keys
            found = key.key_blocks.find(self.active_name) if key is not None and self.active_name else -1
            obj.active_shape_key_index = found if found >= 0 else self.active
        obj.show_only_shape_key = self.show_only
        md.tag_key_update(obj)
        return False


# ---- bake the pose-keeping cleanup -------------------------------------------------------------------------

# A mesh the cleanup leaves within this fraction of its diagonal of the armature pose on every frame gets no key.
UNCHANGED = 1e-9


def bake_targets(context):
    """The mesh objects a bake works on: with an armature active, every mesh with an Armature modifier on it;
    else every selected mesh, the active one first. AddonError if there is none or one is not in Object Mode."""
    active = context.active_object
    if active is not None and active.type == 'ARMATURE':
        obs = sorted((o for o in context.scene.objects if o.type == 'MESH' and
                      any(m.type == 'ARMATURE' and m.object == active for m in o.modifiers)), key=lambda o: o.name)
        if not obs:
            raise AddonError(f"{active.name}: no mesh object has an Armature modifier on this armature")
    else:
        obs = sorted((o for o in context.selected_objects if o.type == 'MESH'), key=lambda o: o.name)
        if active is not None and active.type == 'MESH':
            obs = [active] + [o for o in obs if o != active]
        if not obs:
            raise AddonError("spinmotor: select the mesh objects to bake (or make their armature active)")
    for o in obs:
        if o.mode != 'OBJECT':
            raise AddonError(f"{o.name}: switch to Object Mode first (edit-mode changes are not in the mesh yet)")
    return obs


class SPINMOTOR_OT_bake_cleanup(bpy.types.Operator):
    """Pose-keeping conformal cleanup of the deformed (armature-posed) meshes against their rest shape, baked as a
    corrective shape key per frame: every selected mesh, or every mesh of the active armature; pins and the pose
    attraction from the bone weights (the library's rig cleanup, every connected piece on its own), or a vertex group"""
    bl_idname = "spinmotor.bake_cleanup"
    bl_label = "Bake Conformal Cleanup"
    bl_options = {'REGISTER', 'UNDO'}

    threshold: FloatProperty(
        name="Threshold", default=RIG_DEFAULTS["threshold"], min=0.5, max=1.0, precision=4,
        description="Pin the vertices whose dominant bone weight is at least this (the bones' rigid parts)")
    per_bone_margin: BoolProperty(
        name="Per-bone margin", default=True,
        description="The library's default room for the joints: per bone, a quarter of the widest blend band of its "
                    "joints (off: the Margin distance for every bone)")
    margin: FloatProperty(
        name="Margin", default=0.0, min=0.0, unit='LENGTH',
        description="With Per-bone margin off: pins lie farther than this from every blended vertex (object units)")
    pin_group: StringProperty(
        name="Pin group", default="",
        description="Pin this vertex group's vertices (weight > 0) instead of choosing pins from bone weights")
    pose_weight: FloatProperty(
        name="Pose weight", default=RIG_DEFAULTS["pose_weight"], min=0.0,
        description="Strength of the attraction that holds the soft parts near the armature pose (weights from "
                    "the bones: 1 on rigid parts, 0 mid-joint); 0 = the pins only. The library's rig default")
    frame_start: IntProperty(name="Start", default=1, description="First frame to bake")
    frame_end: IntProperty(name="End", default=1, description="Last frame to bake")
    keep: EnumProperty(name="Keep", items=KEEP_ITEMS, default=RIG_DEFAULTS["keep"],
                       description="Measure kept by the cleanup")
    max_iterations: IntProperty(name="Iterations", default=RIG_DEFAULTS["max_iterations"], min=1, max=10000,
                                description="Maximum local/global iterations per frame")
    output: EnumProperty(name="Output", items=OUTPUT_ITEMS, default="SHAPE_KEY")
    animate: BoolProperty(
        name="Keyframe", default=True,
        description="Keyframe each key's value: 1 on its frame, 0 on the frames before and after")

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        ok = obj is not None and ((obj.type == 'MESH' and obj.mode == 'OBJECT') or
                                  (obj.type == 'ARMATURE' and obj.mode in {'OBJECT', 'POSE'}))
        if not ok:
            cls.poll_message_set("Needs an active mesh in Object Mode, or the armature of the meshes to bake")
        return ok

    def execute(self, context):
        return run_reported(self, lambda: self._run(context))

    def _prepare(self, sm, obj):
        """Everything bound once per object: the welded rest mesh, the pins and the cleanup (cached)."""
        me = obj.data
        if len(me.polygons) == 0:
            raise AddonError(f"{obj.name}: the mesh has no faces")
        V0 = md.rest_positions(obj)
        F, tri_poly = md.triangles(me)
        weld = md.Weld(V0, F, tri_poly)
        V0w, Fw = weld.weld(V0), weld.F
        try:
            W, names = md.bone_weights(obj)
        except AddonError:
            if not self.pin_group:
                raise
            W, names = None, []
        Ww = None if W is None else weld.weld(W)  # the first vertex of each welded group
        b = {"object": obj, "V0": V0, "F": F, "weld": weld, "W": W, "bone_names": names, "pieces": None}
        try:
            if self.pin_group:
                # PinnedCleanup needs a consistently oriented manifold: the library's check names what is wrong.
                md.check_mesh(sm, obj, V0w, Fw, weld.tri_polygon)
                members = md.group_members(obj, self.pin_group)
                if len(members) == 0:  # (the bone weights' attraction alone would hold it: surely a mistake)
                    raise AddonError(f"{obj.name}: the pin group '{self.pin_group}' has no vertex with a weight > 0 "
                                     "(no pinned vertex)")
                pins_w = np.unique(weld.inverse[members])
                attraction = (None if Ww is None or self.pose_weight == 0 else
                              np.asarray(sm.pin_attraction_from_weights(Ww, self.threshold)))
                source = f"vertex group '{self.pin_group}'"
                fp = _fingerprint(V0w, Fw, pins_w, extra=(self.keep, self.max_iterations, self.pose_weight,
                                                          None if attraction is None else hash(attraction.tobytes())))
                cleaner = cached(obj, "cleanup", fp, lambda: sm.PinnedCleanup(
                    V0w, Fw, pins_w, keep=self.keep, max_iterations=self.max_iterations, pose_weight=self.pose_weight,
                    attraction=attraction, warm_start=True))
            else:
                bones = md.rest_bones(obj, names, V0, W)
                options = {"threshold": self.threshold, "pose_weight": self.pose_weight, "keep": self.keep,
                           "max_iterations": self.max_iterations, "warm_start": True}
                if not self.per_bone_margin:
                    options["margin"] = self.margin
                fp = _fingerprint(V0w, Fw, Ww, extra=(bones, sorted(options.items())))
                # warm_start: the frames are cleaned in order, each from the previous frame's correction.
                cleaner = cached(obj, "rigcleanup", fp, lambda: sm.RigCleanup(V0w, Fw, Ww, bones=bones, **options))
                pins_w = np.asarray(cleaner.pins, dtype=np.int64)
                b["pieces"] = list(cleaner.pieces)
                b["margins"] = np.asarray(cleaner.margins)
                m = np.unique(b["margins"])
                margin = (f"margin {self.margin:g}" if not self.per_bone_margin else
                          f"per-bone margin {m[0]:.3g}" if len(m) == 1 else f"per-bone margins {m[0]:.3g}..{m[-1]:.3g}")
                source = f"weights >= {self.threshold:g} of {len(names)} bones, {margin}"
            cleaner.reset()  # a cached cleaner remembers the last frame of the previous bake
        except sm.Error as e:
            raise AddonError(f"{obj.name}: " + md.polygon_note(str(e), weld.tri_polygon)) from None
        b.update({"cleaner": cleaner, "pins_welded": pins_w, "pins": weld.blender_indices(pins_w), "source": source,
                  "diagonal": md.diagonal(V0), "frames": {}})
        return b

    def _clean_frame(self, sm, b, E):
        """The cleanup of one frame's evaluated positions E (every Blender vertex) on the welded mesh."""
        weld, V0 = b["weld"], b["V0"]
        Ew = weld.weld(E)
        try:
            r = b["cleaner"].cleanup(Ew, full=True)
        except sm.Error as e:
            raise AddonError(f"{b['object'].name}: " + md.polygon_note(str(e), weld.tri_polygon)) from None
        Vw = np.asarray(r["V"])
        V = weld.unweld(Vw)
        if "volume_ratio" in r:  # RigCleanup: over the pieces that keep their volume
            ratio, edit_ratio, keep = r["volume_ratio"], r["edit_volume_ratio"], "volume"
        else:
            ratio, edit_ratio, keep = r["measure_ratio"], r["edit_measure_ratio"], r["keep"]
        V0w = weld.weld(V0)
        return {"V_edit": E, "V": V, "V_welded": Vw, "iterations": r["iterations"], "converged": r["converged"],
                "measure_ratio": ratio, "edit_measure_ratio": edit_ratio, "keep": keep, "pin_error": r["pin_error"],
                "change": float(np.abs(V - E).max()) / b["diagonal"],
                "metrics_edit": sm.metrics(V0w, Ew, weld.F), "metrics": sm.metrics(V0w, Vw, weld.F)}

    def _run(self, context):
        sm = spinmotor_module(context)
        obs = bake_targets(context)
        if self.frame_end < self.frame_start:
            raise AddonError(f"frame range {self.frame_start}..{self.frame_end} is empty")
        scene = context.scene
        bakes = [self._prepare(sm, obj) for obj in obs]
        shape_key = self.output == 'SHAPE_KEY'
        frame0, subframe0 = scene.frame_current, scene.frame_subframe
        written = []  # (object, key name, previous (co, value) or None), for the rollback
        try:
            with contextlib.ExitStack() as stack:
                states = [stack.enter_context(KeyState(b["object"], scratch=shape_key)) for b in bakes]
                for f in range(self.frame_start, self.frame_end + 1):
                    scene.frame_set(f)
                    for b, ks in zip(bakes, states):
                        ks.clear_scratch(b["V0"])  # the previous frame's correction is not part of this edit
                        res = self._clean_frame(sm, b, md.evaluated_positions(context, b["object"]))
                        if shape_key and res["change"] > UNCHANGED:
                            # Newton steps to float32 roundoff; an error above 1e-4 of the diagonal.
                            dg = b["diagonal"]
                            res["key"], res["key_residual"] = md.corrective_key(context, b["object"], ks.tmp, b["V0"],
                                                                                res["V"], 1e-6 * dg, 1e-4 * dg)
                        elif shape_key:  # the armature's own result: the key is the basis
                            res["key"], res["key_residual"] = b["V0"].copy(), res["change"] * b["diagonal"]
                        b["frames"][f] = res
                for b in bakes:
                    b["unchanged"] = all(r["change"] <= UNCHANGED for r in b["frames"].values())
                # Everything computed: write (still inside, so that a failure here rolls back too).
                if shape_key:
                    try:
                        for b, ks in zip(bakes, states):
                            if not b["unchanged"]:
                                self._write_keys(b, ks, written)
                    except Exception:
                        for obj, name, existed in written:  # new keys go, overwritten ones get their data back
                            kb = key_by_name(obj, name)
                            if kb is not None and existed is None:
                                obj.shape_key_remove(kb)
                            elif kb is not None:
                                md.set_key_co(kb, existed[0])
                                kb.value = existed[1]
                        raise
        finally:
            scene.frame_set(frame0, subframe=subframe0)
        if self.output == 'OBJECT':
            made = []
            try:
                for b in bakes:
                    made += self._new_objects(context, b["object"], b["frames"])
            except Exception:
                for ob in made:
                    me = ob.data
                    bpy.data.objects.remove(ob)
                    bpy.data.meshes.remove(me)
                raise
        results = {}
        for b in bakes:
            obj = b["object"]
            results[obj.name] = {
                "object": obj.name, "V0": b["V0"], "F": b["F"], "weld": b["weld"], "pins": b["pins"],
                "pins_welded": b["pins_welded"], "pin_source": b["source"], "pieces": b["pieces"],
                "piece_counts": piece_counts(b["pieces"]), "margins": b.get("margins"), "frames": b["frames"],
                "unchanged": b["unchanged"], "keys": [n for o, n, _ in written if o == obj]}
        LAST["bake_cleanup"] = dict(results[obs[0].name], objects=results)
        self._report(bakes, results)
        return {'FINISHED'}

    def _write_keys(self, b, ks, written):
        obj, n = b["object"], len(b["V0"])
        for f, res in b["frames"].items():
            name = f"{CLEANUP_PREFIX}{f:04d}"
            old = key_by_name(obj, name)
            existed = None if old is None else (md._co(old.data, n), old.value)
            kb = write_key(obj, name, res["key"])
            written.append((obj, kb.name, existed))
            ks.written.add(kb.name)
            if self.animate:
                for fr, val in ((f - 1, 0.0), (f, 1.0), (f + 1, 0.0)):
                    kb.value = val
                    kb.keyframe_insert("value", frame=fr)
            kb.value = 1.0
            ks.active_name = kb.name

    def _new_objects(self, context, obj, frames):
        dg = context.evaluated_depsgraph_get()
        made = []
        for f, res in frames.items():
            me = bpy.data.meshes.new_from_object(obj.evaluated_get(dg))
            me.name = f"{obj.name}_cleanup_{f:04d}"
            me.vertices.foreach_set("co", np.ascontiguousarray(res["V"], np.float32).ravel())
            me.update()
            ob = bpy.data.objects.new(me.name, me)
            ob.matrix_world = obj.matrix_world.copy()
            (obj.users_collection[0] if obj.users_collection else context.scene.collection).objects.link(ob)
            made.append(ob)
            res["object"] = ob.name
        return made

    def _report(self, bakes, results):
        """Per object: the pieces by status, the pins, Q_mean and the measure ratio before -> after (of the frame
        the armature distorts most), the frames, and the keys written (or why none)."""
        heads = []
        for b in bakes:
            obj, frames, R = b["object"], b["frames"], results[b["object"].name]
            for f, r in frames.items():
                print(f"spinmotor cleanup: {obj.name} frame {f}: Q_mean {r['metrics_edit']['q_mean']:.4f} -> "
                      f"{r['metrics']['q_mean']:.4f}, {r['keep']} ratio {r['edit_measure_ratio']:.4f} -> "
                      f"{r['measure_ratio']:.4f}, {r['iterations']} iterations, change {r['change']:.2e} of the "
                      "diagonal" + ("" if r["converged"] else " (not converged)"))
            counts = R["piece_counts"]
            pieces = ("pieces " + " / ".join(f"{counts.get(st, 0)} {st}" for st in PIECE_STATES) + ", "
                      if counts else "")
            fw = max(frames, key=lambda f: frames[f]["metrics_edit"]["q_mean"])
            r = frames[fw]
            span = f"frame {fw}" if len(frames) == 1 else f"frames {min(frames)}..{max(frames)}, worst {fw}"
            weld = b["weld"]
            welded = f" ({weld.n} vertices welded to {weld.k} positions)" if weld.k < weld.n else ""
            line = (f"{obj.name}{welded}: {pieces}{len(b['pins'])} pins ({b['source']}); {span}: Q_mean "
                    f"{r['metrics_edit']['q_mean']:.4f} -> {r['metrics']['q_mean']:.4f}, {r['keep']} ratio "
                    f"{r['edit_measure_ratio']:.4f} -> {r['measure_ratio']:.4f}")
            if b["unchanged"]:
                line += (f"; unchanged (within {UNCHANGED:g} of the diagonal of the armature pose on every frame): "
                         + ("no key written" if self.output == 'SHAPE_KEY' else "objects written as posed"))
            elif self.output == 'SHAPE_KEY':
                line += f"; keys {CLEANUP_PREFIX}{min(frames):04d}..{max(frames):04d}"
            print("spinmotor cleanup:", line)
            heads.append(line)
        self.report({'INFO'}, "spinmotor cleanup: " + " | ".join(heads))


PIECE_STATES = ("cleaned", "rigid", "pinned", "unanchored")


def piece_counts(pieces):
    """{status: count} of RigCleanup's pieces ({} for a pin-group bake)."""
    counts = {}
    for p in pieces or []:
        counts[p["status"]] = counts.get(p["status"], 0) + 1
    return counts


class SPINMOTOR_OT_pins_to_group(MeshOperator, bpy.types.Operator):
    """Write the pins the cleanup would use (from the bone weights, the library's rig cleanup) to the vertex group
    'spinmotor_pins', to inspect or edit them and use them as the pin group"""
    bl_idname = "spinmotor.pins_to_group"
    bl_label = "Pins to Vertex Group"
    bl_options = {'REGISTER', 'UNDO'}

    threshold: FloatProperty(name="Threshold", default=RIG_DEFAULTS["threshold"], min=0.5, max=1.0, precision=4)
    per_bone_margin: BoolProperty(name="Per-bone margin", default=True,
                                  description="The library's default room for the joints (off: the Margin distance)")
    margin: FloatProperty(name="Margin", default=0.0, min=0.0, unit='LENGTH')

    def execute(self, context):
        def run():
            sm = spinmotor_module(context)
            obj = active_mesh(context)
            V0 = md.rest_positions(obj)
            F, tri_poly = md.triangles(obj.data)
            weld = md.Weld(V0, F, tri_poly)
            W, names = md.bone_weights(obj)
            options = {"threshold": self.threshold} if self.per_bone_margin else {"threshold": self.threshold,
                                                                                    "margin": self.margin}
            try:
                rc = sm.RigCleanup(weld.weld(V0), weld.F, weld.weld(W), bones=md.rest_bones(obj, names, V0, W),
                                   **options)
            except sm.Error as e:
                raise AddonError(f"{obj.name}: " + md.polygon_note(str(e), weld.tri_polygon)) from None
            pins = weld.blender_indices(rc.pins)
            vg = obj.vertex_groups.get("spinmotor_pins")
            if vg is not None:
                obj.vertex_groups.remove(vg)
            vg = obj.vertex_groups.new(name="spinmotor_pins")
            vg.add([int(i) for i in pins], 1.0, 'REPLACE')
            self.report({'INFO'}, f"spinmotor: {len(pins)} of {len(V0)} vertices in 'spinmotor_pins'")
            return {'FINISHED'}
        return run_reported(self, run)


# ---- snap a sculpted shape key ---------------------------------------------------------------------------


class SPINMOTOR_OT_snap(MeshOperator, bpy.types.Operator):
    """Snap the active shape key (a sculpted edit) to the nearest spin transformation of the shape it is
    relative to (Crane et al. 2011, section 7.2), written as the key '<name>_snap'; the edit is muted"""
    bl_idname = "spinmotor.snap"
    bl_label = "Snap to Spin Transformation"
    bl_options = {'REGISTER', 'UNDO'}

    tradeoff: FloatProperty(name="Trade-off", default=1.0, min=0.0, max=1.0, subtype='FACTOR',
                            description="0 follows the edit, 1 is conformal")

    def execute(self, context):
        return run_reported(self, lambda: self._run(context))

    def _run(self, context):
        sm = spinmotor_module(context)
        obj = active_mesh(context)
        key = obj.data.shape_keys
        src = obj.active_shape_key
        if key is None or src is None or src == key.reference_key or src.relative_key == src:
            raise AddonError(f"{obj.name}: make the sculpted shape key active (not the basis): the snap maps the "
                             "basis to the spin transformation nearest to it")
        n = len(obj.data.vertices)
        V0 = md._co(src.relative_key.data, n)
        E = md._co(src.data, n)
        F, tri_poly = md.triangles(obj.data)
        md.check_mesh(sm, obj, V0, F, tri_poly)
        try:
            snapper = cached(obj, "snap", _fingerprint(V0, F), lambda: sm.ConformalSnap(V0, F))
            r = snapper.snap(E, tradeoff=self.tradeoff, full=True)
        except sm.Error as e:
            raise AddonError(f"{obj.name}: " + md.polygon_note(str(e), tri_poly)) from None
        V = r["V"]
        value = src.value if src.value > 0 else 1.0
        name = src.name + "_snap"
        kb = write_key(obj, name, V, relative_key=src.relative_key)
        kb.value = value
        src.mute = True
        obj.active_shape_key_index = list(key.key_blocks).index(kb)
        qe, qs = sm.metrics(V0, E, F)["q_mean"], sm.metrics(V0, V, F)["q_mean"]
        LAST["snap"] = {"object": obj.name, "V0": V0, "F": F, "V_edit": E, "V": V, "result": r, "key": name,
                        "q_mean_edit": qe, "q_mean": qs}
        self.report({'INFO'}, f"spinmotor snap (trade-off {self.tradeoff:g}): Q_mean {qe:.4f} -> {qs:.4f}, key "
                              f"'{name}' (the edit '{src.name}' is muted)")
        return {'FINISHED'}


# ---- Q colours ---------------------------------------------------------------------------------------------

Q_COLOR = "spinmotor_Q"
Q_VALUE = "spinmotor_Q_value"


class SPINMOTOR_OT_q_colors(MeshOperator, bpy.types.Operator):
    """Colour the mesh by the quasi-conformal error Q of its current (evaluated) shape against the rest shape:
    1 blue (texture undistorted) to Q max red, colour attribute 'spinmotor_Q' (face attribute 'spinmotor_Q_value')"""
    bl_idname = "spinmotor.q_colors"
    bl_label = "Q Colours"
    bl_options = {'REGISTER', 'UNDO'}

    q_max: FloatProperty(name="Q max", default=1.5, min=1.001, description="Q shown red")

    def execute(self, context):
        return run_reported(self, lambda: self._run(context))

    def _run(self, context):
        obj = active_mesh(context)
        me = obj.data
        if len(me.polygons) == 0:
            raise AddonError(f"{obj.name}: the mesh has no faces")
        V0 = md.rest_positions(obj)
        E = md.evaluated_positions(context, obj)
        F, tri_poly = md.triangles(me)
        q, area = md.face_q(V0, F, E)
        npoly = len(me.polygons)
        finite = np.isfinite(q)
        num = np.bincount(tri_poly, weights=area * np.where(finite, q, 0.0), minlength=npoly)
        den = np.bincount(tri_poly, weights=area, minlength=npoly)
        bad = np.bincount(tri_poly, weights=(~finite).astype(float), minlength=npoly) > 0
        with np.errstate(divide="ignore", invalid="ignore"):
            qp = np.where(bad | (den <= 0), np.inf, num / den)
        total = np.empty(npoly, np.int32)
        me.polygons.foreach_get("loop_total", total)
        start = np.empty(npoly, np.int32)
        me.polygons.foreach_get("loop_start", start)
        corner_poly = np.empty(len(me.loops), np.int64)
        offsets = np.arange(len(me.loops)) - np.repeat(np.cumsum(total) - total, total)
        corner_poly[np.repeat(start, total) + offsets] = np.repeat(np.arange(npoly), total)
        rgba = np.ones((len(me.loops), 4), np.float32)
        rgba[:, :3] = md.srgb_to_linear(md.q_colormap(qp, self.q_max))[corner_poly]  # attribute: linear
        attr = me.color_attributes.get(Q_COLOR)
        if attr is not None and (attr.domain != 'CORNER' or attr.data_type != 'FLOAT_COLOR'):
            me.color_attributes.remove(attr)
            attr = None
        if attr is None:
            attr = me.color_attributes.new(Q_COLOR, 'FLOAT_COLOR', 'CORNER')
        attr.data.foreach_set("color", rgba.ravel())
        try:
            me.color_attributes.active_color = attr
            me.color_attributes.render_color_index = me.color_attributes.active_color_index
        except (AttributeError, TypeError):
            pass
        qa = me.attributes.get(Q_VALUE)
        if qa is not None and (qa.domain != 'FACE' or qa.data_type != 'FLOAT'):
            me.attributes.remove(qa)
            qa = None
        if qa is None:
            qa = me.attributes.new(Q_VALUE, 'FLOAT', 'FACE')
        qa.data.foreach_set("value", np.minimum(qp, np.finfo(np.float32).max).astype(np.float32))
        me.update()
        w = area[finite]
        q_mean = float((q[finite] * w).sum() / w.sum()) if w.sum() > 0 else float("nan")
        collapsed = int((~finite).sum())
        LAST["q_colors"] = {"object": obj.name, "V0": V0, "F": F, "V": E, "q": q, "area": area,
                            "q_polygon": qp, "q_mean": q_mean, "collapsed": collapsed}
        self.report({'INFO'}, f"spinmotor Q: Q_mean {q_mean:.4f}, Q_max {float(q[finite].max(initial=1)):.4f}"
                              + (f", {collapsed} collapsed triangles" if collapsed else "")
                              + f" (colour attribute '{Q_COLOR}', red at {self.q_max:g})")
        return {'FINISHED'}


# ---- motor posing with surface harmonic coordinates ----------------------------------------------------------


def handle_empties(scene, obj):
    hs = [o for o in scene.objects if o.get("spinmotor_mesh") == obj.name and "spinmotor_group" in o]
    return sorted(hs, key=lambda o: str(o["spinmotor_group"]))


class SPINMOTOR_OT_add_handle(MeshOperator, bpy.types.Operator):
    """Add an empty at the centroid of the active vertex group: a motor handle for 'Pose by Handles'. Move
    and rotate it (no scale); its motion from where it is now moves the group's vertices rigidly"""
    bl_idname = "spinmotor.add_handle"
    bl_label = "Add Handle"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        return run_reported(self, lambda: self._run(context))

    def _run(self, context):
        from mathutils import Matrix, Vector
        obj = active_mesh(context)
        vg = obj.vertex_groups.active
        if vg is None:
            raise AddonError(f"{obj.name}: no active vertex group (the handle's vertices)")
        idx = md.group_members(obj, vg.name)
        if len(idx) == 0:
            raise AddonError(f"{obj.name}: vertex group '{vg.name}' has no vertex")
        for o in handle_empties(context.scene, obj):
            if o["spinmotor_group"] == vg.name:
                raise AddonError(f"vertex group '{vg.name}' already has the handle '{o.name}'")
        V0 = md.rest_positions(obj)
        c = obj.matrix_world @ Vector(V0[idx].mean(axis=0).tolist())
        e = bpy.data.objects.new(f"{obj.name}.{vg.name}", None)
        e.empty_display_type = 'SPHERE'
        e.empty_display_size = max(0.05 * md.diagonal(V0) * max(obj.matrix_world.to_scale()), 1e-3)
        M = Matrix.Translation(c)
        e.matrix_world = M
        e["spinmotor_mesh"] = obj.name
        e["spinmotor_group"] = vg.name
        e["spinmotor_rest"] = [float(x) for row in M for x in row]
        (obj.users_collection[0] if obj.users_collection else context.scene.collection).objects.link(e)
        self.report({'INFO'}, f"spinmotor: handle '{e.name}' for {len(idx)} vertices")
        return {'FINISHED'}


def _rigid_local(sm, obj_world, empty):
    """The handle's motion since its rest matrix, in the mesh object's local space, as a Motor."""
    Mw = np.array(obj_world, dtype=np.float64)
    E = np.array(empty.matrix_world, dtype=np.float64)
    R = np.array(empty["spinmotor_rest"], dtype=np.float64).reshape(4, 4)
    L = np.linalg.inv(Mw) @ E @ np.linalg.inv(R) @ Mw
    A = L[:3, :3]
    if np.abs(A.T @ A - np.eye(3)).max() < 1e-4 and np.linalg.det(A) > 0:  # float32 roundoff only
        U, _, Vt = np.linalg.svd(A)
        L[:3, :3] = U @ Vt
    L[3] = (0, 0, 0, 1)
    try:
        return sm.Motor(L)
    except sm.Error as e:
        raise AddonError(f"handle '{empty.name}': {e} (handles move rigidly: no scale on the empty or a "
                         "non-uniform scale on the mesh object)") from None


class SPINMOTOR_OT_pose_handles(MeshOperator, bpy.types.Operator):
    """Pose the mesh by its handle empties (surface harmonic coordinates, motors blended per vertex), written as
    the shape key 'spinmotor_pose'; optionally snapped to the nearest spin transformation"""
    bl_idname = "spinmotor.pose_handles"
    bl_label = "Pose by Handles"
    bl_options = {'REGISTER', 'UNDO'}

    weights: EnumProperty(name="Weights", items=[("mean-value", "Mean value", ""), ("cotan", "Cotangent", "")],
                          default="mean-value")
    blend: EnumProperty(name="Blend", items=[("log", "Log", ""), ("pivot-log", "Pivot log", ""),
                                             ("dlb", "Dual quaternion (DLB)", "")], default="log")
    tradeoff: FloatProperty(name="Snap", default=0.0, min=0.0, max=1.0, subtype='FACTOR',
                            description="Then snap to the nearest spin transformation (0 = no snap, 1 = conformal)")

    def execute(self, context):
        return run_reported(self, lambda: self._run(context))

    def _run(self, context):
        sm = spinmotor_module(context)
        obj = active_mesh(context)
        context.view_layer.update()
        empties = handle_empties(context.scene, obj)
        if not empties:
            raise AddonError(f"{obj.name}: no handle (select a vertex group and press Add Handle)")
        V0, F, tri_poly = rest_mesh(sm, obj)
        handles = [(str(e["spinmotor_group"]), md.group_members(obj, str(e["spinmotor_group"]))) for e in empties]
        motors = [_rigid_local(sm, obj.matrix_world, e) for e in empties]
        fp = _fingerprint(V0, F, *[i for _, i in handles], extra=([g for g, _ in handles], self.weights, self.blend))
        try:
            d = cached(obj, "harmonic", fp, lambda: sm.SurfaceHarmonicDeformer(
                V0, F, handles=[(g, i.tolist()) for g, i in handles], weights=self.weights, blend=self.blend))
            V = d.pose(motors)
            posed = V
            if self.tradeoff > 0:
                V = cached(obj, "snap", _fingerprint(V0, F), lambda: sm.ConformalSnap(V0, F)).snap(
                    posed, tradeoff=self.tradeoff)
        except sm.Error as e:
            raise AddonError(f"{obj.name}: " + md.polygon_note(str(e), tri_poly)) from None
        if obj.data.shape_keys is None:
            obj.shape_key_add(name="Basis", from_mix=False)
        kb = write_key(obj, "spinmotor_pose", V)
        kb.value = 1.0
        LAST["pose_handles"] = {"object": obj.name, "V0": V0, "F": F, "handles": handles,
                                "motors": [m.to_matrix() for m in motors], "V_posed": posed, "V": V}
        q = sm.metrics(V0, V, F)["q_mean"]
        self.report({'INFO'}, f"spinmotor: posed by {len(handles)} handles, Q_mean {q:.4f}, key 'spinmotor_pose'")
        return {'FINISHED'}


classes = (SPINMOTOR_OT_bake_cleanup, SPINMOTOR_OT_pins_to_group, SPINMOTOR_OT_snap, SPINMOTOR_OT_q_colors,
           SPINMOTOR_OT_add_handle, SPINMOTOR_OT_pose_handles)
