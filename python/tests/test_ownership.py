"""Ownership: every array the module returns is a fresh numpy array that owns its memory (a copy of the
C++ result), so a later call, a mutation of the returned or the input arrays, or the death of the
object that made it, changes nothing else. scripts/python-asan runs these (and every other test) with
the module built under AddressSanitizer, where a dangling view would be a reported use-after-free."""
import gc

import numpy as np

import spinmotor as sm
from conftest import capsule_handles


def owns(a):
    """A writeable array owning its memory: a numpy allocation, or (pose results, handed over without a
    copy) the C++ matrix held by a capsule that is the array's base."""
    if not (isinstance(a, np.ndarray) and a.flags.writeable and (a.flags.c_contiguous or a.flags.f_contiguous)):
        return False
    return a.flags.owndata or type(a.base).__name__ == "PyCapsule"


def test_pose_results_survive_later_calls_and_the_deformer():
    V, F = sm.capsule(0.5, 3.0, 16, 12)
    V_in = V.copy()
    d = sm.SurfaceHarmonicDeformer(V_in, F, handles=capsule_handles(V))
    m1 = [sm.Motor(), sm.Motor.from_rotation((1, 0, 0), 40, about=(0, 0, 2.5))]
    m2 = [sm.Motor(), sm.Motor.from_rotation((0, 1, 0), -60, about=(0, 0, 2.5))]
    a = d.pose(m1)
    a_copy = a.copy(order="K")  # a's (column-major) layout: equal arrays then also sum in the same order
    b = d.pose(m2)
    assert owns(a) and owns(b) and not np.shares_memory(a, b)
    assert a.flags.f_contiguous and a.shape == V.shape  # pose hands the C++ result over (column-major)
    assert np.array_equal(a, a_copy)  # the second pose did not write into the first result
    b[:] = 0.0  # scribbling on a result changes nothing in the deformer
    V_in[:] = 7.0  # nor does changing the input array after the bind (the bind copied it)
    assert np.array_equal(d.pose(m1), a_copy)
    del d
    gc.collect()
    assert np.array_equal(a, a_copy) and float(a.sum()) == float(a_copy.sum())  # read after the deformer died


def test_snap_and_rig_results_own_their_memory(tmp_path):
    V, F = sm.capsule(0.5, 3.0, 12, 10)
    E = V * [1.0, 1.0, 1.2]
    snap = sm.ConformalSnap(V, F)
    r = snap.snap(E, full=True)
    first = {k: r[k].copy() for k in ("V", "rho", "mu", "lambda")}
    r2 = snap.snap(E * 1.1, full=True)
    for k, v in first.items():
        assert owns(r[k]) and np.array_equal(r[k], v), k
        assert not np.shares_memory(r[k], r2[k]), k
    pins = capsule_handles(V)[0][1]
    c = snap.snap(E, pins=pins)
    c_copy = c.copy()
    snap.snap(E * 0.9, pins=pins)  # reuses the bound cleanup
    assert np.array_equal(c, c_copy)
    del snap
    gc.collect()
    assert np.array_equal(c, c_copy) and np.array_equal(r["V"], first["V"])

    from test_rig_bake import write_bent_capsule
    write_bent_capsule(tmp_path / "bent.gltf")
    rig = sm.read_gltf(tmp_path / "bent.gltf")
    W, P = rig.weights, rig.V
    W[:] = -1.0  # properties are copies: the rig keeps its own weights
    P[:] = 0.0
    assert rig.weights.min() >= 0.0 and np.abs(rig.V).max() > 0
    poser = rig.poser(cleanup="pinned")
    x = poser.pose(0.5)
    x_copy = x.copy()
    poser.pose(1.0)
    del rig, poser
    gc.collect()
    assert owns(x) and np.array_equal(x, x_copy)


def test_mesh_arrays_outlive_the_mesh():
    mesh = sm.icosphere(2)
    V, F = mesh
    V2 = V.copy()
    del mesh
    gc.collect()
    assert np.array_equal(V, V2) and F.max() == len(V) - 1
