#!/usr/bin/env python3
"""bench/longrun_rss.py — resident memory and speed of long animations (issue 19).

    bench/longrun_rss.py [--build DIR] [--cli PATH] [--viewer PATH] [--frames 100,1000,10000]
                         [--work DIR] [--json FILE]

Plays the "twist" animation of the project's procedural limb (`spinmotor demo`'s limb-rig.glb: 1,538
vertices, 3 joints) for each frame count N through
  deform   `spinmotor deform SCENE --out-dir DIR -q`, SCENE a rig scene with "frames": N and the skin
           deformer (LBS): N frames, each measured and written as a metrics JSON (no mesh: 10,000 OBJs
           of the limb would be 1.3 GB);
  viewer   `spinmotor-viewer limb-rig.glb --screenshot X.png --size 64x64 --animation twist --frames N`:
           N frames posed, uploaded and drawn (offscreen when there is no display), one picture at the end;
and prints, per tool, the resident memory at frame N and the frames per second of the longest run.

"RSS at frame N" is the peak resident set of a run of N frames (ru_maxrss from wait4, the VmHWM of
/proc/<pid>/status): a run of 10,000 frames passes through the state of a run of 100, so the curve over
N is the high-water mark of one long run sampled at those frames, without relying on the tool to report
progress. Both tools read the same input whatever N (a rig scene's "frames": N is one number; the scene
still holds one small pose, a time, per frame). Frames per second are N / wall time of the largest N,
process start, reading the rig and the bind included. Memory that grows by a constant per frame shows
as a slope (the column kB / frame, between the smallest and the largest N).
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time


def write_scene(work, rig, n):
    """A rig scene of n frames of the limb's twist, metrics only."""
    doc = {"rig": {"gltf": rig, "animation": "twist", "frames": n},
           "deformer": {"type": "skin", "blend": "lbs"},
           "output": {"metrics": "out/limb.json"}}
    path = os.path.join(work, f"limb-{n}.json")
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def run(cmd, env):
    """Runs cmd; returns (exit code, wall seconds, peak RSS in kB)."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    err = p.stderr.read()
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: exit {p.returncode}\n{err.decode(errors='replace')[-2000:]}")
    return p.returncode, wall, usage.ru_maxrss  # kB on Linux


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--build", default=os.path.join(root, "build"), help="build directory (default ./build)")
    ap.add_argument("--cli", help="the spinmotor executable (default BUILD/bin/spinmotor)")
    ap.add_argument("--viewer", help="the spinmotor-viewer executable (default BUILD/bin/spinmotor-viewer)")
    ap.add_argument("--frames", default="100,1000,10000", help="comma-separated frame counts")
    ap.add_argument("--work", help="scratch folder (default: a temporary one, removed at the end)")
    ap.add_argument("--json", help="also write the figures to this JSON file")
    a = ap.parse_args()
    cli = a.cli or os.path.join(a.build, "bin", "spinmotor")
    viewer = a.viewer or os.path.join(a.build, "bin", "spinmotor-viewer")
    counts = sorted(int(x) for x in a.frames.split(","))
    work = a.work or tempfile.mkdtemp(prefix="spinmotor-longrun-")
    os.makedirs(work, exist_ok=True)
    env = dict(os.environ)
    env.pop("DISPLAY", None)  # the viewer renders offscreen (EGL / OSMesa), as in CI
    env.setdefault("OMP_NUM_THREADS", "1")  # a small mesh: threads only add noise

    tools = {"deform": cli, "viewer": viewer}
    results = {name: [] for name in tools if os.access(tools[name], os.X_OK)}
    run([cli, "demo", "--out", os.path.join(work, "demo"), "-q"], env)  # writes limb-rig.glb
    rig = os.path.join(work, "demo", "limb-rig.glb")
    for n in counts:
        for name in results:
            out = os.path.join(work, f"{name}-{n}")
            if name == "deform":
                cmd = [cli, "deform", write_scene(work, rig, n), "--out-dir", out, "-q"]
            else:
                cmd = [viewer, rig, "--screenshot", out + ".png", "--size", "64x64", "--animation", "twist",
                       "--frames", str(n)]
            _, wall, rss = run(cmd, env)
            results[name].append({"frames": n, "seconds": wall, "rss_kb": rss})
            shutil.rmtree(out, ignore_errors=True)

    print(f"{'tool':8} " + " ".join(f"{'RSS @ ' + format(n, ','):>16}" for n in counts) +
          f" {'kB / frame':>11} {'frames/s':>9}")
    for name, rows in results.items():
        slope = (rows[-1]["rss_kb"] - rows[0]["rss_kb"]) / max(1, rows[-1]["frames"] - rows[0]["frames"])
        fps = rows[-1]["frames"] / rows[-1]["seconds"]
        print(f"{name:8} " + " ".join(f"{r['rss_kb'] / 1024:13.1f} MB" for r in rows) +
              f" {slope:11.2f} {fps:9.0f}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(results, f, indent=2)
    if not a.work:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
