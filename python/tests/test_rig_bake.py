"""Baking rigs and deformation sequences to glTF morph-target animations and reading them back
(scene/rig_pose.hpp, mesh/gltf.hpp): the same frames as the poser and the CLI's `rig pose --out x.glb`,
to float32 precision. The rig is a two-joint capsule written here as a skinned glTF (no shared data
needed); CesiumMan is used too when ../shared/rigs is present."""
import base64
import json
import os
import subprocess

import numpy as np
import pytest

import spinmotor as sm

CLI = os.environ.get("SPINMOTOR_CLI", "")
F32 = 1e-6  # positions are stored as float32: relative rounding 6e-8, with margin


def diag(V):
    return float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))


def quat_x(degrees):
    a = np.radians(degrees) / 2
    return [np.sin(a), 0.0, 0.0, np.cos(a)]  # glTF order x, y, z, w


def write_bent_capsule(path):
    """A capsule along z (0..2) skinned to two joints, hip at the origin and knee at z = 1 (weights
    blend over z in [0.7, 1.3]), under a root node translated by (1, 2, 3); one animation "bend" turns
    the knee 0, 45, 90 degrees about x at t = 0, 0.5, 1 (LINEAR)."""
    V, F = sm.capsule(0.3, 2.0, 16, 10)
    P = V.astype(np.float32)
    t = np.clip((P[:, 2].astype(np.float64) - 0.7) / 0.6, 0.0, 1.0)
    w1 = (t * t * (3 - 2 * t)).astype(np.float32)
    W = np.zeros((len(P), 4), np.float32)
    W[:, 0], W[:, 1] = 1 - w1, w1
    J = np.zeros((len(P), 4), np.uint16)
    J[:, 1] = 1
    ibm = np.stack([np.eye(4), np.eye(4)]).astype(np.float32)
    ibm[1][2, 3] = -1.0  # inverse of the knee's rest translation
    ibm = np.ascontiguousarray(ibm.transpose(0, 2, 1))  # glTF matrices are column-major
    times = np.array([0.0, 0.5, 1.0], np.float32)
    rots = np.array([quat_x(0), quat_x(45), quat_x(90)], np.float32)
    idx = F.astype(np.uint32)
    chunks, views, accessors = [], [], []

    def add(arr, type_, ctype, target=None, minmax=False):
        offset = sum(len(c) for c in chunks)
        data = np.ascontiguousarray(arr).tobytes()
        chunks.append(data + b"\0" * (-len(data) % 4))
        view = {"buffer": 0, "byteOffset": offset, "byteLength": len(data)}
        if target:
            view["target"] = target
        views.append(view)
        acc = {"bufferView": len(views) - 1, "componentType": ctype, "type": type_,
               "count": int(arr.shape[0] if type_ != "SCALAR" else arr.size)}
        if minmax:
            acc["min"], acc["max"] = arr.min(axis=0).tolist(), arr.max(axis=0).tolist()
        accessors.append(acc)
        return len(accessors) - 1

    pos = add(P, "VEC3", 5126, 34962, minmax=True)
    joints = add(J, "VEC4", 5123, 34962)
    weights = add(W, "VEC4", 5126, 34962)
    indices = add(idx.reshape(-1), "SCALAR", 5125, 34963)
    inv = add(ibm.reshape(2, 16), "MAT4", 5126)
    tin = add(times, "SCALAR", 5126, minmax=False)
    accessors[tin]["min"], accessors[tin]["max"] = [0.0], [1.0]
    rout = add(rots, "VEC4", 5126)
    buf = b"".join(chunks)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "root", "translation": [1, 2, 3], "children": [1, 2]},
                  {"name": "body", "mesh": 0, "skin": 0},
                  {"name": "hip", "children": [3]},
                  {"name": "knee", "translation": [0, 0, 1]}],
        "meshes": [{"name": "capsule", "primitives": [{"attributes": {"POSITION": pos, "JOINTS_0": joints,
                                                                      "WEIGHTS_0": weights},
                                                       "indices": indices}]}],
        "skins": [{"joints": [2, 3], "inverseBindMatrices": inv}],
        "animations": [{"name": "bend", "samplers": [{"input": tin, "output": rout, "interpolation": "LINEAR"}],
                        "channels": [{"sampler": 0, "target": {"node": 3, "path": "rotation"}}]}],
        "buffers": [{"byteLength": len(buf),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
        "bufferViews": views,
        "accessors": accessors,
    }
    with open(path, "w") as f:
        json.dump(doc, f)
    return P.astype(np.float64), F


@pytest.fixture
def bent(tmp_path):
    path = tmp_path / "bent.gltf"
    P, F = write_bent_capsule(path)
    return path, P, F


def test_bake_reads_back_to_float32(tmp_path, bent):
    path, P, F = bent
    rig = sm.read_gltf(path)
    assert np.array_equal(rig.V_file, P) and np.array_equal(rig.F, F)
    np.testing.assert_allclose(rig.V, P + [1, 2, 3], rtol=0, atol=1e-15)  # the scene: the root's translation
    assert rig.animations == [("bend", 0.0, 1.0)]
    assert [p["name"] for p in rig.pieces] == ["body"]
    out = rig.bake(tmp_path / "baked.glb", frames=5, blend="dlb", space="mesh")
    assert out["times"] == [0.0, 0.25, 0.5, 0.75, 1.0]
    back = sm.read_gltf_morph_animation(tmp_path / "baked.glb")
    assert back["name"] == "body" and back["times"] == out["times"]  # one mesh per piece
    assert np.array_equal(back["F"], F) and np.array_equal(back["V"], P)  # rest: float32 exactly
    expected = np.eye(4)
    expected[:3, 3] = [1, 2, 3]  # space "mesh": the bind matrix on the root node
    assert np.array_equal(back["node_matrix"], expected)
    frames = back["frames"]
    assert frames.shape == (5, len(P), 3)
    d = diag(P)
    assert np.abs(frames - out["frames"]).max() <= F32 * d
    poser = rig.poser(blend="dlb", space="mesh")
    for k, t in enumerate(out["times"]):
        assert np.array_equal(out["frames"][k], poser.pose(t))  # the baker poses with the poser
    # independent figure: the knee's end (z = 2.3 at rest, 1.3 above the knee) turns 90 deg about x at
    # the knee, to (y, z) = (-1.3, 1) (rigid part: weight 1 on the knee)
    top = np.argmax(P[:, 2])
    assert frames[-1][top] == pytest.approx([P[top, 0], -(P[top, 2] - 1.0), 1.0], abs=F32 * d)
    assert np.abs(frames[0] - P).max() <= F32 * d  # t = 0: the rest pose


def test_bake_in_scene_space_with_cleanup_and_times(tmp_path, bent):
    path, P, F = bent
    rig = sm.read_gltf(path)
    times = [0.1, 0.6, 0.9]
    out = rig.bake(tmp_path / "clean.gltf", times=times, cleanup="pinned", space="scene", name="walk")
    back = sm.read_gltf_morph_animation(tmp_path / "clean.gltf")
    assert back["name"] == "body" and back["times"] == pytest.approx(times, rel=F32)
    assert np.array_equal(back["node_matrix"], np.eye(4))  # scene coordinates: nothing to place
    poser = rig.poser(cleanup="pinned", warm_start=True)  # scene space, as the bake
    cold = rig.bake(tmp_path / "cold.gltf", times=times, cleanup="pinned", warm_start=False)
    cold_poser = rig.poser(cleanup="pinned")
    assert 0 < len(poser.pins) < len(P)
    for k, t in enumerate(times):
        mine = poser.pose(t)  # in the bake's order: the same warm start
        assert np.array_equal(out["frames"][k], mine)
        assert np.array_equal(cold["frames"][k], cold_poser.pose(t))
        if k == 0:
            assert np.array_equal(cold["frames"][k], mine)  # nothing to carry yet
        assert np.abs(back["frames"][k] - mine).max() <= F32 * diag(P)
        assert np.array_equal(mine[poser.pins], rig.pose(t)[poser.pins])  # pins stay where the skin put them
    # mesh space positions are the scene ones moved back by the bind matrix (a fresh poser: cold)
    np.testing.assert_allclose(rig.poser(cleanup="pinned", space="mesh").pose(0.6) + [1, 2, 3],
                               cold["frames"][1], rtol=0, atol=1e-12)


@pytest.mark.skipif(not os.path.isfile(CLI), reason="SPINMOTOR_CLI (the spinmotor binary) not set")
def test_bake_matches_the_cli(tmp_path, bent):
    path, P, F = bent
    r = subprocess.run([CLI, "rig", "pose", str(path), "--frames", "4", "--blend", "pivot-log", "--space",
                        "mesh", "--out", str(tmp_path / "cli.glb")], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stdout + r.stderr
    sm.read_gltf(path).bake(tmp_path / "py.glb", frames=4, blend="pivot-log", space="mesh", name="cli")
    a = sm.read_gltf_morph_animation(tmp_path / "cli.glb")
    b = sm.read_gltf_morph_animation(tmp_path / "py.glb")
    for k in ("V", "F", "frames", "node_matrix"):
        assert np.array_equal(a[k], b[k]), k
    assert a["times"] == b["times"] and a["pieces"] == b["pieces"]


def test_bake_cesium_man(tmp_path, rigs_dir):
    rig = sm.read_gltf(os.path.join(rigs_dir, "CesiumMan.gltf"))
    out = rig.bake(tmp_path / "man.glb", frames=3, blend="dlb", space="mesh")
    back = sm.read_gltf_morph_animation(tmp_path / "man.glb")
    d = diag(rig.V)
    assert np.array_equal(back["F"], rig.F) and np.array_equal(back["V"], rig.V_file)
    assert np.abs(back["frames"] - out["frames"]).max() <= F32 * d
    np.testing.assert_allclose(back["UV"][back["FUV"]], rig.UV[rig.FUV], atol=1e-7)  # per corner


def test_write_a_deformer_sequence_with_uvs(tmp_path):
    mesh = sm.capsule(0.5, 3.0, 12, 10)
    V, F = mesh
    assert mesh.UV is not None
    d = sm.SurfaceHarmonicDeformer(V, F, handles=[("base", np.flatnonzero(V[:, 2] < -0.2)),
                                                  ("tip", np.flatnonzero(V[:, 2] > 3.2))])
    frames = [d.pose([sm.Motor(), sm.Motor.from_rotation((1, 0, 0), a, about=(0, 0, 2.5))])
              for a in (0, 30, 60)]
    sm.write_gltf_morph_animation(tmp_path / "seq.glb", V, F, np.stack(frames), [0, 1 / 24, 2 / 24],
                                  UV=mesh.UV, FUV=mesh.FUV)
    back = sm.read_gltf_morph_animation(tmp_path / "seq.glb")
    assert np.array_equal(back["F"], F)  # vertex order kept through the UV seams
    assert np.array_equal(back["V"], V.astype(np.float32).astype(np.float64))
    assert np.abs(back["frames"] - np.stack(frames)).max() <= F32 * diag(V)
    np.testing.assert_allclose(back["UV"][back["FUV"]], mesh.UV[mesh.FUV], atol=1e-7)
    assert back["times"] == pytest.approx([0, 1 / 24, 2 / 24], rel=F32)


def test_bake_errors_write_nothing(tmp_path, bent):
    path, P, F = bent
    rig = sm.read_gltf(path)
    out = tmp_path / "x.glb"
    cases = [
        (dict(), "exactly one of frames"),
        (dict(frames=3, times=[0, 1]), "exactly one of frames"),
        (dict(times=[0.5, 0.5]), "not after the previous"),
        (dict(frames=3, blend="cubic"), "one of: lbs, dlb, log, pivot-log"),
        (dict(frames=3, cleanup="smooth"), "one of: none, pinned"),
        (dict(frames=3, space="world"), "one of: mesh, scene"),
        (dict(frames=3, animation=1), "out of range"),
        (dict(frames=3, cleanup="pinned", pin_threshold=0.2), "outside [0.5, 1]"),
        (dict(frames=3, cleanup="pinned", pose_weight=-1.0), "pose weight must be a finite number"),
        (dict(frames=3, mode="sideways"), "frames or correctives"),
    ]
    for kwargs, message in cases:
        with pytest.raises(sm.Error, match=message.replace("[", r"\[").replace("(", r"\(")):
            rig.bake(out, **kwargs)
        assert not out.exists(), kwargs
    with pytest.raises(sm.Error, match="glTF"):
        rig.bake(tmp_path / "x.obj", frames=2)
    with pytest.raises(sm.Error, match="no mesh with morph targets"):
        sm.read_gltf_morph_animation(path)  # a rig, not a baked animation
    rig.bake(out, frames=2)
    with pytest.raises(sm.Error, match="no skinned mesh"):
        sm.read_gltf(out)
    with pytest.raises(sm.Error, match="frames"):
        sm.write_gltf_morph_animation(tmp_path / "y.glb", P, F, [P, P[:-1]], [0, 1])
    with pytest.raises(sm.Error, match="UV and FUV"):
        sm.write_gltf_morph_animation(tmp_path / "y.glb", P, F, [P], [0], UV=np.zeros((3, 2)))
    assert not (tmp_path / "y.glb").exists()
