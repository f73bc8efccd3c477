"""mspline: manifold splines on meshes, from Python.

Arrays in and out are numpy arrays: vertices float64 (n, 3), triangles int64 (m, 3).

    import mspline
    V, F = mspline.read_mesh("data/meshes/eight.off")
    model = mspline.fit(V, F, kind="tspline", tolerance=1e-3)
    model.evaluate(0, [0.5, 0.5])
    model.save("eight.msp")
"""

from ._mspline import *  # noqa: F401,F403
