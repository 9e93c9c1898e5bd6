#!/usr/bin/env python3
"""bench/python_overhead.py — what the Python module adds to the C++ calls it wraps (issue 18's bench:
the overhead of pose on 1M vertices, of the snap on spot, and of the pose-keeping cleanup).

    PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py [--quick] [--rounds N]
                                                                      [--meshes DIR] [--json FILE]

For each case, two timings of the same bound object on the same inputs, interleaved round by round:
  python  time.perf_counter() around the Python call: argument conversion (numpy -> Eigen, with the
          finiteness checks), the C++ call, the result copied into a new numpy array;
  c++     the C++ call alone, timed inside the module (private _time_* hooks: inputs converted once, the
          output matrix reused across calls, as a C++ caller poses frame after frame).
Reported: the medians, overhead = python / c++ - 1 of the medians and of the minima (the least
disturbed calls). --quick: the smallest sizes, 3 rounds. The machine is shared: compare the columns of
one run, not runs with each other; on a loaded machine OMP_NUM_THREADS=1 steadies the figures (threads
waiting for a core otherwise quantise the times to scheduler slices).
"""
import argparse
import json
import os
import statistics
import sys
import time

import numpy as np

import spinmotor as sm


def capsule_arm(vertices):
    """A capsule along z (radius 1, length 6) with about `vertices` vertices (rings:sides = 3:2)."""
    sides = max(8, int(round((vertices / 1.5) ** 0.5)))
    rings = max(4, int(round(vertices / sides)))
    return sm.capsule(1.0, 6.0, rings, sides)


def two_bones(V):
    bones = [{"name": "upper", "head": (0, 0, 0), "tail": (0, 0, 3)},
             {"name": "lower", "parent": 0, "head": (0, 0, 3), "tail": (0, 0, 6)}]
    t = np.clip((V[:, 2] - 2.5) / 1.0, 0.0, 1.0)
    return bones, np.stack([1.0 - t, t], axis=1)


def bend(degrees):
    return sm.Motor.from_rotation((1, 0, 0), degrees, about=(0, 0, 3))


def measure(py_call, cpp_call, rounds):
    py_call()  # warm-up (first-touch of buffers, thread pools)
    cpp_call()
    py, cpp = [], []
    for _ in range(rounds):
        t0 = time.perf_counter()
        py_call()
        py.append(1e3 * (time.perf_counter() - t0))
        cpp.append(cpp_call()[0])
    return statistics.median(py), statistics.median(cpp), min(py), min(cpp)


def cases(quick, meshes):
    sizes = [10_000, 100_000] if quick else [10_000, 100_000, 1_000_000]
    for n in sizes:
        V, F = capsule_arm(n)
        bones, W = two_bones(V)
        for blend in ("lbs", "dlb"):
            d = sm.SkinDeformer(V, F, skeleton=bones, weights=W, blend=blend)
            motors = [sm.Motor(), bend(60)]
            yield (f"SkinDeformer.pose ({blend})", len(V), lambda d=d, m=motors: d.pose(m),
                   lambda d=d, m=motors: d._time_pose(m, 1))
    V, F = capsule_arm(10_000 if quick else 100_000)
    handles = [("base", np.flatnonzero(V[:, 2] < -0.5)), ("tip", np.flatnonzero(V[:, 2] > 6.5))]
    d = sm.SurfaceHarmonicDeformer(V, F, handles=handles)
    motors = [sm.Motor(), bend(60)]
    yield ("SurfaceHarmonicDeformer.pose (log)", len(V), lambda: d.pose(motors), lambda: d._time_pose(motors, 1))
    V, F = capsule_arm(10_000)
    bones, W = two_bones(V)
    E = sm.SkinDeformer(V, F, skeleton=bones, weights=W, blend="lbs").pose([sm.Motor(), bend(90)])
    c = sm.PinnedCleanup(V, F, sm.pins_from_weights(V, W, 0.999, 0.5))
    yield ("PinnedCleanup.cleanup (bend 90)", len(V), lambda: c.cleanup(E), lambda: c._time_cleanup(E, 1))
    spot = os.path.join(meshes, "spot.obj") if meshes else ""
    if spot and os.path.isfile(spot):
        V, F = sm.read_mesh(spot)
        E = V * [1.0, 1.0, 1.3]
        s = sm.ConformalSnap(V, F)
        yield ("ConformalSnap.snap (spot)", len(V), lambda: s.snap(E), lambda: s._time_snap(E, 1))
    else:
        print("(spot.obj not found: no snap case; pass --meshes ../shared/meshes)", file=sys.stderr)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--rounds", type=int, default=0)
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--meshes", default=os.environ.get("SPINMOTOR_MESHES_DIR",
                                                       os.path.join(here, "..", "..", "shared", "meshes")))
    ap.add_argument("--json", default="")
    a = ap.parse_args()
    rounds = a.rounds or (3 if a.quick else 15)
    rows = []
    print(f"{'case':38} {'vertices':>9} {'python ms':>10} {'c++ ms':>9} {'overhead':>9} {'(minima)':>9}")
    for name, n, py_call, cpp_call in cases(a.quick, a.meshes):
        r = rounds if "pose" in name else max(3, rounds // 3)
        py, cpp, py_min, cpp_min = measure(py_call, cpp_call, r)
        rows.append({"case": name, "vertices": n, "python_ms": py, "cpp_ms": cpp, "overhead": py / cpp - 1,
                     "python_min_ms": py_min, "cpp_min_ms": cpp_min, "overhead_min": py_min / cpp_min - 1,
                     "rounds": r, "omp_num_threads": os.environ.get("OMP_NUM_THREADS", "")})
        print(f"{name:38} {n:>9} {py:>10.3f} {cpp:>9.3f} {100 * (py / cpp - 1):>8.1f}% "
              f"{100 * (py_min / cpp_min - 1):>8.1f}%", flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "rows": rows}, f, indent=2)


if __name__ == "__main__":
    main()
