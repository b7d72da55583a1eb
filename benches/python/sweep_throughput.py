"""Throughput of the Python package, measured side by side in one run (docs/python.md#measured):

1. the bindings' cost per call: the wall time of ``Scene.simulate`` from Python against the
   engine's own part of it (``Trajectory.engine_seconds``: the same run from Rust), on a
   cheap run and a typical one;
2. a sweep of the same points as a serial Python loop, on a LocalCluster of 1 worker and of
   2 workers (cluster start-up timed apart), points per second each, the frames compared;
3. Dask's cost per task: the same sweep in chunks of 1 point and in the default chunks.

Each configuration is timed ``--repeats`` times and the best kept.

    .venv/bin/python benches/python/sweep_throughput.py [--points 2000] [--t-end 5] [--repeats 3]
"""

import argparse
import math
import statistics
import time

import numpy as np
from distributed import Client, LocalCluster

import lagrange


def overhead(scene, t_end, repeats, **kwargs):
    """Median Python wall time, median engine time, and their difference (s) over `repeats`."""
    walls, engines = [], []
    for _ in range(repeats):
        started = time.perf_counter()
        run = scene.simulate(t_end, **kwargs)
        walls.append(time.perf_counter() - started)
        engines.append(run.engine_seconds)
    return statistics.median(walls), statistics.median(engines), statistics.median(
        w - e for w, e in zip(walls, engines))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--points", type=int, default=2000)
    parser.add_argument("--t-end", type=float, default=5.0)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()

    print("1. bindings: Python call against the engine's part (medians)")
    cheap = lagrange.scene("harmonic_oscillator")
    for label, scene, t_end, kwargs in [
        ("harmonic oscillator, 1 step of rk4", cheap, 1e-3, dict(method="rk4", dt=1e-3)),
        (f"double pendulum, {args.t_end} s dop853 1e-10", lagrange.scene("double_pendulum"), args.t_end,
         dict(method="dop853", tol=1e-10)),
    ]:
        wall, engine, extra = overhead(scene, t_end, 200 if t_end < 1 else 20, **kwargs)
        print(f"   {label}: call {wall * 1e6:9.1f} µs, engine {engine * 1e6:9.1f} µs, "
              f"bindings {extra * 1e6:7.1f} µs ({extra / wall:.1%} of the call)")

    scene = lagrange.scene("double_pendulum")
    angles = np.linspace(0.5, 2.5, args.points)
    grid = {"q[0]": angles}
    settings = dict(t_end=args.t_end, method="dop853", tol=1e-10, quantities=["final_state"])

    print(f"2. {args.points} double-pendulum runs of {args.t_end} s (dop853, tol 1e-10)")
    # Each configuration the best of `--repeats` (a shared machine's noise only adds time).
    t_serial = math.inf
    for _ in range(args.repeats):
        started = time.perf_counter()
        serial = [scene.simulate(args.t_end, q=[a, 0.5], method="dop853", tol=1e-10).q[-1] for a in angles]
        t_serial = min(t_serial, time.perf_counter() - started)
    print(f"   serial Python loop: {t_serial:7.2f} s, {args.points / t_serial:7.1f} points/s")
    frames, times = {}, {}
    for workers in (1, 2):
        started = time.perf_counter()
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
            with Client(cluster) as client:
                client.wait_for_workers(workers)
                start_up = time.perf_counter() - started
                for chunk_size, label in [(None, "default chunks"), (1, "chunks of 1")]:
                    if chunk_size == 1 and workers == 1:
                        continue
                    elapsed = math.inf
                    for _ in range(args.repeats):
                        started = time.perf_counter()
                        frame = lagrange.sweep(scene, grid=grid, q=[0.0, 0.5], client=client,
                                               chunk_size=chunk_size, progress=False, **settings)
                        elapsed = min(elapsed, time.perf_counter() - started)
                    frames[(workers, chunk_size)] = frame
                    times[(workers, chunk_size)] = elapsed
                    size = chunk_size or lagrange.sweeps.default_chunk_size(args.points, workers)
                    print(f"   {workers} worker(s), {label} ({size} points): {elapsed:7.2f} s, "
                          f"{args.points / elapsed:7.1f} points/s, {elapsed / t_serial:.2f}× the serial loop "
                          f"(cluster start-up {start_up:.2f} s apart)")
    ends = np.array(serial)
    for key, frame in frames.items():
        same = np.array_equal(frame[["q_end.θ1", "q_end.θ2"]].to_numpy(), ends)
        print(f"   {key}: final states equal to the serial loop's bit for bit: {same}")
    # Each extra task costs its worker the same time: wall difference × workers / extra tasks.
    tasks_default = -(-args.points // lagrange.sweeps.default_chunk_size(args.points, 2))
    per_task = (times[(2, 1)] - times[(2, None)]) * 2 / (args.points - tasks_default)
    point = t_serial / args.points
    print(f"3. Dask's cost per task on 2 workers: {per_task * 1e3:.2f} ms, against {point * 1e3:.2f} ms per "
          f"point: a chunk of the default size spends {per_task / (point * lagrange.sweeps.default_chunk_size(args.points, 2)):.1%} "
          "of its time on Dask")

if __name__ == "__main__":
    main()
