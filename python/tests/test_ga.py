"""Motors: construction, matrices, log/exp, composition, blends (known values)."""
import math

import numpy as np
import pytest

import spinmotor as sm


def rot_z(deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def test_identity():
    M = sm.Motor()
    np.testing.assert_array_equal(M.to_matrix(), np.eye(4))
    np.testing.assert_array_equal(M.log(), np.zeros(6))
    P = np.random.default_rng(0).normal(size=(10, 3))
    np.testing.assert_array_equal(M.apply(P), P)


def test_matrix_round_trip():
    A = np.eye(4)
    A[:3, :3] = rot_z(30) @ np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0.0]])
    A[:3, 3] = [0.5, -2.0, 3.0]
    M = sm.Motor(A)
    np.testing.assert_allclose(M.to_matrix(), A, atol=1e-14)
    np.testing.assert_allclose(sm.Motor(np.asfortranarray(A)).to_matrix(), A, atol=1e-14)


def test_from_rotation_about_a_point():
    # 90 degrees about z through (1, 0, 0), then +z: the origin goes to (1, -1, 2)
    M = sm.Motor.from_rotation((0, 0, 1), 90, about=(1, 0, 0), translate=(0, 0, 2))
    np.testing.assert_allclose(M.apply(np.zeros(3)), [1, -1, 2], atol=1e-15)
    np.testing.assert_allclose(M.apply([1.0, 0, 0]), [1, 0, 2], atol=1e-15)  # the pivot stays (+t)
    np.testing.assert_allclose(M.to_matrix()[:3, :3], rot_z(90), atol=1e-15)


def test_log_exp_round_trip():
    rng = np.random.default_rng(1)
    for _ in range(20):
        axis = rng.normal(size=3)
        M = sm.Motor.from_rotation(axis, rng.uniform(-170, 170), about=rng.normal(size=3),
                                   translate=rng.normal(size=3))
        B = M.log()
        assert B.shape == (6,)
        np.testing.assert_allclose(sm.Motor.exp(B).to_matrix(), M.to_matrix(), atol=1e-12)
    # a rotation by theta has |omega| = theta / 2
    B = sm.Motor.from_rotation((0, 0, 1), 60).log()
    assert abs(np.linalg.norm(B[:3]) - math.radians(30)) < 1e-15


def test_composition_is_the_matrix_product():
    a = sm.Motor.from_rotation((1, 2, 3), 40, translate=(1, 0, 0))
    b = sm.Motor.from_rotation((0, 1, 0), -75, about=(0, 0, 2))
    np.testing.assert_allclose((a * b).to_matrix(), a.to_matrix() @ b.to_matrix(), atol=1e-14)
    P = np.random.default_rng(2).normal(size=(5, 3))
    np.testing.assert_allclose((a * b).apply(P), a.apply(b.apply(P)), atol=1e-14)
    np.testing.assert_allclose((a * a.inverse()).to_matrix(), np.eye(4), atol=1e-14)


def test_apply_matches_the_matrix():
    M = sm.Motor.from_rotation((1, 1, 0), 33, translate=(0.1, 0.2, 0.3))
    P = np.random.default_rng(3).normal(size=(50, 3))
    A = M.to_matrix()
    np.testing.assert_allclose(M.apply(P), P @ A[:3, :3].T + A[:3, 3], atol=1e-14)
    np.testing.assert_allclose(M.apply(np.asfortranarray(P)), M.apply(P), atol=0)


def test_blend_modes():
    a = sm.Motor.from_rotation((0, 0, 1), 0)
    b = sm.Motor.from_rotation((0, 0, 1), 90)
    for mode in sm.option_values("blend"):
        half = sm.blend([a, b], [0.5, 0.5], mode=mode)
        np.testing.assert_allclose(half.to_matrix()[:3, :3], rot_z(45), atol=1e-14)
    np.testing.assert_allclose(sm.blend([b], [1.0]).to_matrix(), b.to_matrix(), atol=1e-14)


def test_blend_errors_list_the_choices():
    with pytest.raises(sm.Error, match=r"unknown blend 'lgo' \(one of: log, pivot-log, dlb\)") as e:
        sm.blend([sm.Motor()], [1.0], mode="lgo")
    assert e.value.kind == "bad_input"
    with pytest.raises(sm.Error, match="weights"):
        sm.blend([sm.Motor(), sm.Motor()], [1.0])
    with pytest.raises(sm.Error):
        sm.blend([], [])
    with pytest.raises(sm.Error, match=r"motors\[1\]"):
        sm.blend([sm.Motor(), 3], [0.5, 0.5])


def test_bad_matrices():
    with pytest.raises(sm.Error, match="rotation"):
        sm.Motor(np.diag([2.0, 1, 1, 1]))
    with pytest.raises(sm.Error, match="shape"):
        sm.Motor(np.eye(3))
    bad = np.eye(4)
    bad[0, 3] = np.nan
    with pytest.raises(sm.Error, match="not finite"):
        sm.Motor(bad)
    with pytest.raises(sm.Error, match="axis"):
        sm.Motor.from_rotation((0, 0, 0), 10)


def test_pickle():
    import pickle
    M = sm.Motor.from_rotation((1, 0, 0), 20, translate=(1, 2, 3))
    np.testing.assert_array_equal(pickle.loads(pickle.dumps(M)).coefficients(), M.coefficients())
