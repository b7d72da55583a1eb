"""A parameter study of the driven pendulum on Dask: the largest swing over a grid of drive
amplitudes and frequencies, run on a LocalCluster by default or, unchanged, on any cluster
whose scheduler address is given.

    .venv/bin/python examples/python/parameter_sweep.py                      # LocalCluster
    dask scheduler &  dask worker tcp://127.0.0.1:8786 &                      # any cluster
    .venv/bin/python examples/python/parameter_sweep.py --scheduler tcp://127.0.0.1:8786

Prints a table of the largest |θ| over the run per (amplitude, frequency) and the sweep's
throughput; ``--csv`` writes the whole frame.
"""

import argparse
import time

import numpy as np

import lagrange


def largest_swing(run):
    """max |θ| over the run (rad)."""
    return {"max_angle": float(np.max(np.abs(run.q[:, 0])))}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scheduler", help="address of a Dask scheduler (default: a LocalCluster)")
    parser.add_argument("--amplitudes", type=int, default=8, help="drive amplitudes on the grid")
    parser.add_argument("--frequencies", type=int, default=8, help="drive frequencies on the grid")
    parser.add_argument("--t-end", type=float, default=20.0, help="simulated time (s)")
    parser.add_argument("--csv", help="write the results here")
    args = parser.parse_args()

    pendulum = lagrange.scene("driven_pendulum")
    nominal = pendulum.parameters
    grid = {
        "amplitude": nominal["amplitude"] * np.linspace(0.25, 2.0, args.amplitudes),
        "drive_frequency": nominal["drive_frequency"] * np.linspace(0.5, 1.5, args.frequencies),
    }
    started = time.perf_counter()
    frame = lagrange.sweep(pendulum, grid=grid, t_end=args.t_end, method="dop853", tol=1e-10,
                           quantities=[largest_swing], client=args.scheduler)
    elapsed = time.perf_counter() - started
    where = args.scheduler or "a LocalCluster"
    print(f"{len(frame)} runs on {where} in {elapsed:.2f} s ({len(frame) / elapsed:.1f} runs/s); "
          f"{frame['error'].notna().sum()} failed")
    table = frame.pivot(index="amplitude", columns="drive_frequency", values="max_angle")
    print("largest |θ| (rad) by drive amplitude (rows) and frequency (columns):")
    print(table.round(3).to_string())
    if args.csv:
        frame.to_csv(args.csv, index=False)
        print(f"results: {args.csv}")


if __name__ == "__main__":
    main()
