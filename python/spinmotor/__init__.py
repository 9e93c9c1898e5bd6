"""spinmotor: mesh deformation with CGA motors and conformal cleanup by spin transformations.

Meshes are numpy arrays: V (n, 3) float64 positions and F (m, 3) integer triangles (C or Fortran order,
any real / integer dtype is converted). Every function validates its input before any work and raises
spinmotor.Error (attribute .kind: "bad_input" or "numerical") with the C++ library's message.

    import spinmotor as sm
    V, F = sm.capsule(0.5, 3.0, 40, 24)
    tip = [i for i in range(len(V)) if V[i, 2] > 3.2]
    base = [i for i in range(len(V)) if V[i, 2] < -0.2]
    d = sm.SurfaceHarmonicDeformer(V, F, handles=[("base", base), ("tip", tip)])
    V1 = d.pose([sm.Motor(), sm.Motor.from_rotation((1, 0, 0), 60, about=(0, 0, 3))])
    V2 = sm.ConformalSnap(V, F).snap(V1)
    print(sm.metrics(V, V2, F)["q_mean"])

The extension module is spinmotor._spinmotor (C++, pybind11); this package re-exports it.
"""

from ._spinmotor import *  # noqa: F401,F403
from ._spinmotor import Error, Motor, Mesh, Deformer  # noqa: F401
from . import _spinmotor

__all__ = [name for name in dir(_spinmotor) if not name.startswith("_")]
__version__ = "0.1.0"
