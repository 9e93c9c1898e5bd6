"""Deformers through the shared shape: identity poses return the rest mesh, handles follow their
motors, controls, options and errors."""
import numpy as np
import pytest

import spinmotor as sm
from conftest import capsule_handles


def identities(d):
    return [sm.Motor() for _ in d.controls]


def skeleton_rig(V):
    """Two bones along z (0..1.5, 1.5..3) and smooth weights by height."""
    bones = [{"name": "root", "head": (0, 0, 0), "tail": (0, 0, 1.5)},
             {"name": "tip", "parent": 0, "head": (0, 0, 1.5), "tail": (0, 0, 3)}]
    t = np.clip((V[:, 2] - 1.0) / 1.0, 0.0, 1.0)
    W = np.stack([1.0 - t, t], axis=1)
    return bones, W


def all_deformers(V, F):
    handles = capsule_handles(V)
    bones, W = skeleton_rig(V)
    cage_V, cage_F = sm.icosphere(1, radius=3.0)
    cage_V = cage_V + np.array([0, 0, 1.5])
    chain = np.array([[0, 0, 0], [0, 0, 1.0], [0, 0, 2.0], [0, 0, 3.0]])
    return [
        sm.SurfaceHarmonicDeformer(V, F, handles=handles),
        sm.ArapDeformer(V, F, handles=handles),
        sm.FfdDeformer(V, F, lattice=(3, 3, 4)),
        sm.CageDeformer(V, F, cage=(cage_V, cage_F), coordinates="mean-value"),
        sm.SkinDeformer(V, F, skeleton=bones, weights=W, blend="log"),
        sm.DeltaMushDeformer(V, F, skeleton=bones, weights=W),
        sm.DirectDeltaMushDeformer(V, F, skeleton=bones, weights=W),
        sm.SplineDeformer(V, F, handles=handles),
        sm.SplineIkDeformer(V, F, handles=handles, chain=chain, target=(0, 0, 3.0)),
    ]


def test_identity_motors_return_the_rest_mesh(capsule):
    V, F = capsule
    for d in all_deformers(V, F):
        assert isinstance(d, sm.Deformer) and d.vertices == len(V)
        out = d.pose(identities(d))
        assert out.shape == V.shape and out.dtype == np.float64
        # Delta Mush's smoothed frames reproduce the rest up to rounding of the deltas
        np.testing.assert_allclose(out, V, atol=1e-12 if "Mush" not in d.type else 1e-10, err_msg=d.type)


def test_surface_harmonic_handles_follow_their_motors(capsule):
    V, F = capsule
    handles = capsule_handles(V)
    d = sm.SurfaceHarmonicDeformer(V, F, handles=handles, weights="cotan", blend="pivot-log")
    names = [c[0] for c in d.controls]
    assert names == ["base", "tip"]
    np.testing.assert_allclose(d.controls[1][1], V[handles[1][1]].mean(axis=0), atol=1e-15)
    M0 = sm.Motor.from_translation((0.1, 0, 0))
    M1 = sm.Motor.from_rotation((1, 0, 0), 70, about=(0, 0, 3), translate=(0, 0.5, 0))
    out = d.pose([M0, M1])
    np.testing.assert_allclose(out[handles[0][1]], M0.apply(V[handles[0][1]]), atol=1e-12)
    np.testing.assert_allclose(out[handles[1][1]], M1.apply(V[handles[1][1]]), atol=1e-12)
    # dict handles and F-ordered inputs give the same result
    d2 = sm.SurfaceHarmonicDeformer(np.asfortranarray(V), np.asfortranarray(F).astype(np.int64),
                                    handles={n: list(i) for n, i in handles}, weights="cotan",
                                    blend="pivot-log")
    np.testing.assert_array_equal(d2.pose([M0, M1]), out)


def test_arap_handles_follow_their_motors(capsule):
    V, F = capsule
    handles = capsule_handles(V)
    d = sm.ArapDeformer(V, F, handles=handles, initial="harmonic")
    M0 = sm.Motor()
    M1 = sm.Motor.from_rotation((0, 1, 0), 25, about=(0, 0, 3), translate=(0.2, 0, 0))
    out = d.pose([M0, M1])
    np.testing.assert_allclose(out[handles[0][1]], V[handles[0][1]], atol=1e-12)
    np.testing.assert_allclose(out[handles[1][1]], M1.apply(V[handles[1][1]]), atol=1e-12)
    # edge lengths stay close to the rest ones (as rigid as possible)
    E = np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    rest = np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1)
    posed = np.linalg.norm(out[E[:, 0]] - out[E[:, 1]], axis=1)
    assert np.median(np.abs(posed / rest - 1.0)) < 0.05


def test_ffd_and_skin_move_rigidly(capsule):
    V, F = capsule
    M = sm.Motor.from_rotation((1, 1, 1), 40, translate=(1, 2, 3))
    d = sm.FfdDeformer(V, lattice=(2, 2, 2))
    assert len(d.controls) == 8 and d.controls[0][0] == "ffd[0,0,0]"
    np.testing.assert_allclose(d.pose([M] * 8), M.apply(V), atol=1e-12)
    bones, W = skeleton_rig(V)
    for blend in ["lbs", "dlb", "log", "pivot-log"]:
        s = sm.SkinDeformer(V, F, skeleton=bones, weights=W, blend=blend)
        assert [c[0] for c in s.controls] == ["root", "tip"]
        np.testing.assert_allclose(s.pose([M, M]), M.apply(V), atol=1e-12)


def test_defaults_come_from_the_options():
    import inspect
    doc = sm.ArapDeformer.__init__.__doc__
    assert "energy: str = 'spokes-and-rims'" in doc and "iterations: int = 100" in doc
    assert "weights: str = 'mean-value'" in sm.SurfaceHarmonicDeformer.__init__.__doc__
    assert "blend: str = 'dlb'" in sm.SkinDeformer.__init__.__doc__
    assert "margin: float = 0.05" in sm.FfdDeformer.__init__.__doc__
    del inspect


def test_deformer_errors(capsule):
    V, F = capsule
    handles = capsule_handles(V)
    with pytest.raises(sm.Error, match=r"unknown weights 'harmonic' \(one of: mean-value, cotan\)"):
        sm.SurfaceHarmonicDeformer(V, F, handles=handles, weights="harmonic")
    with pytest.raises(sm.Error, match="unknown blend"):
        sm.SurfaceHarmonicDeformer(V, F, handles=handles, blend="linear")
    with pytest.raises(sm.Error, match="tip"):  # index out of range, named by the handle
        sm.SurfaceHarmonicDeformer(V, F, handles=[("base", handles[0][1]), ("tip", [len(V)])])
    with pytest.raises(sm.Error):  # a vertex in two handles
        sm.SurfaceHarmonicDeformer(V, F, handles=[("a", [0, 1]), ("b", [1, 2])])
    d = sm.SurfaceHarmonicDeformer(V, F, handles=handles)
    with pytest.raises(sm.Error, match="motors"):
        d.pose([sm.Motor()])
    with pytest.raises(sm.Error, match=r"motors\[0\]"):
        d.pose([np.eye(4), sm.Motor()])
    bones, W = skeleton_rig(V)
    with pytest.raises(sm.Error, match="weights"):
        sm.SkinDeformer(V, F, skeleton=bones, weights=W[:, :1])
    with pytest.raises(sm.Error, match="unknown key 'parnet'"):
        sm.SkinDeformer(V, F, skeleton=[{"name": "a", "parnet": 0, "head": (0, 0, 0), "tail": (0, 0, 1)}],
                        weights=W[:, :1])
    with pytest.raises(sm.Error, match="cage"):
        sm.CageDeformer(V, F, cage=None)
    V2 = V.copy()
    V2[3, 1] = np.inf
    with pytest.raises(sm.Error, match="row 3, column 1 is not finite"):
        sm.ArapDeformer(V2, F, handles=handles)


def test_memory_limit_refuses_a_cage_grid_at_once():
    """set_memory_limit: a harmonic cage grid that cannot fit raises spinmotor.Error naming the estimate
    and the limit before any work (grid 512 ran for minutes before); None restores the default."""
    V, F = sm.torus(1.0, 0.4, 24, 12)
    cage_V, cage_F = sm.icosphere(1, radius=2.0)
    default = sm.memory_limit()
    try:
        sm.set_memory_limit("4G")
        assert sm.memory_limit() == 4 << 30
        with pytest.raises(sm.Error, match=r"grid 512 \(.* nodes\) needs an estimated .* TB of memory; "
                                           r"the limit is 4\.0 GB"):
            sm.CageDeformer(V, F, cage=(cage_V, cage_F), coordinates="harmonic", grid=512)
        sm.set_memory_limit(64 << 20)
        assert sm.CageDeformer(V, F, cage=(cage_V, cage_F), coordinates="harmonic", grid=16) is not None
        with pytest.raises(sm.Error, match="memory size '12X'"):
            sm.set_memory_limit("12X")
        with pytest.raises(sm.Error, match="must be positive"):
            sm.set_memory_limit(0)
    finally:
        sm.set_memory_limit(None)
    assert sm.memory_limit() == default
