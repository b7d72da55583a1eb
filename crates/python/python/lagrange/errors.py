"""The exceptions of ``lagrange``: one class per kind of failure, each carrying the message the
command line prints for the same failure.

``Error`` is the root: ``except lagrange.Error`` catches everything the engine raises.
``ArgumentError`` (also a ``ValueError``) is a bad request — an unknown scene or method, a
parameter outside its domain, a NaN, an array of the wrong length; ``FileError`` and
``GraphError`` are bad scene files and joint graphs. ``EngineError`` and its subclasses are
failures on a valid request. ``UnhealthyRunError`` is a run that finished but did not keep what
its scene declares (a constant of the motion, the constraints) to the error its method allows.
"""

__all__ = [
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


class Error(Exception):
    """Anything the engine raises."""


class ArgumentError(Error, ValueError):
    """A bad request: unknown scene, method or engine; a parameter outside its domain; a
    non-finite value; an array of the wrong length; a setting the method does not take."""


class FileError(ArgumentError):
    """A scene file that cannot be read or is not a valid scene (the message shows the place)."""


class GraphError(ArgumentError):
    """A joint graph that is not a mechanism, or whose loops do not close from its state."""


class EngineError(Error):
    """The engine failed on a valid request."""


class SingularMassMatrixError(EngineError):
    """The mass matrix is singular or indefinite at the state."""


class NonFiniteError(EngineError):
    """A quantity became infinite or NaN."""


class ConstraintError(EngineError):
    """The constraints cannot hold: an inconsistent state, a loop that cannot be assembled."""


class IntegrationError(EngineError):
    """The integration failed: it diverged, its step underflowed, Newton did not converge."""


class EquilibriumError(EngineError):
    """No equilibrium near the configuration (normal modes)."""


class UnhealthyRunError(Error):
    """A run that did not keep what its scene declares to the error its method allows.

    ``trajectory`` holds the run, for a look at what drifted."""

    def __init__(self, message, trajectory=None):
        super().__init__(message)
        self.trajectory = trajectory
