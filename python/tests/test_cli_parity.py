"""check() and metrics() return what `spinmotor check --json` / `spinmotor metrics --json` print (the
CLI binary from SPINMOTOR_CLI, set by CTest; skipped without it)."""
import json
import os
import subprocess

import numpy as np
import pytest

import spinmotor as sm

CLI = os.environ.get("SPINMOTOR_CLI", "")
pytestmark = pytest.mark.skipif(not os.path.isfile(CLI), reason="SPINMOTOR_CLI (the spinmotor binary) not set")


def run(*args):
    r = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, timeout=60)
    return r.returncode, r.stdout


def test_check_matches_the_cli(tmp_path):
    V, F = sm.torus(2.0, 0.6, 16, 8)
    F = np.vstack([F, F[:1, ::-1]])  # a defect, so that "first" and "defects" are present
    p = tmp_path / "t.obj"
    sm.write_mesh(p, V, F)
    rc, out = run("check", p, "--json")
    cli = json.loads(out)
    assert rc == 2 and cli.pop("file") == str(p)
    assert sm.check(V, F) == cli  # same keys, same order, same values


def test_metrics_match_the_cli(tmp_path):
    V, F = sm.capsule(0.5, 2.0, 12, 10)
    V1 = sm.Motor.from_rotation((1, 0, 0), 30, about=(0, 0, 2)).apply(V) * [1.0, 1.2, 1.0]
    sm.write_mesh(tmp_path / "a.obj", V, F)
    sm.write_mesh(tmp_path / "b.obj", V1, F)
    rc, out = run("metrics", tmp_path / "a.obj", tmp_path / "b.obj", "--json")
    assert rc == 0, out
    cli = json.loads(out)
    mine = sm.metrics(V, V1, F)
    assert set(mine) <= set(cli), set(mine) - set(cli)
    for k, v in mine.items():
        assert cli[k] == pytest.approx(v, rel=1e-12, abs=1e-15) if isinstance(v, float) else cli[k] == v, k


# ---- snaps and poses: the CLI's output mesh and the Python call on the same inputs ----------------------
# OBJ numbers are written in the shortest form that reads back to the same double (mesh/io.hpp), so the
# CLI reads exactly the arrays Python wrote and its output reads back exactly as computed: the two
# computations are compared, not two roundings of them.


def diag(V):
    return float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))


def twisted_sausage(tmp_path):
    """The capsule (sausage) with its tip turned 90 degrees about its axis and bent 30 degrees (surface
    harmonic deformer), both written as OBJ."""
    V, F = sm.capsule(0.5, 3.0, 24, 16)
    handles = [("base", np.flatnonzero(V[:, 2] < -0.2)), ("tip", np.flatnonzero(V[:, 2] > 3.2))]
    d = sm.SurfaceHarmonicDeformer(V, F, handles=handles)
    tip = sm.Motor.from_rotation((1, 0, 0), 30, about=(0, 0, 2.5)) * sm.Motor.from_rotation((0, 0, 1), 90)
    E = d.pose([sm.Motor(), tip])
    sm.write_mesh(tmp_path / "rest.obj", V, F)
    sm.write_mesh(tmp_path / "edit.obj", E, F)
    return V, F, E, handles


def snap_cli(tmp_path, *options):
    out = tmp_path / "cli.obj"
    rc, text = run("snap", tmp_path / "rest.obj", tmp_path / "edit.obj", "--out", out, "--json", *options)
    assert rc == 0, text
    return sm.read_mesh(out)[0], json.loads(text)


def test_snap_free_matches_the_cli(tmp_path):
    V, F, E, _ = twisted_sausage(tmp_path)
    cli, j = snap_cli(tmp_path)
    mine = sm.ConformalSnap(V, F).snap(E)
    assert np.abs(mine - cli).max() <= 1e-12 * diag(E)
    # the figure: the same Q_mean as `spinmotor snap` to 1e-12
    assert sm.metrics(V, mine, F)["q_mean"] == pytest.approx(j["q_mean_after"], rel=1e-12)
    assert sm.metrics(V, E, F)["q_mean"] == pytest.approx(j["q_mean_before"], rel=1e-12)
    assert j["q_mean_after"] < j["q_mean_before"]  # the snap does something measurable
    # options through the same tables: tradeoff, alignment
    cli, j = snap_cli(tmp_path, "--tradeoff", "0.5", "--align", "translation", "--smooth-rho", "2")
    snap = sm.ConformalSnap(V, F, alignment="translation", rho_smoothing=2)
    mine = snap.snap(E, tradeoff=0.5)
    assert np.abs(mine - cli).max() <= 1e-12 * diag(E)
    assert j["align"] == "translation" and j["tradeoff"] == 0.5


def test_snap_shape_matches_the_cli(tmp_path):
    V, F, E, _ = twisted_sausage(tmp_path)
    cli, j = snap_cli(tmp_path, "--mode", "shape", "--steps", "2", "--area-constraint", "0.5")
    r = sm.ConformalSnap(V, F).snap(E, mode="shape", steps=2, area_constraint=0.5, full=True)
    assert np.abs(r["V"] - cli).max() <= 1e-12 * diag(E)
    assert sm.metrics(V, r["V"], F)["q_mean"] == pytest.approx(j["q_mean_after"], rel=1e-12)
    assert list(r["closure"]) == pytest.approx(j["closure"], rel=1e-12, abs=1e-15)


def test_snap_pinned_matches_the_cli(tmp_path):
    V, F, E, handles = twisted_sausage(tmp_path)
    pins = np.concatenate([ix for _, ix in handles])
    pin_file = tmp_path / "pins.txt"
    pin_file.write_text("# base and tip caps\n" + "\n".join(map(str, pins[::-1])) + "\n")
    snap = sm.ConformalSnap(V, F)
    for options, keep in (((), None), (("--keep", "area"), "area")):
        cli, j = snap_cli(tmp_path, "--pin", pin_file, *options)  # --pin alone selects mode pinned
        r = snap.snap(E, pins=pins, keep=keep, full=True)
        assert np.abs(r["V"] - cli).max() <= 1e-12 * diag(E), options
        assert np.array_equal(r["V"][pins], E[pins]) and np.array_equal(cli[pins], E[pins])
        assert r["keep"] == j["keep"] == (keep or "volume")
        assert r["iterations"] == j["iterations"]
        assert r["measure_ratio"] == pytest.approx(j["measure_ratio_after"], rel=1e-12)
        assert sm.metrics(V, r["V"], F)["q_mean"] == pytest.approx(j["q_mean_after"], rel=1e-12)
    # the explicit mode gives the same as the implied one
    assert np.array_equal(snap.snap(E, mode="pinned", pins=pins, keep="area"), r["V"])


def test_scene_pose_and_pinned_snap_match_the_cli(tmp_path):
    """`spinmotor deform scene.json` (surface-harmonic, cotan weights, pivot-log blend, two frames, the
    pinned snap) against the deformer and ConformalSnap called from Python on the same arrays."""
    V, F = sm.capsule(0.5, 3.0, 24, 16)
    sm.write_mesh(tmp_path / "rest.obj", V, F)
    base, tip = np.flatnonzero(V[:, 2] < -0.2), np.flatnonzero(V[:, 2] > 3.2)
    poses = [dict(axis=[1, 0, 0], degrees=50.0, about=[0, 0, 2.5], translate=[0, 0.2, 0]),
             dict(axis=[0, 1, 1], degrees=-35.0, about=[0, 0, 2.0], translate=[0.1, 0, -0.3])]
    scene = {
        "mesh": "rest.obj",
        "handles": [{"name": "base", "select": {"vertices": base.tolist()}},
                    {"name": "tip", "select": {"vertices": tip.tolist()}}],
        "deformer": {"type": "surface-harmonic", "weights": "cotan", "blend": "pivot-log"},
        "frames": [{"tip": {"rotate": {k: p[k] for k in ("axis", "degrees", "about")},
                            "translate": p["translate"]}} for p in poses],
        "output": {"mesh": "out/posed.obj"},
    }
    (tmp_path / "pose.json").write_text(json.dumps(scene))
    scene["snap"] = {"mode": "pinned", "keep": "volume"}
    scene["output"] = {"mesh": "out/snapped.obj"}
    (tmp_path / "snap.json").write_text(json.dumps(scene))
    for name in ("pose.json", "snap.json"):
        rc, text = run("deform", tmp_path / name)
        assert rc == 0, text
    d = sm.SurfaceHarmonicDeformer(V, F, handles=[("base", base), ("tip", tip)], weights="cotan",
                                   blend="pivot-log")
    snap = sm.ConformalSnap(V, F)
    pins = np.concatenate([base, tip])
    for k, p in enumerate(poses):
        m = sm.Motor.from_rotation(p["axis"], p["degrees"], about=p["about"], translate=p["translate"])
        E = d.pose([sm.Motor(), m])
        posed = sm.read_mesh(tmp_path / "out" / f"posed.{k:04d}.obj")[0]
        assert np.abs(E - posed).max() <= 1e-12 * diag(E), k
        snapped = sm.read_mesh(tmp_path / "out" / f"snapped.{k:04d}.obj")[0]
        mine = snap.snap(E, pins=pins, keep="volume")
        assert np.abs(mine - snapped).max() <= 1e-12 * diag(E), k
        assert np.abs(mine - E).max() > 1e-3 * diag(E)  # the snap moved the free vertices


def test_rig_pose_matches_the_cli(tmp_path, rigs_dir):
    """`spinmotor rig pose --time T` (dlb; and lbs with --cleanup pinned, --space scene, --pose-weight)
    against Rig.pose / Rig.poser on CesiumMan."""
    path = os.path.join(rigs_dir, "CesiumMan.gltf")
    rig = sm.read_gltf(path)
    _, start, end = rig.animations[0]
    t = start + 0.37 * (end - start)
    rc, text = run("rig", "pose", path, "--time", repr(t), "--blend", "dlb", "--out", tmp_path / "dlb.obj")
    assert rc == 0, text
    cli = sm.read_mesh(tmp_path / "dlb.obj")[0]
    mine = rig.pose(t, blend="dlb")  # both in the file's scene coordinates
    assert np.abs(mine - cli).max() <= 1e-12 * diag(mine)
    assert np.array_equal(rig.poser(blend="dlb").pose(t), mine)
    for gamma in (None, 3.0):  # the default pose attraction (scene/rig_cleanup.hpp) and another one
        extra = () if gamma is None else ("--pose-weight", repr(gamma))
        rc, text = run("rig", "pose", path, "--time", repr(t), "--cleanup", "pinned", "--space", "scene",
                       *extra, "--out", tmp_path / "clean.obj")
        assert rc == 0, text
        cli = sm.read_mesh(tmp_path / "clean.obj")[0]
        poser = rig.poser(cleanup="pinned", space="scene", **({} if gamma is None else {"pose_weight": gamma}))
        mine = poser.pose(t)
        assert np.abs(mine - cli).max() <= 1e-12 * diag(mine), gamma
        assert len(poser.pins) > 0
