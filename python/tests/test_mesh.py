"""Meshes: generators, I/O, check() and metrics() (known values), memory order and dtypes."""
import numpy as np
import pytest

import spinmotor as sm


def test_generators_counts():
    V, F = sm.icosphere(2)
    assert V.shape == (162, 3) and F.shape == (320, 3)
    assert V.dtype == np.float64 and F.dtype == np.int32
    np.testing.assert_allclose(np.linalg.norm(V, axis=1), 1.0, atol=1e-15)
    m = sm.capsule(0.5, 2.0, 10, 12)
    assert m.V.shape == (10 * 12 + 2, 3) and m.UV is not None and m.FUV.shape == m.F.shape
    assert sm.tube(1.0, 2.0, 5, 8).V.shape == (40, 3)
    assert sm.tube(1.0, 2.0, 5, 8, capped=True).V.shape == (42, 3)
    assert sm.torus(2.0, 0.5, 12, 8).F.shape == (2 * 12 * 8, 3)
    assert sm.grid((2.0, 1.0), (4, 3)).V.shape == (12, 3)
    assert sm.uv_sphere(4, 8).V.shape == (34, 3)
    assert sm.cross_bar(segments=8).V.shape[1] == 3
    with pytest.raises(sm.Error, match="level"):
        sm.icosphere(11)


def test_check_keys_and_values(sphere):
    r = sm.check(*sphere)
    keys = ["vertices", "faces", "edges", "components", "boundary_loops", "boundary_edges",
            "euler_characteristic", "genus", "non_manifold_edges", "non_manifold_vertices",
            "degenerate_faces", "duplicate_vertices", "unreferenced_vertices", "nonfinite_vertices",
            "inconsistent_orientation", "closed", "manifold", "ok", "first"]
    assert list(r.keys()) == keys
    assert (r["vertices"], r["faces"], r["edges"]) == (162, 320, 480)
    assert r["euler_characteristic"] == 2 and r["genus"] == 0 and r["ok"] and r["closed"]
    t = sm.check(*sm.tube(1.0, 2.0, 4, 8))
    assert t["boundary_loops"] == 2 and t["genus"] == 0 and t["first"]["boundary_edge"]


def test_check_reports_defects():
    V, F = sm.icosphere(1)
    V = V.copy()
    V[5] = np.nan
    F2 = np.vstack([F, F[:1, ::-1]])  # a repeated, flipped face: non-manifold edges
    r = sm.check(V, F2)
    assert r["nonfinite_vertices"] == 1 and r["first"]["nonfinite_vertex"] == 5
    assert r["non_manifold_edges"] == 3 and not r["ok"] and "defects" in r
    assert r["genus"] is None and r["genus_note"]


def test_metrics_identity(capsule):
    V, F = capsule
    m = sm.metrics(V, V, F)
    assert m["q_mean"] == pytest.approx(1.0, abs=1e-12)
    assert m["q_max"] == pytest.approx(1.0, abs=1e-12)
    assert m["rms"] == 0.0 and m["max"] == 0.0 and m["alignment"] == "none"
    assert m["willmore_rest"] == pytest.approx(m["willmore_deformed"])
    # a similarity keeps Q = 1 and, aligned, rms 0
    V2 = 2.0 * sm.Motor.from_rotation((1, 0, 0), 30).apply(V) + 1.0
    m2 = sm.metrics(V, V2, F, alignment="similarity", willmore=False)
    assert m2["q_mean"] == pytest.approx(1.0, abs=1e-9)
    assert m2["rms"] < 1e-12 and m2["area_scale"] == pytest.approx(4.0)
    assert "willmore_rest" not in m2
    with pytest.raises(sm.Error, match="one of: none, translation, rigid, similarity"):
        sm.metrics(V, V, F, alignment="affine")
    with pytest.raises(sm.Error, match="V1"):
        sm.metrics(V, V[:-1], F)


def test_io_round_trip(tmp_path, capsule):
    m = capsule
    for ext in ("obj", "off", "ply", "stl"):
        p = tmp_path / f"c.{ext}"
        sm.write_mesh(p, m.V, m.F, m.UV, m.FUV)
        r = sm.read_mesh(str(p))
        if ext == "stl":  # float32 corners, equal positions merged (the seam): only the faces count
            assert r.F.shape == m.F.shape and len(r.V) <= len(m.V)
        else:
            np.testing.assert_array_equal(r.V, m.V)
            np.testing.assert_array_equal(r.F, m.F)
        if ext == "obj":
            np.testing.assert_array_equal(r.UV, m.UV)
            np.testing.assert_array_equal(r.FUV, m.FUV)
        else:
            assert r.UV is None
    with pytest.raises(sm.Error, match="unsupported mesh format"):
        sm.write_mesh(tmp_path / "x.xyz", m.V, m.F)
    with pytest.raises(sm.Error, match="face 0"):
        sm.write_mesh(tmp_path / "bad.obj", m.V, np.array([[0, 1, 10**6]]))
    assert not (tmp_path / "bad.obj").exists()
    with pytest.raises(sm.Error):
        sm.read_mesh(tmp_path / "missing.obj")


def test_memory_order_and_dtypes(capsule):
    V, F = capsule
    ref = sm.check(V, F)
    assert sm.check(np.asfortranarray(V), np.asfortranarray(F)) == ref
    assert sm.check(V.astype(np.float32), F.astype(np.int64)) == sm.check(V.astype(np.float32).astype(float), F)
    assert sm.check(V.tolist(), F.tolist()) == ref
    Vt = V.T.copy().T  # a transposed view: Fortran strides
    assert sm.metrics(V, Vt, F)["rms"] == 0.0
    assert sm.metrics(V[::1], np.asfortranarray(V), F.astype(np.uint32))["q_mean"] == pytest.approx(1.0)


def test_shared_mesh(meshes_dir):
    import glob
    import os
    files = sorted(glob.glob(os.path.join(meshes_dir, "*.obj")))
    if not files:
        pytest.skip("no OBJ in the shared meshes")
    V, F = sm.read_mesh(files[0])
    r = sm.check(V, F)
    assert r["vertices"] == len(V) and r["faces"] == len(F)
