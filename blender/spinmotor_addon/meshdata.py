"""Mesh data between Blender and numpy for the add-on: rest and evaluated positions, triangles, pins,
per-face quasi-conformal error Q and its colours, and the rest-space ("corrective") shape key that makes
a modifier stack produce given positions.

Everything is in the object's local space (the space of mesh coordinates and of the modifier stack's
output), in float64. Blender stores coordinates as float32: what is read is exact in float64, what is
written back is rounded to float32 (a relative 6e-8).
"""
import re

import numpy as np

CLEANUP_PREFIX = "spinmotor_cleanup_"


class AddonError(Exception):
    """A problem with the Blender-side input (no armature, missing vertex group, ...): reported as is."""


# ---- reading -----------------------------------------------------------------------------------------


def _co(collection, n):
    co = np.empty(3 * n, np.float32)
    collection.foreach_get("co", co)
    return co.reshape(n, 3).astype(np.float64)


def rest_positions(obj):
    """(n, 3): the basis shape key if the mesh has shape keys, else the mesh's vertex coordinates."""
    me = obj.data
    key = me.shape_keys
    if key is not None:
        return _co(key.reference_key.data, len(me.vertices))
    return _co(me.vertices, len(me.vertices))


def triangles(me):
    """F (m, 3) int64 and the polygon of each triangle (m,): Blender's triangulation of the polygons
    (loop triangles, the winding of their polygon), on the mesh's own vertex indices."""
    me.calc_loop_triangles()
    m = len(me.loop_triangles)
    F = np.empty(3 * m, np.int32)
    P = np.empty(m, np.int32)
    me.loop_triangles.foreach_get("vertices", F)
    me.loop_triangles.foreach_get("polygon_index", P)
    return F.reshape(m, 3).astype(np.int64), P


def evaluated_positions(context, obj):
    """(n, 3): the object's mesh after its shape keys and modifier stack at the current frame (the
    armature pose). AddonError if the stack changes the vertex count (subdivision, mirror, ...)."""
    dg = context.evaluated_depsgraph_get()
    ob = obj.evaluated_get(dg)
    me = ob.to_mesh()
    try:
        n = len(me.vertices)
        if n != len(obj.data.vertices):
            raise AddonError(
                f"{obj.name}: the modifier stack changes the vertex count ({len(obj.data.vertices)} -> {n}); "
                "the cleanup needs the deformed mesh vertex for vertex (disable Subdivision, Mirror, ... "
                "or move them after the deformers and turn them off for the bake)")
        return _co(me.vertices, n)
    finally:
        ob.to_mesh_clear()


def group_members(obj, name):
    """Indices of the vertices with a positive weight in the vertex group `name` (AddonError if the
    object has no such group)."""
    vg = obj.vertex_groups.get(name)
    if vg is None:
        have = ", ".join(g.name for g in obj.vertex_groups) or "none"
        raise AddonError(f"{obj.name}: no vertex group named '{name}' (its vertex groups: {have})")
    gi = vg.index
    return np.array([v.index for v in obj.data.vertices for g in v.groups if g.group == gi and g.weight > 0],
                    dtype=np.int64)


def armature_modifiers(obj):
    return [m for m in obj.modifiers if m.type == 'ARMATURE' and m.object is not None and m.object.type == 'ARMATURE'
            and m.use_vertex_groups]


def bone_weights(obj):
    """W (n, B) skin weights of the object's Armature modifiers: one column per deform bone that has a
    vertex group, rows normalised as Blender's armature deform does; vertices without any bone weight
    (which the armature leaves where they are) get a column of their own. Returns (W, names)."""
    mods = armature_modifiers(obj)
    if not mods:
        raise AddonError(f"{obj.name}: no Armature modifier with an armature object (the pins come from its "
                         "bone weights); add one or name a pin vertex group")
    names = []
    for m in mods:
        for b in m.object.data.bones:
            if b.use_deform and b.name not in names and b.name in obj.vertex_groups:
                names.append(b.name)
    if not names:
        raise AddonError(f"{obj.name}: no vertex group is named after a deform bone of "
                         f"{', '.join(m.object.name for m in mods)} (no skin weights)")
    col = {obj.vertex_groups[nm].index: c for c, nm in enumerate(names)}
    n = len(obj.data.vertices)
    W = np.zeros((n, len(names) + 1))
    for v in obj.data.vertices:
        for g in v.groups:
            c = col.get(g.group)
            if c is not None and g.weight > 0:
                W[v.index, c] += g.weight
    s = W.sum(axis=1)
    loose = s <= 0
    if loose.any():
        W[loose, -1] = 1.0
        names.append("(no bone)")
        s[loose] = 1.0
    else:
        W = W[:, :-1]
    return W / s[:, None], names


def rest_bones(obj, names, V0, W):
    """The rest bones of the weight columns `names` (W (n, B) and names from bone_weights), for the library's
    per-bone default margin: (name, parent column or None, head, tail) in the object's local space (the space of
    its mesh and of the Armature modifier's result), from each bone's head_local / tail_local in its armature's
    space. A bone's parent is its nearest ancestor that is a column. The "(no bone)" column (vertices no bone
    deforms) gets a root bone across their rest bounding box."""
    found = {}
    for m in armature_modifiers(obj):
        for b in m.object.data.bones:
            found.setdefault(b.name, (m.object, b))
    col = {nm: c for c, nm in enumerate(names)}
    to_local = obj.matrix_world.inverted()
    bones = []
    for c, nm in enumerate(names):
        if nm not in found:  # "(no bone)": a root across the loose vertices
            P = np.asarray(V0)[np.asarray(W)[:, c] > 0]
            lo, hi = P.min(axis=0), P.max(axis=0)
            if not np.linalg.norm(hi - lo) > 0:
                hi = lo + np.array([0.0, 0.0, 1.0])
            bones.append((nm, None, tuple(map(float, lo)), tuple(map(float, hi))))
            continue
        arm, b = found[nm]
        M = to_local @ arm.matrix_world
        p = b.parent
        while p is not None and p.name not in col:
            p = p.parent
        bones.append((nm, col[p.name] if p is not None else None, tuple(M @ b.head_local), tuple(M @ b.tail_local)))
    return bones


# ---- welding by position ----------------------------------------------------------------------------------------


class Weld:
    """The mesh with the vertices of exactly equal rest positions merged (float32 coordinates, as Blender stores
    them): importers split vertices at UV seams and hard edges (a glTF file arrives as loose triangles when every
    corner has its own texture coordinate), which would leave the cleanup a surface of disconnected pieces.

    first (k,): the first Blender vertex of each welded vertex, in order of appearance; inverse (n,): the welded
    vertex of each Blender vertex; F (m', 3): the triangles on welded vertices (those that collapse dropped) and
    tri_polygon (m',) their polygons. weld(X) takes per-vertex rows (positions, weights) to the welded mesh (the
    first vertex of each group), unweld(Y) back to every Blender vertex."""

    def __init__(self, V0, F, tri_polygon):
        key = np.ascontiguousarray(V0, dtype=np.float32)
        _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
        order = np.argsort(first, kind="stable")
        rank = np.empty_like(order)
        rank[order] = np.arange(len(order))
        self.first = first[order]
        self.inverse = rank[np.asarray(inverse).ravel()]
        Fw = self.inverse[F]
        keep = (Fw[:, 0] != Fw[:, 1]) & (Fw[:, 1] != Fw[:, 2]) & (Fw[:, 2] != Fw[:, 0])
        self.F = Fw[keep]
        self.tri_polygon = np.asarray(tri_polygon)[keep]
        self.n, self.k = len(V0), len(self.first)

    def weld(self, X):
        return np.asarray(X)[self.first]

    def unweld(self, Y):
        return np.asarray(Y)[self.inverse]

    def blender_indices(self, welded):
        """The Blender vertices of the welded vertices `welded` (every copy), increasing."""
        mask = np.zeros(self.k, bool)
        mask[np.asarray(welded, dtype=np.int64)] = True
        return np.flatnonzero(mask[self.inverse])


# ---- quasi-conformal error -----------------------------------------------------------------------------


def face_q(V0, F, V):
    """Per triangle Q = sigma_max / sigma_min of the linear map from the rest triangle to the deformed
    one (inf for a collapsed image) and the rest areas. The same definition as `spinmotor metrics`."""
    p0, p1, p2 = V0[F[:, 0]], V0[F[:, 1]], V0[F[:, 2]]
    u, w = p1 - p0, p2 - p0
    a = np.linalg.norm(u, axis=1)
    x = u / a[:, None]
    b = np.einsum("ij,ij->i", w, x)
    d = np.linalg.norm(w - b[:, None] * x, axis=1)
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    j0 = e1 / a[:, None]
    j1 = (e2 - (b / a)[:, None] * e1) / d[:, None]
    g11, g22, g12 = (j0 * j0).sum(1), (j1 * j1).sum(1), (j0 * j1).sum(1)
    h = 0.5 * (g11 + g22)
    disc = np.sqrt(np.maximum(0.0, h * h - (g11 * g22 - g12 * g12)))
    smax2, smin2 = h + disc, h - disc
    with np.errstate(divide="ignore", invalid="ignore"):
        q = np.where(smin2 <= 1e-24 * smax2, np.inf, np.sqrt(smax2 / np.maximum(smin2, 1e-300)))
    area = 0.5 * np.linalg.norm(np.cross(u, w), axis=1)
    return q, area


def q_colormap(q, q_max):
    """RGB (k, 3) in [0, 1]: Q = 1 blue, sqrt(q_max) pale yellow, >= q_max red, on a log scale (the
    colours of `spinmotor render --color q`)."""
    t = np.log(np.maximum(np.nan_to_num(q, nan=np.inf, posinf=1e300), 1.0)) / np.log(max(q_max, 1.0 + 1e-9))
    t = np.clip(t, 0.0, 1.0)
    c = np.array([[49, 54, 149], [255, 255, 191], [165, 0, 38]], float) / 255.0
    lo = t < 0.5
    s = np.where(lo, 2 * t, 2 * t - 1)[:, None]
    return np.where(lo[:, None], c[0] + s * (c[1] - c[0]), c[1] + s * (c[2] - c[1]))


def srgb_to_linear(c):
    """Display (sRGB) colour values to the scene-linear values float colour attributes hold."""
    c = np.asarray(c, dtype=np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def volume(V, F):
    return float(np.einsum("ij,ij->i", V[F[:, 0]], np.cross(V[F[:, 1]], V[F[:, 2]])).sum() / 6.0)


def diagonal(V):
    return float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))


# ---- messages --------------------------------------------------------------------------------------------


def polygon_note(message, tri_polygon):
    """The library names triangles of the triangulation ("face 17"); add the Blender polygon each is part
    of, so the artist can find it."""
    def note(m):
        f = int(m.group(2))
        if 0 <= f < len(tri_polygon):
            return f"{m.group(0)} (triangle of polygon {int(tri_polygon[f])})"
        return m.group(0)
    return re.sub(r"\b(face|faces) (\d+)\b", note, message, count=2)


def check_mesh(sm, obj, V, F, tri_polygon):
    """AddonError with the library's own description (spinmotor.check) if the triangulated mesh is not a
    consistently oriented manifold, has vertices in no face or non-finite coordinates."""
    c = sm.check(V, F)
    bad = (c.get("non_manifold_edges", 0) or c.get("non_manifold_vertices", 0) or
           c.get("inconsistent_orientation", 0) or c.get("unreferenced_vertices", 0) or
           c.get("nonfinite_vertices", 0))
    if bad:
        raise AddonError(f"{obj.name}: " + polygon_note(str(c.get("defects", "not a manifold mesh")), tri_polygon))
    return c


# ---- writing a rest-space key -------------------------------------------------------------------------------


def set_key_co(kb, V):
    kb.data.foreach_set("co", np.ascontiguousarray(V, dtype=np.float32).ravel())


def tag_key_update(obj):
    key = obj.data.shape_keys
    if key is not None:
        key.update_tag()
    obj.data.update_tag()
    obj.update_tag()


def corrective_key(context, obj, tmp, basis, target, goal, accept, max_steps=8):
    """Coordinates K (n, 3) for a relative shape key such that the object's evaluated mesh with that key at
    value 1 (on top of the other keys) is `target` (n, 3), through the modifier stack.

    The stack's per-vertex Jacobian J (3×3, from finite differences of the whole stack with every vertex
    displaced along x, y, z) gives Newton steps d += J⁻¹ (target − f(basis + d)); an armature (linear blend
    or dual quaternion skinning) is affine per vertex, so the first step is exact up to float32; other
    stacks take a few steps. Steps stop at a max residual <= `goal` (float32 roundoff of Blender's
    evaluation bounds what is reachable). `tmp` is a scratch shape key (value 1) used for the evaluations.
    Returns (K, max residual). AddonError if J is singular (e.g. a bone scaled to 0) or the residual stays
    above `accept`."""
    n = len(basis)

    def f(offset):
        set_key_co(tmp, basis + offset)
        tag_key_update(obj)
        return evaluated_positions(context, obj)

    f0 = f(np.zeros((n, 3)))
    h = max(1e-2 * diagonal(basis), 1e-6)
    J = np.empty((n, 3, 3))
    for k in range(3):
        e = np.zeros((n, 3))
        e[:, k] = h
        J[:, :, k] = (f(e) - f0) / h
    det = np.linalg.det(J)
    scale = np.abs(J).max(axis=(1, 2)) ** 3
    singular = np.flatnonzero(~(np.abs(det) > 1e-9 * np.maximum(scale, 1e-300)))
    if len(singular):
        raise AddonError(f"{obj.name}: the modifier stack flattens vertex {int(singular[0])} ({len(singular)} "
                         "vertices in all; a bone or hook scaled to 0?): no shape key before it can reach the "
                         "cleaned positions")
    d = np.linalg.solve(J, (target - f0)[:, :, None])[:, :, 0]
    best, best_err = d, np.inf
    for _ in range(max_steps):
        r = target - f(d)
        err = float(np.abs(r).max())
        if err < best_err:
            best, best_err = d, err
        if err <= goal:
            break
        d = d + np.linalg.solve(J, r[:, :, None])[:, :, 0]
    d, err = best, best_err
    if not err <= accept:
        raise AddonError(f"{obj.name}: the corrective shape key does not reproduce the cleanup through the "
                         f"modifier stack (residual {err:.3g} > {accept:.3g} after {max_steps} Newton steps); "
                         "write a new object instead (Output: New object)")
    set_key_co(tmp, basis + d)
    return basis + d, err
