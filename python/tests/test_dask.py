"""The dask example: fair + extrude over a folder of 2 generated meshes on a LocalCluster."""
import os
import subprocess
import sys

import pytest

import spinmotor as sm

distributed = pytest.importorskip("distributed", reason="dask.distributed is not installed")
SOURCE = os.environ.get("SPINMOTOR_SOURCE_DIR",
                        os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
EXAMPLE = os.path.join(SOURCE, "examples", "python", "batch_fair_dask.py")


@pytest.mark.dask
def test_batch_fair_dask(tmp_path):
    if not os.path.exists(EXAMPLE):
        pytest.skip("examples/python/batch_fair_dask.py not found")
    src = tmp_path / "in"
    src.mkdir()
    for i, stretch in enumerate([1.3, 1.6]):
        V, F = sm.icosphere(2)
        sm.write_mesh(src / f"ellipsoid{i}.obj", V * [1.0, 1.0, stretch], F)
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, EXAMPLE, str(src), str(out), "--steps", "3"],
                       capture_output=True, text=True, timeout=180, env=dict(os.environ))
    assert r.returncode == 0, r.stdout + r.stderr
    for i in range(2):
        faired = sm.read_mesh(out / f"ellipsoid{i}.faired.obj")
        back = sm.read_mesh(out / f"ellipsoid{i}.extruded.obj")
        assert faired.V.shape == (162, 3) and back.V.shape == (162, 3)
    assert "ellipsoid1" in r.stdout
