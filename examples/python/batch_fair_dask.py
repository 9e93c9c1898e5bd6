"""Fair and extrude back every mesh of a folder in parallel with dask.distributed.

Usage: batch_fair_dask.py IN_DIR OUT_DIR [--steps N] [--tau T] [--workers W]

Each mesh (closed, oriented, manifold; .obj/.off/.ply/.stl) is faired toward a round sphere
(spinmotor.fair) and extruded back from that sphere (spinmotor.extrude); OUT_DIR gets
<name>.faired.obj and <name>.extruded.obj, and one line per mesh is printed. The cluster is a
LocalCluster of worker *processes* (one thread each: the solvers release the GIL but CHOLMOD and
OpenMP use their own threads) bound to the loopback interface.
"""
import argparse
import os
import sys


def fair_one(path, out_dir, steps, tau):
    """One task: returns (name, vertices, Willmore before, after fairing, rms of the extrusion)."""
    import spinmotor as sm  # imported in the worker process

    name = os.path.splitext(os.path.basename(path))[0]
    V, F = sm.read_mesh(path)
    faired = sm.fair(V, F, steps=steps, tau=tau)
    back = sm.extrude(faired["V"], F, V, steps=steps)
    sm.write_mesh(os.path.join(out_dir, name + ".faired.obj"), faired["V"], F)
    sm.write_mesh(os.path.join(out_dir, name + ".extruded.obj"), back["V"], F)
    rms = sm.metrics(V, back["V"], F, alignment="similarity", willmore=False)["rms"]
    return name, len(V), faired["willmore"][0], faired["willmore"][-1], rms


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("in_dir")
    ap.add_argument("out_dir")
    ap.add_argument("--steps", type=int, default=6)
    ap.add_argument("--tau", type=float, default=0.5)
    ap.add_argument("--workers", type=int, default=2)
    a = ap.parse_args(argv)
    from dask.distributed import Client, LocalCluster

    exts = (".obj", ".off", ".ply", ".stl")
    files = sorted(os.path.join(a.in_dir, f) for f in os.listdir(a.in_dir) if f.lower().endswith(exts))
    if not files:
        print(f"no mesh in {a.in_dir}", file=sys.stderr)
        return 2
    os.makedirs(a.out_dir, exist_ok=True)
    with LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster, Client(cluster) as client:
        futures = client.map(fair_one, files, out_dir=a.out_dir, steps=a.steps, tau=a.tau)
        for name, n, w0, w1, rms in client.gather(futures):
            print(f"{name}: {n} vertices, Willmore {w0:.4g} -> {w1:.4g}, extruded back rms {rms:.3g} of the diagonal")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
