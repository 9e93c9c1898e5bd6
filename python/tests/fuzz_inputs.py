"""Random inputs for every entry point: each call must return or raise spinmotor.Error, never crash
and never raise anything else. Run as a script (test_fuzz.py runs it in a subprocess, so a crash is
a failed test rather than a dead pytest): python3 fuzz_inputs.py SEED COUNT."""
import os
import sys
import tempfile

import numpy as np

import spinmotor as sm

DTYPES = [np.float64, np.float32, np.int32, np.int64, np.uint8, np.uint64, bool, complex, object, "U3"]


def random_array(rng, base=None):
    """A random array: sometimes a perturbed valid one, sometimes any shape and dtype."""
    r = rng.random()
    if base is not None and r < 0.5:
        a = np.array(base, copy=True)
        if a.size and rng.random() < 0.5:
            idx = tuple(rng.integers(0, s) for s in a.shape)
            if a.dtype.kind == "f":
                a[idx] = rng.choice([np.nan, np.inf, -np.inf, 1e308, -0.0])
            else:
                a[idx] = rng.choice([-1, a.max() + 1, 2**31 - 1, -(2**31)])
        if rng.random() < 0.3:
            a = np.asfortranarray(a)
        if rng.random() < 0.2:
            a = a[: rng.integers(0, len(a) + 1)]
        return a
    ndim = int(rng.integers(0, 4))
    shape = tuple(int(rng.integers(0, 5)) for _ in range(ndim))
    dt = DTYPES[int(rng.integers(0, len(DTYPES)))]
    if dt in (object, "U3"):
        return np.full(shape, "x", dtype=dt)
    if dt is complex:
        return rng.normal(size=shape) + 1j
    if np.dtype(dt).kind in "iub":
        return rng.integers(-3, 8, size=shape).astype(dt)
    a = rng.normal(size=shape).astype(dt)
    if a.size and rng.random() < 0.3:
        a.flat[0] = np.nan
    return a


def main(seed, count):
    rng = np.random.default_rng(seed)
    V0, F0 = sm.icosphere(1)
    tmp = tempfile.mkdtemp()
    calls = [
        lambda V, F: sm.check(V, F),
        lambda V, F: sm.metrics(V, V, F),
        lambda V, F: sm.metrics(V0, V, F),
        lambda V, F: sm.write_mesh(os.path.join(tmp, "f.off"), V, F),
        lambda V, F: sm.Mesh(V, F),
        lambda V, F: sm.SurfaceHarmonicDeformer(V, F, handles=[("a", [0]), ("b", [11])]),
        lambda V, F: sm.ArapDeformer(V, F, handles={"a": [0], "b": [11]}).pose([sm.Motor()] * 2),
        lambda V, F: sm.FfdDeformer(V, lattice=(2, 2, 2)).pose([sm.Motor()] * 8),
        lambda V, F: sm.CageDeformer(V0 * 0.5, F0, cage=(V, F)),
        lambda V, F: sm.SkinDeformer(V, F, skeleton=[("a", -1, (0, 0, 0), (0, 0, 1))], weights=np.ones((len(V0), 1))),
        lambda V, F: sm.ConformalSnap(V0, F0).snap(V),
        lambda V, F: sm.ConformalSnap(V, F),
        lambda V, F: sm.SpinTransform(V0, F0).solve(V),
        lambda V, F: sm.dirac_spectrum(V, F, count=2),
        lambda V, F: sm.fair(V, F, steps=1, tau=0.5),
        lambda V, F: sm.Motor(V),
        lambda V, F: sm.Motor.exp(V),
        lambda V, F: sm.Motor().apply(V),
        lambda V, F: sm.blend([sm.Motor()] * 2, V),
        lambda V, F: sm.SurfaceHarmonicDeformer(V0, F0, handles=[("a", V), ("b", [5])]),
        lambda V, F: sm.ConformalSnap(V0, F0).snap(V, mode="shape", steps=1),
        lambda V, F: sm.ConformalSnap(V0, F0).snap(V0 * 1.1, pins=np.ravel(F)),
        lambda V, F: sm.SpinTransform(V, F, problem="generalized", scale="unit", ordering="amd"),
        lambda V, F: sm.write_gltf_morph_animation(os.path.join(tmp, "a.glb"), V0, F0, [V], [0.0]),
        lambda V, F: sm.write_gltf_morph_animation(os.path.join(tmp, "b.gltf"), V, F, np.stack([V0, V0]),
                                                   np.ravel(F)[:2]),
    ]
    outcomes = {"ok": 0, "error": 0}
    for k in range(count):
        V = random_array(rng, V0)
        F = random_array(rng, F0)
        call = calls[k % len(calls)]
        try:
            call(V, F)
            outcomes["ok"] += 1
        except sm.Error as e:
            assert e.kind in ("bad_input", "numerical") and str(e), "an Error without kind or message"
            outcomes["error"] += 1
        except Exception as e:  # anything else is a bug of the bindings
            print(f"call {k % len(calls)} raised {type(e).__name__}: {e}\n V {getattr(V, 'shape', None)} "
                  f"{getattr(V, 'dtype', None)}, F {getattr(F, 'shape', None)} {getattr(F, 'dtype', None)}")
            return 1
    print(outcomes)
    return 0


if __name__ == "__main__":
    sys.exit(main(int(sys.argv[1]), int(sys.argv[2])))
