"""Sweeps on Dask equal the serial loop over the same points, bit for bit, failures included."""

import math

import numpy as np
import pandas as pd
import pytest
from distributed import Client, LocalCluster

import lagrange


@pytest.fixture(scope="module")
def client():
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        with Client(cluster) as client:
            yield client


def swing(run):
    """The largest |θ2| of the run: a function of the trajectory, shipped to the workers."""
    return float(np.max(np.abs(run.q[:, 1])))


GRID = {"q[0]": [0.3, 1.2, 2.5], "mass_2": [0.5, 2.0, -1.0]}  # mass_2 = −1 fails


def serial(scene, point):
    """The same point by hand: a direct call, no sweep code."""
    q = list(scene.default_state().q)
    q[0] = point["q[0]"]
    try:
        run = scene.simulate(2.0, method="dop853", tol=1e-11, q=q, params={"mass_2": point["mass_2"]})
    except lagrange.Error as error:
        return {"error": str(error), "error_type": type(error).__name__}
    h = run.energy
    return {
        "q_end.θ1": run.q[-1, 0], "q_end.θ2": run.q[-1, 1],
        "qdot_end.θ1": run.qdot[-1, 0], "qdot_end.θ2": run.qdot[-1, 1],
        "energy_drift": float(np.max(np.abs(h - h[0])) / abs(h[0])),
        "swing": swing(run),
        "error": None, "error_type": None,
    }


def test_sweep_on_two_workers_equals_the_serial_loop(client):
    scene = lagrange.scene("double_pendulum")
    progress = []
    frame = lagrange.sweep(
        scene, grid=GRID, t_end=2.0, method="dop853", tol=1e-11,
        quantities=["final_state", "energy_drift", swing], client=client, chunk_size=2,
        progress=lambda done, total: progress.append((done, total)),
    )
    points = [{"q[0]": a, "mass_2": m} for a in GRID["q[0]"] for m in GRID["mass_2"]]
    assert len(frame) == len(points) == 9
    assert progress[-1] == (9, 9) and len(progress) == 5  # five chunks of at most two points
    for (_, row), point in zip(frame.iterrows(), points):
        assert row["q[0]"] == point["q[0]"] and row["mass_2"] == point["mass_2"]
        expected = serial(scene, point)
        for key, value in expected.items():
            got = row[key]
            if value is None:
                assert got is None or (isinstance(got, float) and math.isnan(got)), (point, key)
            else:
                assert got == value, (point, key, got, value)  # bit for bit
        if point["mass_2"] < 0:
            assert row["error_type"] == "ArgumentError" and "mass_2" in row["error"]
            assert all(math.isnan(row[k]) for k in ("q_end.θ1", "swing"))
        assert row["wall_time"] > 0


def test_samples_as_a_frame_and_by_coordinate_name(client):
    four_bar = lagrange.scene("four_bar")
    rng = np.random.default_rng(7)
    samples = pd.DataFrame({"crank": 0.2 + 1e-3 * rng.standard_normal(6), "rocker": 0.5 + 1e-3 * rng.standard_normal(6)})
    frame = lagrange.sweep(four_bar, samples=samples, t_end=0.5, quantities=["final_q", "violation"], client=client)
    assert list(frame["crank"]) == list(samples["crank"])
    for (_, row), (_, point) in zip(frame.iterrows(), samples.iterrows()):
        run = four_bar.simulate(0.5, params={"crank": point["crank"], "rocker": point["rocker"]})
        assert row["q_end.θ4"] == run.q[-1, 2] and row["violation"] == run.max_violation()
    # The initial state by coordinate name, with hold for the loop.
    by_name = lagrange.sweep(
        four_bar, grid={"q.θ2": [0.9, 1.1]}, hold="θ2", t_end=0.2, quantities="final_q", client=client
    )
    assert by_name["error"].isna().all()
    start = four_bar.initial_state(q=[1.1, *four_bar.default_state().q[1:]], hold="θ2")
    assert by_name["q_end.θ2"].iloc[1] == four_bar.simulate(0.2, q=start.q, qdot=start.qdot).q[-1, 0]


def test_sweep_rejects_bad_requests_before_running(client):
    scene = lagrange.scene("double_pendulum")
    with pytest.raises(lagrange.ArgumentError, match="grid or samples"):
        lagrange.sweep(scene, t_end=1.0, client=client)
    with pytest.raises(lagrange.ArgumentError, match="unknown quantity"):
        lagrange.sweep(scene, grid={"mass_1": [1.0]}, t_end=1.0, quantities=["nope"], client=client)


def test_default_cluster_runs_a_sweep():
    # No client: a LocalCluster with a worker per core, opened and closed by the sweep.
    oscillator = lagrange.scene("harmonic_oscillator")
    assert oscillator.parameters["mass"] == 1.0 and oscillator.parameters["damping"] == 0.0
    x0 = oscillator.default_state().q[0]
    assert oscillator.default_state().qdot[0] == 0.0
    frame = lagrange.sweep(oscillator, grid={"stiffness": [1.0, 4.0]}, t_end=math.pi, quantities="final_q")
    # x(t) = x₀ cos(√k t) from rest (mass 1, no damping): at t = π, x₀ cos π = −x₀, x₀ cos 2π = x₀;
    # dopri5 at its default tolerance 1e-10 over about 100 steps: 1e-8 relative with margin.
    np.testing.assert_allclose(frame["q_end.x"], [-x0, x0], rtol=1e-8)
