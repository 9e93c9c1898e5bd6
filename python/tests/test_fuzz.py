"""Random arrays (shapes, dtypes, NaN/inf, out-of-range faces) into every entry point: spinmotor.Error
or success, never a crash (run in a subprocess: a segfault fails the test instead of killing pytest)."""
import os
import subprocess
import sys

import numpy as np
import pytest

import spinmotor as sm

HERE = os.path.dirname(os.path.abspath(__file__))


@pytest.mark.parametrize("seed", [1, 2])
def test_random_inputs_never_crash(seed):
    r = subprocess.run([sys.executable, os.path.join(HERE, "fuzz_inputs.py"), str(seed), "300"],
                       capture_output=True, text=True, timeout=120, env=dict(os.environ))
    assert r.returncode == 0, f"exit {r.returncode}\n{r.stdout}\n{r.stderr}"
    assert "'error'" in r.stdout


def test_error_type_and_kind(sphere):
    V, F = sphere
    assert issubclass(sm.Error, Exception)
    with pytest.raises(sm.Error) as e:
        sm.check(V[:, :2], F)
    assert e.value.kind == "bad_input" and "V: expected shape (n, 3), got (162, 2)" in str(e.value)
    with pytest.raises(sm.Error, match="face 3 has vertex index 162"):
        F2 = F.copy()
        F2[3, 1] = 162
        sm.metrics(V, V, F2)
    with pytest.raises(sm.Error, match="integer array, got dtype float64"):
        sm.check(V, F.astype(float))
    with pytest.raises(sm.Error, match="row 7, column 2 is not finite"):
        V2 = V.copy()
        V2[7, 2] = np.nan
        sm.metrics(V2, V, F)
    with pytest.raises(sm.Error, match="got None"):
        sm.check(None, F)
    with pytest.raises(sm.Error, match="32-bit"):
        sm.check(V, F.astype(np.int64) + 2**40)


def test_error_pickles_with_its_kind():
    """dask ships worker exceptions pickled: spinmotor.Error keeps its class, message and kind."""
    import pickle
    with pytest.raises(sm.Error) as e:
        sm.icosphere(99)
    back = pickle.loads(pickle.dumps(e.value))
    assert type(back) is sm.Error and back.kind == "bad_input" and "level" in str(back)
