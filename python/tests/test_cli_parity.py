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
