"""Scenes, runs and their results: the Python face of the extension module ``_lagrange``."""

import json
import os
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

from . import _lagrange
from .errors import ArgumentError, FileError, UnhealthyRunError

# The maximal-coordinate engines ``Scene.compare`` runs by default.
ENGINES = ("cartesian", "rapier-impulse", "rapier-multibody", "rapier-impulse-f32", "rapier-multibody-f32")


def _params(params) -> list:
    """A parameter dict as the engine takes it: ``(name, value)`` pairs (name, symbol or ASCII
    symbol), values as floats."""
    if params is None:
        return []
    if not isinstance(params, dict):
        raise ArgumentError(f"params must be a dict of name: value, got {type(params).__name__}")
    pairs = []
    for name, value in params.items():
        try:
            pairs.append((str(name), float(value)))
        except (TypeError, ValueError):
            raise ArgumentError(f"params: `{name}` = {value!r} is not a number") from None
    return pairs


def _vector(what: str, values) -> Optional[list]:
    """A state vector (list, tuple, numpy array) as a list of floats; ``None`` stays ``None``."""
    if values is None:
        return None
    try:
        array = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise ArgumentError(f"{what} must be numbers, got {values!r}") from None
    if array.ndim != 1:
        raise ArgumentError(f"{what} must be one-dimensional, got shape {array.shape}")
    return array.tolist()


def _number(what: str, value) -> Optional[float]:
    if value is None:
        return None
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ArgumentError(f"{what} must be a number, got {value!r}") from None


def _hold(hold) -> Optional[List[str]]:
    """Coordinates to hold: a name or a list of names."""
    if hold is None:
        return None
    if isinstance(hold, str):
        return [hold]
    return [str(h) for h in hold]


@dataclass(frozen=True)
class State:
    """A state of the mechanism: time ``t``, coordinates ``q`` and velocities ``qdot``."""

    t: float
    q: np.ndarray
    qdot: np.ndarray


@dataclass
class Trajectory:
    """A run: the samples and what the run says of itself.

    ``t`` (samples,), ``q`` and ``qdot`` (samples × coordinates), ``energy`` (the energy
    function h at each sample), ``violation`` (samples × 2: max |Φ| and max |Φ̇|, for a mechanism
    with constraints among its coordinates; ``None`` otherwise). ``stats`` counts the steps,
    rejections and evaluations; ``health`` is the run's check against the constants of the
    motion its scene declares and its constraints: the ``expected`` relative error, the
    quantities ``checked`` and the ``findings`` beyond their bounds (empty for a healthy run).
    ``engine_seconds`` is the wall time of the engine's part of the call (building the system,
    the run, its check): what the same run costs from Rust."""

    scene: str
    coordinates: List[str]
    t: np.ndarray
    q: np.ndarray
    qdot: np.ndarray
    energy: np.ndarray
    violation: Optional[np.ndarray]
    stats: Dict[str, object]
    health: Dict[str, object]
    method: str
    engine_seconds: float = 0.0

    @property
    def final_state(self) -> State:
        """The last sample."""
        return State(float(self.t[-1]), self.q[-1].copy(), self.qdot[-1].copy())

    @property
    def healthy(self) -> bool:
        """Whether the run kept everything its scene declares."""
        return not self.health["findings"]

    def energy_drift(self) -> float:
        """``max |h − h(0)|`` over the samples, relative to ``|h(0)|`` (absolute when it is 0)."""
        h = self.energy
        scale = abs(h[0]) if h[0] != 0 else 1.0
        return float(np.max(np.abs(h - h[0])) / scale)

    def max_violation(self) -> float:
        """The largest constraint residual over the samples (0 without constraints)."""
        return 0.0 if self.violation is None else float(np.max(self.violation))

    def to_pandas(self):
        """The samples as a ``pandas.DataFrame``: ``t``, each coordinate, each velocity
        (``<name>_dot``), ``h`` and, with constraints, ``max|Phi|`` and ``max|Phi_dot|``."""
        import pandas as pd

        columns = {"t": self.t}
        for j, name in enumerate(self.coordinates):
            columns[name] = self.q[:, j]
        for j, name in enumerate(self.coordinates):
            columns[f"{name}_dot"] = self.qdot[:, j]
        columns["h"] = self.energy
        if self.violation is not None:
            columns["max|Phi|"] = self.violation[:, 0]
            columns["max|Phi_dot|"] = self.violation[:, 1]
        return pd.DataFrame(columns)

    def __len__(self) -> int:
        return len(self.t)


class Equations(dict):
    """A scene's equations of motion derived symbolically: ``T``, ``V``, ``L``, Lagrange's
    equations, constraints and constants of the motion, each formula in Unicode, LaTeX and the
    scene-file language (the keys of ``lagrange eom --json``). ``str()`` prints them as a
    textbook does; ``latex`` is one ``align*`` environment."""

    def __init__(self, data, text, latex):
        super().__init__(data)
        self.text = text
        self.latex = latex

    def __str__(self) -> str:
        return self.text.rstrip("\n")

    def _repr_latex_(self) -> str:
        return "$$" + self.latex.replace("\\begin{align*}", "\\begin{aligned}").replace(
            "\\end{align*}", "\\end{aligned}"
        ) + "$$"


class Scene:
    """A mechanism: its coordinates, parameters, default state, and everything the engine
    derives from them. Get one with :func:`scene` or :func:`from_graph`.

    Every method takes the parameters as ``params={"name": value}`` (name, symbol, or symbol
    in ASCII: ``alpha`` for ``α``) over the scene's defaults, and a state as ``q``, ``qdot``
    (sequences or numpy arrays of the scene's length) and ``t``, each defaulting to the scene's
    initial state. A scene pickles (its description travels, not its memory): it can be sent
    to another process or a Dask worker."""

    def __init__(self, inner):
        self._inner = inner

    @classmethod
    def _from_spec(cls, spec: str) -> "Scene":
        return cls(_lagrange.Scene.from_spec(spec))

    def __reduce__(self):
        return (Scene._from_spec, (self._inner.spec(),))

    def __repr__(self) -> str:
        return f"<lagrange.Scene {self.id!r}: {self.title}>"

    @property
    def id(self) -> str:
        """The scene's id."""
        return self._inner.id

    @property
    def title(self) -> str:
        """One line on the scene."""
        return self._inner.title

    @property
    def reference(self) -> str:
        """Where the scene and its closed form come from."""
        return self._inner.reference

    @property
    def horizon(self) -> Optional[float]:
        """The span (s) the validation report runs the scene over, if it declares one."""
        return self._inner.horizon

    @property
    def parameters(self) -> Dict[str, float]:
        """The parameters' defaults, by name."""
        return {name: default for name, _, _, default, _ in self._inner.parameters()}

    def parameter_info(self) -> List[dict]:
        """Every parameter: name, symbol, unit, default, description."""
        keys = ("name", "symbol", "unit", "default", "description")
        return [dict(zip(keys, p)) for p in self._inner.parameters()]

    def coordinates(self, params=None) -> List[str]:
        """The generalized coordinates' names."""
        return [name for name, _ in self._inner.coordinates(_params(params))]

    def units(self, params=None) -> List[str]:
        """The generalized coordinates' units (``m``, ``rad``)."""
        return [unit for _, unit in self._inner.coordinates(_params(params))]

    def default_state(self, params=None) -> State:
        """The scene's initial state."""
        t, q, qdot = self._inner.default_state(_params(params))
        return State(t, np.array(q), np.array(qdot))

    def initial_state(self, q=None, qdot=None, t=None, hold=None, params=None) -> State:
        """The given state brought onto the constraints among the coordinates, keeping the
        coordinates named in ``hold`` (and their rates); a state given without ``hold`` must be
        on them already (:class:`ArgumentError` otherwise)."""
        t, q, qdot = self._inner.initial_state(
            _params(params), _number("t", t), _vector("q", q), _vector("qdot", qdot), _hold(hold)
        )
        return State(t, np.array(q), np.array(qdot))

    def simulate(
        self,
        t_end,
        *,
        method: str = "dopri5",
        dt=None,
        tol=None,
        q=None,
        qdot=None,
        t0=None,
        hold=None,
        times=None,
        every=None,
        params=None,
        allow_drift: bool = False,
    ) -> Trajectory:
        """Integrate from the given state (default: the scene's) to ``t_end``.

        ``method``: ``rk4``, ``variational``, ``gauss4`` (fixed step ``dt``, default 1e-3) or
        ``dopri5``, ``dop853``, ``sdirk4`` (tolerance ``tol``; defaults 1e-10, 1e-12, 1e-8).
        Samples at ``times`` (increasing, within the run), or every ``every`` seconds, or at 200
        intervals. The run is checked against every constant of the motion its scene declares
        and against its constraints: a run that drifts beyond what its method allows raises
        :class:`UnhealthyRunError` (carrying the trajectory), unless ``allow_drift``."""
        out = self._inner.simulate(
            _params(params),
            _number("t_end", t_end),
            method,
            _number("dt", dt),
            _number("tol", tol),
            _number("t0", t0),
            _vector("q", q),
            _vector("qdot", qdot),
            _hold(hold),
            _vector("times", times),
            _number("every", every),
        )
        trajectory = Trajectory(
            scene=self.id,
            coordinates=out["coordinates"],
            t=out["t"],
            q=out["q"],
            qdot=out["qdot"],
            energy=out["energy"],
            violation=out["violation"],
            stats=out["stats"],
            health=out["health"],
            method=out["method"],
            engine_seconds=out["engine_seconds"],
        )
        health = out["health"]
        fixed_step = method in ("rk4", "variational", "gauss4", "gauss")
        message = _lagrange.Scene.unhealthy_message(
            self.id, out["method"], health["findings"], health["expected"], fixed_step
        )
        if message is not None and not allow_drift:
            raise UnhealthyRunError(message, trajectory)
        return trajectory

    def accelerations(self, q=None, qdot=None, t=None, params=None) -> np.ndarray:
        """The generalized accelerations q̈ at a state."""
        return self._inner.accelerations(_params(params), _number("t", t), _vector("q", q), _vector("qdot", qdot))

    def closed_form_accelerations(self, q=None, qdot=None, t=None, params=None) -> Optional[np.ndarray]:
        """The scene's closed-form q̈ at a state, where it has one (``None`` otherwise)."""
        return self._inner.closed_form_accelerations(
            _params(params), _number("t", t), _vector("q", q), _vector("qdot", qdot)
        )

    def mass_matrix(self, q=None, t=None, params=None) -> np.ndarray:
        """The mass matrix M(q) (n × n)."""
        return self._inner.mass_matrix(_params(params), _number("t", t), _vector("q", q))

    def energy(self, q=None, qdot=None, t=None, params=None) -> float:
        """The energy function h = q̇ · ∂L/∂q̇ − L at a state."""
        return self._inner.energy(_params(params), _number("t", t), _vector("q", q), _vector("qdot", qdot))

    def multipliers(self, q=None, qdot=None, t=None, params=None) -> Optional[np.ndarray]:
        """The constraint multipliers λ (M q̈ + Gᵀλ = f) at a state; ``None`` for a scene
        without constraints among its coordinates."""
        return self._inner.multipliers(_params(params), _number("t", t), _vector("q", q), _vector("qdot", qdot))

    def multiplier_rank(self, q=None, qdot=None, t=None, params=None) -> Optional[dict]:
        """How far the equations determine the multipliers at a state: ``rows`` (m + k),
        ``determined`` (directions of λ the equations fix: eigenvalues of G M⁻¹ Gᵀ above the
        constrained solve's shift), ``conditioning`` (its smallest eigenvalue over its largest)
        and ``unique``. At a redundancy or a singular configuration ``unique`` is ``False``:
        :meth:`multipliers` returns the smallest λ of many, while q̈ and :meth:`reactions` are
        unique. ``None`` for a scene without constraints among its coordinates."""
        rank = self._inner.multiplier_rank(_params(params), _number("t", t), _vector("q", q), _vector("qdot", qdot))
        if rank is None:
            return None
        rows, determined, conditioning = rank
        return {"rows": rows, "determined": determined, "conditioning": conditioning, "unique": determined == rows}

    def reactions(self, q=None, qdot=None, t=None, params=None) -> Optional[np.ndarray]:
        """The constraint forces on the bodies at a state: a row (Fx, Fy, τ) per body, in the
        order of :meth:`bodies`."""
        return self._inner.reactions(_params(params), _number("t", t), _vector("q", q), _vector("qdot", qdot))

    def bodies(self, params=None) -> List[str]:
        """The bodies' names."""
        return self._inner.bodies(_params(params))

    def compare(
        self,
        engines=ENGINES,
        *,
        t_end=2.0,
        dt=1.0 / 240.0,
        substeps: int = 4,
        tol=1e-12,
        q=None,
        qdot=None,
        t0=None,
        hold=None,
        params=None,
    ) -> List[dict]:
        """The scene beside the maximal-coordinate engines over ``t_end`` seconds: one dict per
        engine with its errors over time (``times``, ``errors``: ‖q − q_ref‖∞ against the
        scene's closed form or the reduced solution at tolerance 3e-15, ``reference`` says which),
        ``max_error``, ``final_error``, energy and momentum drifts, constraint violation, force
        error, ``steps`` and ``seconds_per_step``; or ``unbuildable`` with the reason. rapier
        runs at step ``dt`` with ``substeps``; the Cartesian engine at tolerance ``tol``."""
        if isinstance(engines, str):
            engines = ENGINES if engines == "all" else [engines]
        if not isinstance(substeps, int) or substeps < 1:
            raise ArgumentError(f"substeps must be a positive integer, got {substeps!r}")
        rows = json.loads(
            self._inner.compare(
                _params(params),
                list(engines),
                _number("t_end", t_end),
                _number("dt", dt),
                int(substeps),
                _number("tol", tol),
                _number("t0", t0),
                _vector("q", q),
                _vector("qdot", qdot),
                _hold(hold),
            )
        )
        for row in rows:
            for key in ("times", "errors"):
                if key in row:
                    row[key] = np.array(row[key], dtype=np.float64)
        return rows

    def modes(self, q=None, t=None, params=None) -> dict:
        """The equilibrium nearest ``q`` (default: the initial configuration) and the normal
        modes about it: ``equilibrium``, ``mass_matrix`` and ``stiffness_matrix`` there (n × n),
        and ``modes``, each with ``kind`` (oscillating, zero, unstable), ``omega_squared``,
        ``omega``, ``frequency``, ``period`` and ``shape``."""
        out = json.loads(self._inner.modes(_params(params), _number("t", t), _vector("q", q)))
        n = len(out["coordinates"])
        out["equilibrium"] = np.array(out["equilibrium"])
        for key in ("mass_matrix", "stiffness_matrix"):
            out[key] = np.array(out[key]).reshape(n, n)
        for mode in out["modes"]:
            mode["shape"] = np.array(mode["shape"])
        return out

    def eom(self) -> Equations:
        """The equations of motion derived symbolically, for a scene file or a joint graph
        (:class:`Equations`; ``print()`` it)."""
        data, text, latex = self._inner.eom()
        return Equations(json.loads(data), text, latex)


def scene(name: str) -> Scene:
    """A built-in scene by id (:func:`scenes` lists them), or the scene file at a path
    (``*.toml``, or any file that exists; docs/files.md)."""
    if not isinstance(name, (str, os.PathLike)):
        raise ArgumentError(f"scene: expected an id or a path, got {type(name).__name__}")
    path = os.fspath(name)
    if path.endswith(".toml") or os.path.isfile(path):
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise FileError(f"cannot read {path}: {e.strerror or e}") from None
        except UnicodeDecodeError:
            raise FileError(f"{path}: not a text file: the bytes are not UTF-8") from None
        spec = {"file": {"path": path, "text": text}}
    else:
        spec = {"builtin": path}
    return Scene._from_spec(json.dumps(spec))


def from_graph(graph: dict, q, qdot=None, t: float = 0.0) -> Scene:
    """The scene of a joint graph given as plain dicts and lists (the serde form of
    ``lagrange::graph::JointGraph``: ``name``, ``gravity``, ``bodies``, ``joints``, …), starting
    at ``q``, ``qdot`` (zeros by default) at time ``t``; with loops, the state is brought onto
    them keeping the first coordinate. Its id is the graph's name."""
    q = _vector("q", q)
    if q is None:
        raise ArgumentError("q: the initial coordinates of a joint graph are required")
    qdot = _vector("qdot", qdot) if qdot is not None else [0.0] * len(q)
    spec = {"graph": {"graph": graph, "t": float(t), "q": q, "qdot": qdot}}
    try:
        text = json.dumps(spec, allow_nan=False)
    except (TypeError, ValueError) as e:
        raise ArgumentError(f"the graph is not plain data (dicts, lists, finite numbers, strings): {e}") from None
    return Scene._from_spec(text)


def scenes() -> List[str]:
    """Every built-in scene's id."""
    return list(_lagrange.scene_ids())


def report(scenes=None, *, quick: bool = False, t_end=None, jobs: Optional[int] = None, out=None) -> dict:
    """The validation report (the schema of ``report.json``, docs/validation.md): the given
    scenes (ids, paths or :class:`Scene` objects; every built-in scene by default) by every
    method over its sweeps against their references, then the stability suite of those scenes,
    on ``jobs`` threads (default: every core). ``quick`` runs the short sweeps. With ``out``
    (a directory), also writes ``report.json``, ``report.md`` and each scene's plots there."""
    if jobs is not None and (not isinstance(jobs, int) or jobs < 1):
        raise ArgumentError(f"jobs must be a positive integer, got {jobs!r}")
    specs = []
    for s in scenes or []:
        s = s if isinstance(s, Scene) else scene(s)
        specs.append(s._inner.spec())
    text = _lagrange.report(
        specs, bool(quick), _number("t_end", t_end), None if jobs is None else int(jobs),
        None if out is None else os.fspath(out),
    )
    return json.loads(text)
