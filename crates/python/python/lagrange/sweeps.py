"""Sweeps: one simulation per point of a grid or a sample, on a Dask cluster.

``lagrange.sweep(scene, grid=... | samples=..., t_end=..., quantities=...)`` runs every point
in chunks on a ``dask.distributed`` client — by default a ``LocalCluster`` with one worker
process per core; any other client (dask-jobqueue on Slurm or PBS, dask-kubernetes, a cloud
cluster, a scheduler address) with no change of code — and returns a ``pandas.DataFrame``, a
row per point in the order given: the point's values, the requested quantities, the wall time
of the point, and the error of a point that failed (a failed point never aborts the sweep).

A point is a dict. Its keys name parameters of the scene (name, symbol or ASCII symbol), or
the initial state: ``q[i]`` / ``qdot[i]`` by index, ``q.<name>`` / ``qdot.<name>`` by
coordinate name, ``t0``. Every point runs the same code as :meth:`lagrange.Scene.simulate`, so
the results are those of the same runs made one after another, bit for bit.
"""

import itertools
import math
import os
import re
import time
from typing import Callable, Dict, List, Optional

import numpy as np

from .errors import ArgumentError

# Quantities by name: what each reads off a finished run.
_STATE = re.compile(r"^(q|qdot)(?:\[(\d+)\]|\.(.+))$")


def _final_q(run) -> Dict[str, float]:
    return {f"q_end.{name}": float(v) for name, v in zip(run.coordinates, run.q[-1])}


def _final_qdot(run) -> Dict[str, float]:
    return {f"qdot_end.{name}": float(v) for name, v in zip(run.coordinates, run.qdot[-1])}


QUANTITIES: Dict[str, Callable] = {
    "final_q": _final_q,
    "final_qdot": _final_qdot,
    "final_state": lambda run: {**_final_q(run), **_final_qdot(run)},
    "energy_drift": lambda run: {"energy_drift": run.energy_drift()},
    "violation": lambda run: {"violation": run.max_violation()},
    "steps": lambda run: {"steps": int(run.stats["steps"])},
}


def _points(grid, samples) -> List[dict]:
    """The points: the Cartesian product of a grid (name → values), or the samples (a list of
    dicts, a dict of equal-length sequences, or a DataFrame)."""
    if (grid is None) == (samples is None):
        raise ArgumentError("give grid or samples (one of them)")
    if grid is not None:
        if not isinstance(grid, dict) or not grid:
            raise ArgumentError("grid must be a non-empty dict of name: values")
        names = list(grid)
        values = [list(np.atleast_1d(grid[n]).tolist()) for n in names]
        return [dict(zip(names, combination)) for combination in itertools.product(*values)]
    if hasattr(samples, "to_dict") and hasattr(samples, "columns"):
        return samples.to_dict("records")
    if isinstance(samples, dict):
        columns = {k: list(np.atleast_1d(v).tolist()) for k, v in samples.items()}
        lengths = {len(v) for v in columns.values()}
        if len(lengths) != 1:
            raise ArgumentError(f"samples: the columns have different lengths {sorted(lengths)}")
        count = lengths.pop()
        return [{k: v[i] for k, v in columns.items()} for i in range(count)]
    return [dict(p) for p in samples]


def _quantities(quantities) -> List[tuple]:
    """``(name, function)`` pairs; a function of the run returns a number or a dict of them."""
    if isinstance(quantities, (str, dict)) or callable(quantities):
        quantities = [quantities]
    pairs = []
    for q in quantities:
        if isinstance(q, str):
            if q not in QUANTITIES:
                raise ArgumentError(f"unknown quantity `{q}`; known: {', '.join(QUANTITIES)}, or a function of the run")
            pairs.append((q, QUANTITIES[q]))
        elif isinstance(q, dict):
            pairs.extend(q.items())
        elif callable(q):
            pairs.append((getattr(q, "__name__", "quantity"), q))
        else:
            raise ArgumentError(f"a quantity is a name or a function of the run, got {q!r}")
    return pairs


def _split(scene, point: dict, base: dict):
    """A point's parameters and initial state over the sweep's base settings."""
    params = dict(base.get("params") or {})
    coordinates = None
    q = None if base.get("q") is None else list(np.asarray(base["q"], dtype=float))
    qdot = None if base.get("qdot") is None else list(np.asarray(base["qdot"], dtype=float))
    t0 = base.get("t0")
    for key, value in point.items():
        match = _STATE.match(str(key))
        if key == "t0":
            t0 = value
        elif match:
            which, index, name = match.groups()
            if coordinates is None:
                coordinates = scene.coordinates(params)
            if index is not None:
                j = int(index)
                if j >= len(coordinates):
                    raise ArgumentError(f"{key}: the scene has {len(coordinates)} coordinates")
            elif name in coordinates:
                j = coordinates.index(name)
            else:
                raise ArgumentError(f"{key}: no coordinate `{name}`; the coordinates are {', '.join(coordinates)}")
            if which == "q":
                if q is None:
                    q = list(scene.default_state(params).q)
                q[j] = value
            else:
                if qdot is None:
                    qdot = list(scene.default_state(params).qdot)
                qdot[j] = value
        else:
            params[key] = value
    return params, q, qdot, t0


def run_point(scene, point: dict, settings: dict, quantities) -> dict:
    """One point: its run and quantities, or the error that stopped it. What every worker runs;
    the serial form of a sweep is a loop over it."""
    row = {}
    started = time.perf_counter()
    try:
        params, q, qdot, t0 = _split(scene, point, settings)
        run = scene.simulate(
            settings["t_end"],
            method=settings["method"],
            dt=settings.get("dt"),
            tol=settings.get("tol"),
            q=q,
            qdot=qdot,
            t0=t0,
            hold=settings.get("hold"),
            times=settings.get("times"),
            params=params,
            allow_drift=settings.get("allow_drift", False),
        )
        for name, function in _quantities(quantities):
            value = function(run)
            if isinstance(value, dict):
                row.update(value)
            else:
                row[name] = value
        row["error"] = None
        row["error_type"] = None
    except Exception as error:  # a failed point is a row, never the end of the sweep
        row["error"] = str(error)
        row["error_type"] = type(error).__name__
    row["wall_time"] = time.perf_counter() - started
    return row


def _run_chunk(scene, points, settings, quantities) -> List[dict]:
    return [run_point(scene, point, settings, quantities) for point in points]


def _chunks(points: list, size: int) -> List[list]:
    return [points[i : i + size] for i in range(0, len(points), size)]


def default_chunk_size(points: int, workers: int) -> int:
    """Eight chunks per worker: enough for the load to balance when points differ in cost (a
    chaotic run, a failing point), few enough that Dask's cost per task (about 5 ms measured on
    a 2-core machine, docs/python.md#measured) is a few percent of a chunk of millisecond runs.
    For much cheaper points, give a larger ``chunk_size``."""
    return max(1, math.ceil(points / (8 * max(1, workers))))


def sweep(
    scene,
    *,
    t_end,
    grid: Optional[dict] = None,
    samples=None,
    quantities=("final_state", "energy_drift"),
    method: str = "dopri5",
    dt=None,
    tol=None,
    q=None,
    qdot=None,
    t0=None,
    hold=None,
    times=None,
    params: Optional[dict] = None,
    allow_drift: bool = False,
    client=None,
    chunk_size: Optional[int] = None,
    progress=None,
):
    """Run ``scene`` once per point of ``grid`` (name → values, every combination) or
    ``samples`` (a list of dicts, a dict of columns, a DataFrame) to ``t_end`` on a Dask
    client, and return a ``pandas.DataFrame``, a row per point in order.

    ``quantities``: names (``final_q``, ``final_qdot``, ``final_state``, ``energy_drift``,
    ``violation``, ``steps``), functions of the :class:`lagrange.Trajectory` (named by their
    ``__name__``, returning a number or a dict of them), or a dict name → function. ``method``,
    ``dt``, ``tol``, ``q``, ``qdot``, ``t0``, ``hold``, ``times``, ``params`` and
    ``allow_drift`` are those of :meth:`lagrange.Scene.simulate`, for every point; a point's
    own values override them. Columns: the point's keys, the quantities, ``wall_time`` (s),
    ``error`` and ``error_type`` (``None`` for a point that ran).

    ``client``: a ``distributed.Client`` (or a scheduler address); by default a
    ``LocalCluster`` with one single-threaded worker process per core, closed afterwards.
    ``chunk_size``: points per task (default :func:`default_chunk_size`). ``progress``:
    ``True`` for Dask's progress bar, a function ``(done, total)`` called as points finish, or
    ``None`` for the bar when standard output is a terminal."""
    import pandas as pd
    from distributed import Client, LocalCluster, as_completed

    from ._scene import Scene
    from ._scene import scene as scene_by_name

    if not isinstance(scene, Scene):
        scene = scene_by_name(scene)
    points = _points(grid, samples)
    _quantities(quantities)  # unknown names fail here, not in every point
    settings = {
        "t_end": t_end, "method": method, "dt": dt, "tol": tol, "q": q, "qdot": qdot, "t0": t0,
        "hold": hold, "times": None if times is None else list(np.asarray(times, dtype=float)),
        "params": params, "allow_drift": allow_drift,
    }
    own_cluster = None
    if client is None:
        own_cluster = LocalCluster(
            n_workers=os.cpu_count() or 1, threads_per_worker=1, processes=True, dashboard_address=":0"
        )
        client = Client(own_cluster)
    elif isinstance(client, str):
        client = Client(client)
        own_cluster = client  # closed with the sweep: it was opened for it
    try:
        workers = max(1, len(client.scheduler_info().get("workers", {})))
        size = chunk_size if chunk_size is not None else default_chunk_size(len(points), workers)
        if not (isinstance(size, int) and size >= 1):
            raise ArgumentError(f"chunk_size must be a positive integer, got {size!r}")
        chunks = _chunks(points, size)
        # The scene travels with every task as its description (a few hundred bytes, a scene
        # file's text at most); a worker resolves it once and keeps it.
        futures = [client.submit(_run_chunk, scene, chunk, settings, quantities, pure=False) for chunk in chunks]
        if progress is None:
            progress = os.isatty(1) if hasattr(os, "isatty") else False
        if callable(progress):
            done = 0
            sizes = {future.key: len(chunk) for future, chunk in zip(futures, chunks)}
            for future in as_completed(futures):
                done += sizes[future.key]
                progress(done, len(points))
        elif progress:
            from distributed import progress as dask_progress

            dask_progress(futures, notebook=False)
        rows = [row for chunk_rows in client.gather(futures) for row in chunk_rows]
    finally:
        if own_cluster is not None:
            if own_cluster is not client:
                client.close()
            own_cluster.close()
    frame = pd.DataFrame([{**point, **row} for point, row in zip(points, rows)])
    return frame
