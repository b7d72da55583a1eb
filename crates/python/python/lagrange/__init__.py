"""Exact Lagrangian mechanics of planar mechanisms, from Python.

A scene — built in (``lagrange.scene("double_pendulum")``), a scene file
(``lagrange.scene("examples/scenes/four_bar.toml")``) or a joint graph given as plain dicts
(``lagrange.from_graph(graph, q=..., qdot=...)``) — has exact equations of motion derived by
automatic differentiation of its Lagrangian, integrated by the same engine and checked by the
same rules as the ``lagrange`` command line::

    import lagrange
    pendulum = lagrange.scene("double_pendulum")
    run = pendulum.simulate(5.0, method="dop853", tol=1e-12)
    run.q[-1]                     # numpy arrays: t, q, qdot, energy, violation
    run.to_pandas()               # a DataFrame, a row per sample
    pendulum.accelerations(q=[0.3, -0.2], qdot=[0, 0])
    pendulum.modes()["modes"][0]["omega"]

Sweeps of many runs on a Dask cluster: :func:`lagrange.sweep`. Every failure raises a
subclass of :class:`lagrange.Error` with the command line's message (``lagrange.errors``).
The engine runs without the GIL: Python threads run scenes in parallel.
"""

from . import errors
from ._lagrange import __version__
from ._scene import Equations, Scene, State, Trajectory, from_graph, report, scene, scenes
from .errors import (
    ArgumentError,
    ConstraintError,
    EngineError,
    EquilibriumError,
    Error,
    FileError,
    GraphError,
    IntegrationError,
    NonFiniteError,
    SingularMassMatrixError,
    UnhealthyRunError,
)
from .sweeps import sweep

__all__ = [
    "__version__",
    "scene",
    "scenes",
    "from_graph",
    "report",
    "sweep",
    "Scene",
    "State",
    "Trajectory",
    "Equations",
    "errors",
    "Error",
    "ArgumentError",
    "FileError",
    "GraphError",
    "EngineError",
    "SingularMassMatrixError",
    "NonFiniteError",
    "ConstraintError",
    "IntegrationError",
    "EquilibriumError",
    "UnhealthyRunError",
]
