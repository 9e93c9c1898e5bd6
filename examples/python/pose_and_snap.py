"""Pose a mesh with two surface-harmonic handles, snap the edit to a conformal shape, write, print Q.
Usage: pose_and_snap.py [MESH] [OUT.obj]   (default: a generated capsule along z)."""
import sys
import numpy as np
import spinmotor as sm

V, F = sm.read_mesh(sys.argv[1]) if len(sys.argv) > 1 else sm.capsule(0.5, 3.0, 40, 24)
lo, hi = V[:, 2].min(), V[:, 2].max()
base, tip = np.flatnonzero(V[:, 2] < lo + 0.1 * (hi - lo)), np.flatnonzero(V[:, 2] > hi - 0.1 * (hi - lo))
bend = sm.Motor.from_rotation((1, 0, 0), 70, about=V[tip].mean(axis=0) - [0, 0, 0.5 * (hi - lo)])
edit = sm.SurfaceHarmonicDeformer(V, F, handles=[("base", base), ("tip", tip)]).pose([sm.Motor(), bend])
snapped = sm.ConformalSnap(V, F).snap(edit)
sm.write_mesh(sys.argv[2] if len(sys.argv) > 2 else "pose_and_snap.obj", snapped, F)
print(f"Q mean: edit {sm.metrics(V, edit, F)['q_mean']:.4f} -> snapped {sm.metrics(V, snapped, F)['q_mean']:.4f}")
