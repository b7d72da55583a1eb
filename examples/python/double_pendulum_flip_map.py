"""The double pendulum's flip-time map: released at rest from every pair of initial angles
(θ1, θ2) on a grid, how long until either arm flips over the top (|θ| passes π)?

Each grid point is one run of ``--t-end`` seconds sampled every ``--every`` seconds; the flip
time is the first sample at which |θ1| or |θ2| exceeds π (none within the run: white). Starts
with too little energy to flip (3 cos θ1 + cos θ2 > 2 for equal masses and lengths) are the
white region around the origin, whatever the run. The grid runs as one Dask sweep. Writes the
map to ``--out``.

    .venv/bin/python examples/python/double_pendulum_flip_map.py --size 200
"""

import argparse

import numpy as np

import lagrange


def flip_time(run):
    """The first sample time at which either arm has gone over the top; NaN if none did."""
    over = np.any(np.abs(run.q) > np.pi, axis=1)
    return {"flip_time": float(run.t[np.argmax(over)]) if over.any() else float("nan")}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", type=int, default=100, help="grid points per angle")
    parser.add_argument("--t-end", type=float, default=10.0, help="simulated time (s)")
    parser.add_argument("--every", type=float, default=0.01, help="sampling interval (s)")
    parser.add_argument("--scheduler", help="address of a Dask scheduler (default: a LocalCluster)")
    parser.add_argument("--out", default="double_pendulum_flip_map.png", help="the map (PNG)")
    args = parser.parse_args()

    angles = np.linspace(-3.0, 3.0, args.size)
    frame = lagrange.sweep(
        "double_pendulum", grid={"q[0]": angles, "q[1]": angles}, qdot=[0.0, 0.0],
        t_end=args.t_end, method="dop853", tol=1e-10,
        quantities=[flip_time, "energy_drift"], client=args.scheduler,
    )
    failed = frame["error"].notna().sum()
    times = frame["flip_time"].to_numpy().reshape(args.size, args.size)
    flipped = np.isfinite(times)
    print(f"{args.size}×{args.size} starts, {failed} failed; {flipped.sum()} flip within {args.t_end} s; "
          f"largest relative energy drift {frame['energy_drift'].max():.1e}")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    fig, ax = plt.subplots(figsize=(6.5, 5.5))
    image = ax.imshow(
        times.T, origin="lower", extent=(angles[0], angles[-1], angles[0], angles[-1]),
        norm=LogNorm(vmin=max(args.every, 0.1), vmax=args.t_end), cmap="viridis_r",
    )
    fig.colorbar(image, label="time to the first flip (s)")
    ax.set_xlabel("initial θ1 (rad)")
    ax.set_ylabel("initial θ2 (rad)")
    ax.set_title("Double pendulum: time to flip")
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"map: {args.out}")


if __name__ == "__main__":
    main()
