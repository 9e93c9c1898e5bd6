"""examples/python/pose_and_snap.py runs and its snap lowers Q."""
import os
import re
import subprocess
import sys

import spinmotor as sm

SOURCE = os.environ.get("SPINMOTOR_SOURCE_DIR",
                        os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


def test_pose_and_snap(tmp_path):
    out = tmp_path / "snapped.obj"
    example = os.path.join(SOURCE, "examples", "python", "pose_and_snap.py")
    V, F = sm.capsule(0.5, 3.0, 20, 16)
    sm.write_mesh(tmp_path / "capsule.obj", V, F)
    r = subprocess.run([sys.executable, example, str(tmp_path / "capsule.obj"), str(out)],
                       capture_output=True, text=True, timeout=60, env=dict(os.environ))
    assert r.returncode == 0, r.stdout + r.stderr
    q = [float(x) for x in re.findall(r"\d+\.\d+", r.stdout)]
    assert len(q) == 2 and 1.0 <= q[1] < q[0]
    V2, F2 = sm.read_mesh(out)
    assert V2.shape == V.shape and (F2 == F).all()
