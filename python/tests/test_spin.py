"""Spin transformations, the conformal snap, flows and the Dirac spectrum (known values), progress
callbacks."""
import numpy as np
import pytest

import spinmotor as sm
from conftest import capsule_handles


def similarity(V):
    M = sm.Motor.from_rotation((1, 2, -0.5), 40, translate=(0.3, -2.0, 5.0))
    return 1.7 * M.apply(V)


def diag(V):
    return np.linalg.norm(V.max(axis=0) - V.min(axis=0))


def test_snap_of_a_similarity_returns_it():
    V, F = sm.icosphere(3)
    E = similarity(V)
    snap = sm.ConformalSnap(V, F)
    out = snap.snap(E)
    assert np.abs(out - E).max() / diag(E) < 1e-8
    r = snap.snap(np.asfortranarray(E), full=True)
    assert np.abs(r["rho"]).max() < 1e-8
    np.testing.assert_allclose(r["V"], out, atol=1e-12)
    assert set(r) >= {"V", "rho", "mu", "lambda", "eigenvalue", "iterations", "residual", "timings_ms"}


def test_snap_brings_a_bent_capsule_near_conformal(capsule):
    V, F = capsule
    d = sm.SurfaceHarmonicDeformer(V, F, handles=capsule_handles(V))
    E = d.pose([sm.Motor(), sm.Motor.from_rotation((1, 0, 0), 80, about=(0, 0, 2.5))])
    snap = sm.ConformalSnap(V, F)
    q_edit = sm.metrics(V, E, F)["q_mean"]
    q_snap = sm.metrics(V, snap.snap(E), F)["q_mean"]
    q_half = sm.metrics(V, snap.snap(E, tradeoff=0.5), F)["q_mean"]
    assert q_snap < q_half < q_edit
    assert q_snap < 1.0 + 0.1 * (q_edit - 1.0)
    def rms(X):
        return np.sqrt(((X - E) ** 2).sum(axis=1).mean())
    assert rms(snap.snap(E, tradeoff=0.0)) < rms(snap.snap(E, tradeoff=1.0))  # 0 follows the edit
    with pytest.raises(sm.Error, match="tradeoff"):
        snap.snap(E, tradeoff=1.5)
    with pytest.raises(sm.Error, match="V_edit"):
        snap.snap(E[:10])


def test_spin_transform_rho_zero_is_the_mesh(sphere):
    V, F = sphere
    st = sm.SpinTransform(V, F)
    out = st.solve(np.zeros(len(F)))
    np.testing.assert_allclose(out, V, atol=1e-8)
    r = st.solve(0.3 * np.sin(np.arange(len(F))), full=True)
    assert r["V"].shape == V.shape and r["lambda"].shape == (len(V), 4)
    with pytest.raises(sm.Error, match="rho"):
        st.solve(np.zeros(len(F) + 1))
    with pytest.raises(sm.Error, match="not finite"):
        st.solve(np.full(len(F), np.nan))


def test_spin_rejects_open_or_broken_meshes():
    V, F = sm.tube(1.0, 2.0, 4, 8)
    with pytest.raises(sm.Error, match="closed"):
        sm.fair(V, F, steps=1, tau=0.5)
    V2, F2 = sm.icosphere(1)
    with pytest.raises(sm.Error):
        sm.SpinTransform(V2, np.vstack([F2, F2[:1]]))


def test_fair_with_progress_and_extrude_back():
    V, F = sm.icosphere(2)
    E = V * np.array([1.0, 1.0, 1.6])  # an ellipsoid
    seen = []
    r = sm.fair(E, F, steps=3, tau=0.5, progress=lambda s, n: seen.append((s, n)))
    assert seen == [(1, 3), (2, 3), (3, 3)]
    w = r["willmore"]
    assert len(w) == 4 and w[-1] < w[0]
    back = sm.extrude(r["V"], F, E, steps=4)
    assert sm.metrics(E, back["V"], F, alignment="similarity", willmore=False)["rms"] < 0.02


def test_progress_exception_propagates():
    V, F = sm.icosphere(1)

    class Stop(Exception):
        pass

    def stop(step, total):
        raise Stop()

    with pytest.raises(Stop):
        sm.fair(V * [1, 1, 1.3], F, steps=3, tau=0.5, progress=stop)
    with pytest.raises(sm.Error, match="progress"):
        sm.fair(V, F, steps=1, tau=0.5, progress=3)


def test_willmore_flow_decreases_energy():
    V, F = sm.icosphere(2)
    E = V * np.array([1.0, 1.0, 1.5])
    seen = []
    r = sm.willmore_flow(E, F, tau=0.05, steps=3, progress=lambda s, n: seen.append(s))
    assert seen == [1, 2, 3] and len(r["willmore"]) == 4 and len(r["positions"]) == 4
    assert r["willmore"][-1] < r["willmore"][0]


def test_dirac_spectrum_of_a_sphere(sphere):
    V, F = sphere
    s = sm.dirac_spectrum(V, F, count=4)
    assert s["eigenvalues"].shape == (4,) and s["constant_kernel"] == 4
    assert np.all(np.diff(np.abs(s["eigenvalues"])) >= -1e-12)


def test_gil_is_released_during_snaps():
    """Two threads snapping at once finish (and agree with the serial result)."""
    import threading
    V, F = sm.icosphere(3)
    E = similarity(V)
    snaps = [sm.ConformalSnap(V, F) for _ in range(2)]
    out = [None, None]

    def run(i):
        out[i] = snaps[i].snap(E)

    ts = [threading.Thread(target=run, args=(i,)) for i in range(2)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    np.testing.assert_allclose(out[0], out[1], atol=1e-12)


def test_python_runs_while_a_snap_solves():
    """The GIL is released inside the solve: the main thread keeps running Python meanwhile. Counted,
    not timed: with the GIL held the main thread could run only between the three solves (a handful of
    loop turns); released, it turns throughout them (hundreds at 1 ms a turn)."""
    import threading
    import time
    V, F = sm.icosphere(5)  # 10,242 vertices
    snap = sm.ConformalSnap(V, F)
    E = similarity(V)
    done = threading.Event()
    started = threading.Event()

    def run():
        started.set()
        for _ in range(3):
            snap.snap(E)
        done.set()

    t = threading.Thread(target=run)
    t.start()
    started.wait()
    turns = 0
    while not done.is_set():
        time.sleep(0.001)
        turns += 1
    t.join()
    assert turns >= 20, turns


def volume(V, F):
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    return np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0


def test_pinned_cleanup_keeps_the_pins_and_the_volume(capsule):
    V, F = capsule
    handles = capsule_handles(V)
    d = sm.SurfaceHarmonicDeformer(V, F, handles=handles)
    E = d.pose([sm.Motor(), sm.Motor.from_rotation((1, 0, 0), 80, about=(0, 0, 2.5))])
    pins = np.concatenate([np.asarray(ix) for _, ix in handles])
    c = sm.PinnedCleanup(V, F, pins)
    r = c.cleanup(E, full=True)
    out = r["V"]
    assert np.array_equal(out[pins], E[pins])  # pins are copied bit for bit
    q_edit = sm.metrics(V, E, F)["q_mean"]
    q_clean = sm.metrics(V, out, F)["q_mean"]
    assert q_clean < q_edit
    assert abs(volume(out, F) / volume(V, F) - 1) < 1e-6  # the rest volume (closed capsule)
    assert r["keep"] == "volume" and r["pin_error"] == 0.0
    assert sorted(c.pins) == sorted(set(pins.tolist()))


def test_pinned_cleanup_errors(capsule):
    V, F = capsule
    with pytest.raises(sm.Error, match="keep"):
        sm.PinnedCleanup(V, F, [0, 1], keep="mass")
    with pytest.raises(sm.Error):
        sm.PinnedCleanup(V, F, [])
    with pytest.raises(sm.Error):
        sm.PinnedCleanup(V, F, [len(V)])
    W = np.zeros((len(V), 2))
    W[:, 0] = (V[:, 2] < 1.5).astype(float)
    W[:, 1] = 1 - W[:, 0]
    pins = sm.pins_from_weights(V, W, 0.999, 0.0)
    assert len(pins) == len(V)  # every vertex is one bone's with weight 1


def test_rig_pose_matches_the_gltf_formula_and_cleans_up(meshes_dir):
    import os
    rigs = os.path.join(os.path.dirname(meshes_dir), "rigs")
    if not os.path.isdir(rigs):
        pytest.skip("../shared/rigs not found")
    rig = sm.read_gltf(os.path.join(rigs, "CesiumMan.gltf"))
    V0, F = rig.V, rig.F
    assert V0.shape == (2338, 3) and len(rig.joint_names) == 19
    name, start, end = rig.animations[0]
    t = 0.5 * (start + end)
    V = rig.pose(t)
    ref = rig.skin_positions(t)
    assert np.abs(V - ref).max() / diag(ref) < 1e-5  # float32 inverse bind matrices: 7e-7 measured
    assert np.abs(rig.pose(t, blend="dlb") - V).max() / diag(V) < 0.05
    pins = sm.pins_from_weights(V0, rig.weights, 0.95, 0.0)
    out = sm.PinnedCleanup(V0, F, pins).cleanup(V)
    assert np.array_equal(out[pins], V[pins])
    assert sm.metrics(V0, out, F)["q_mean"] < sm.metrics(V0, V, F)["q_mean"]
    with pytest.raises(sm.Error, match="blend"):
        rig.pose(t, blend="quadratic")
    with pytest.raises(sm.Error, match="out of range"):
        rig.pose(t, animation=3)


def test_pose_attraction_matches_the_library_and_holds_the_pose(capsule):
    """PinnedCleanup(pose_weight, attraction) and pin_attraction_from_weights: gamma = 0 is the plain
    cleanup bit for bit, the smoothstep weights are exact, a larger gamma stays nearer the edit."""
    V0, F = capsule
    z = V0[:, 2]
    t = np.clip((z - 1.0) / 1.0, 0, 1)
    w = t * t * (3 - 2 * t)
    W = np.stack([1 - w, w], axis=1)
    a = sm.pin_attraction_from_weights(W)
    s = np.clip((np.maximum(W[:, 0], W[:, 1]) - 0.5) / (0.999 - 0.5), 0, 1)
    assert np.abs(a - s * s * (3 - 2 * s)).max() < 1e-15
    pins = sm.pins_from_weights(V0, W, 0.999, 0.25)
    c, s_ = np.cos(np.pi / 2), np.sin(np.pi / 2)
    R = np.array([[1, 0, 0], [0, c, -s_], [0, s_, c]])
    elbow = np.array([0, 0, 1.5])
    E = W[:, :1] * V0 + W[:, 1:] * ((V0 - elbow) @ R.T + elbow)  # LBS, elbow bent 90 degrees
    plain = sm.PinnedCleanup(V0, F, pins).cleanup(E)
    assert np.array_equal(sm.PinnedCleanup(V0, F, pins, pose_weight=0.0, attraction=a).cleanup(E), plain)
    held = sm.PinnedCleanup(V0, F, pins, pose_weight=10.0, attraction=a).cleanup(E)
    assert np.array_equal(held[pins], E[pins])
    assert np.linalg.norm(held - E) < np.linalg.norm(plain - E)
    with pytest.raises(sm.Error, match="attraction"):
        sm.PinnedCleanup(V0, F, pins, pose_weight=1.0, attraction=a[:5])
    with pytest.raises(sm.Error, match="pose_weight"):
        sm.PinnedCleanup(V0, F, pins, pose_weight=-1.0)



def test_pinned_cleanup_warm_start_and_reset(capsule):
    """warm_start: frames cleaned in order start from the previous correction (fewer steps in all);
    the first frame and the first after reset() are bit for bit a fresh object's."""
    V0, F = capsule
    z = V0[:, 2]
    t = np.clip((z - 1.0) / 1.0, 0, 1)
    w = t * t * (3 - 2 * t)
    W = np.stack([1 - w, w], axis=1)
    pins = sm.pins_from_weights(V0, W, 0.999, 0.25)
    elbow = np.array([0, 0, 1.5])

    def frame(k):  # LBS, the elbow bent k * 6 degrees
        c, s_ = np.cos(np.radians(6 * k)), np.sin(np.radians(6 * k))
        R = np.array([[1, 0, 0], [0, c, -s_], [0, s_, c]])
        return W[:, :1] * V0 + W[:, 1:] * ((V0 - elbow) @ R.T + elbow)

    cold = sm.PinnedCleanup(V0, F, pins)
    warm = sm.PinnedCleanup(V0, F, pins, warm_start=True)
    steps_cold = steps_warm = 0
    for k in range(1, 16):
        rc, rw = cold.cleanup(frame(k), full=True), warm.cleanup(frame(k), full=True)
        if k == 1:
            assert np.array_equal(rc["V"], rw["V"])
        assert rw["pin_error"] == 0.0
        steps_cold += rc["iterations"]
        steps_warm += rw["iterations"]
    assert steps_warm < steps_cold, (steps_warm, steps_cold)
    warm.reset()
    assert np.array_equal(warm.cleanup(frame(8)), cold.cleanup(frame(8)))

def test_rig_bind_cleanup_is_the_cli_default(meshes_dir):
    import os
    rigs = os.path.join(os.path.dirname(meshes_dir), "rigs")
    if not os.path.isdir(rigs):
        pytest.skip("../shared/rigs not found")
    rig = sm.read_gltf(os.path.join(rigs, "CesiumMan.gltf"))
    E = rig.pose(1.0)
    cleanup = rig.bind_cleanup()
    assert len(cleanup.pins) == 62
    V = cleanup.cleanup(E)
    assert np.array_equal(V[cleanup.pins], E[cleanup.pins])
    rms = np.sqrt(((V - E) ** 2).sum(1).mean()) / diag(E)
    assert rms < 0.008  # measured 0.0052 (pins only: 0.041)
    a = sm.pin_attraction_from_weights(rig.weights)
    by_hand = sm.PinnedCleanup(rig.V, rig.F, cleanup.pins, pose_weight=10.0, attraction=a).cleanup(E)
    assert np.array_equal(by_hand, V)
    # A margin wider than the man pins nothing: the attraction alone anchors him (never an abort), and
    # without it he is kept as skinned.
    held = rig.bind_cleanup(margin=1e3)
    assert len(held.pins) == 0 and [p["status"] for p in held.pieces] == ["cleaned"]
    loose = rig.bind_cleanup(margin=1e3, pose_weight=0)
    assert [p["status"] for p in loose.pieces] == ["unanchored"]
    assert np.array_equal(loose.cleanup(E), E)
