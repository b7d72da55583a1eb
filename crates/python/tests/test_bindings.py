"""Every binding against the command line's numbers for the same request (the command line is
the Rust API's front end: same engine, same defaults), and against closed forms where the
command line prints nothing to compare with. Equal means bit for bit unless a comment says
why not."""

import csv
import io
import math
import pickle
import threading

import numpy as np
import pytest

import lagrange
from conftest import SCENES


def read_csv(text):
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], np.array([[float(v) for v in row] for row in rows[1:]])


def test_scene_ids_are_the_command_lines(cli_json):
    assert lagrange.scenes() == [s["id"] for s in cli_json("scenes")]


def test_scene_describes_itself(cli_json):
    listed = {s["id"]: s for s in cli_json("scenes")}
    for id in lagrange.scenes():
        scene = lagrange.scene(id)
        assert scene.id == id
        assert scene.title == listed[id]["title"]
        assert scene.coordinates() == [c["name"] for c in listed[id]["coordinates"]]
        assert scene.parameters == {p["name"]: p["default"] for p in listed[id]["parameters"]}


@pytest.mark.parametrize(
    "id, args, kwargs",
    [
        ("double_pendulum", ["--integrator", "dop853", "--tol", "1e-12"], dict(method="dop853", tol=1e-12)),
        ("four_bar", ["--integrator", "rk4", "--dt", "1e-3"], dict(method="rk4", dt=1e-3)),
        ("harmonic_oscillator", ["--integrator", "sdirk4", "--param", "damping=0.3"],
         dict(method="sdirk4", params={"damping": 0.3})),
        ("kepler", ["--integrator", "variational", "--dt", "1e-3", "--q", "1.2,0.1", "--qdot", "0,0.9"],
         dict(method="variational", dt=1e-3, q=[1.2, 0.1], qdot=np.array([0.0, 0.9]))),
    ],
)
def test_simulate_equals_the_command_line(cli, id, args, kwargs):
    _, out, _ = cli("simulate", id, "--t-end", "1.5", *args)
    header, table = read_csv(out)
    run = lagrange.scene(id).simulate(1.5, **kwargs)
    n = len(run.coordinates)
    assert table.shape == (len(run.t), 2 * n + 2 + (0 if run.violation is None else 2))
    # The CSV writes t to 15 significant digits (a sample time carries the rounding of k·Δ).
    np.testing.assert_allclose(run.t, table[:, 0], rtol=1e-14, atol=0)
    # Every other number in its shortest form that reads back to the same f64: exact.
    assert np.array_equal(run.q, table[:, 1 : 1 + n])
    assert np.array_equal(run.qdot, table[:, 1 + n : 1 + 2 * n])
    assert np.array_equal(run.energy, table[:, 1 + 2 * n])
    if run.violation is not None:
        assert np.array_equal(run.violation, table[:, 2 + 2 * n :])
    # Checked against what the scene declares: nothing for the damped oscillator.
    assert run.healthy and bool(run.health["checked"]) == (id != "harmonic_oscillator")
    frame = run.to_pandas()
    assert list(frame.columns)[: 1 + n] == ["t", *run.coordinates] and len(frame) == len(run.t)
    assert frame["h"].to_numpy().tolist() == run.energy.tolist()


def test_simulate_at_given_times_and_intervals():
    pendulum = lagrange.scene("double_pendulum")
    times = [0.0, 0.25, 0.5, 1.0]
    run = pendulum.simulate(1.0, times=times, method="dop853")
    assert run.t.tolist() == times and run.q.shape == (4, 2)
    every = pendulum.simulate(1.0, every=0.1, method="rk4", dt=0.01)
    assert len(every.t) == 11
    np.testing.assert_allclose(every.t, np.linspace(0, 1, 11), atol=1e-15)


def test_accelerations_equal_the_command_line(cli_json):
    for id in lagrange.scenes():
        expected = cli_json("accel", id)
        scene = lagrange.scene(id)
        qddot = scene.accelerations()
        assert qddot.tolist() == expected["qddot"], id
        closed = scene.closed_form_accelerations()
        assert (None if closed is None else closed.tolist()) == expected["closed_form"], id
    # At a given state and parameters.
    expected = cli_json("accel", "four_bar", "--param", "crank=0.25", "--q", "1.0,0.5,1.3", "--hold", "θ2")
    four_bar = lagrange.scene("four_bar")
    start = four_bar.initial_state(q=[1.0, 0.5, 1.3], hold="θ2", params={"crank": 0.25})
    assert start.q.tolist() == expected["q"]
    assert four_bar.accelerations(start.q, start.qdot, params={"crank": 0.25}).tolist() == expected["qddot"]


def test_mass_matrix_and_energy_of_the_double_pendulum_are_its_closed_forms():
    # Point masses m1, m2 on rods l1, l2 (inertias 0 by default):
    # M = [[(m1 + m2) l1², m2 l1 l2 cos(θ1 − θ2)], [·, m2 l2²]],
    # h = ½ q̇ᵀ M q̇ − (m1 + m2) g l1 cos θ1 − m2 g l2 cos θ2.
    m1, m2, l1, l2, g = 1.3, 0.7, 0.9, 1.1, 9.81
    params = {"mass_1": m1, "mass_2": m2, "length_1": l1, "length_2": l2, "gravity": g}
    q, qdot = np.array([0.4, -1.2]), np.array([0.3, 2.0])
    pendulum = lagrange.scene("double_pendulum")
    c = math.cos(q[0] - q[1])
    expected = np.array([[(m1 + m2) * l1**2, m2 * l1 * l2 * c], [m2 * l1 * l2 * c, m2 * l2**2]])
    # Exact formulas evaluated in a different order: a few ulps apart.
    # The engine sums body terms (m₂ l₁ l₂ (cos θ₁ cos θ₂ + sin θ₁ sin θ₂) off the diagonal): its
    # rounding is relative to the terms, the entries' scale, not to their difference.
    scale = np.max(np.abs(expected))
    np.testing.assert_allclose(pendulum.mass_matrix(q, params=params), expected, rtol=0,
                               atol=8 * np.finfo(float).eps * scale)
    h = 0.5 * qdot @ expected @ qdot - (m1 + m2) * g * l1 * math.cos(q[0]) - m2 * g * l2 * math.cos(q[1])
    assert pendulum.energy(q, qdot, params=params) == pytest.approx(h, rel=16 * np.finfo(float).eps)


def test_multipliers_and_reactions_of_the_nonminimal_pendulum_are_the_rod_tension():
    # A particle on a rod of length l written in (x, y) with x² + y² = l²: the rod's pull is
    # m (g cos θ + v²/l) along it, θ from the downward vertical.
    pendulum = lagrange.scene("nonminimal_pendulum")
    m, l, g = (pendulum.parameters[k] for k in ("mass", "length", "gravity"))
    theta, omega = 0.7, 1.9
    q = [l * math.sin(theta), -l * math.cos(theta)]
    qdot = [l * omega * math.cos(theta), l * omega * math.sin(theta)]
    tension = m * (g * math.cos(theta) + l * omega**2)
    lam = pendulum.multipliers(q, qdot)
    assert lam is not None and lam.shape == (1,)
    assert pendulum.reactions(q, qdot) is None or pendulum.reactions(q, qdot).shape[1] == 3
    M = pendulum.mass_matrix(q)
    f_applied = np.array([0.0, -m * g])
    qddot = pendulum.accelerations(q, qdot)
    constraint_force = M @ qddot - f_applied  # = −Gᵀλ, the rod's force on the particle
    assert np.linalg.norm(constraint_force) == pytest.approx(tension, rel=1e-13)
    # It points from the particle to the pivot.
    assert np.dot(constraint_force, q) < 0
    assert lagrange.scene("double_pendulum").multipliers() is None


def test_multiplier_rank_says_when_the_multipliers_are_not_unique():
    # The parallelogram with a third crank: one of its loop rows is redundant everywhere.
    redundant = lagrange.scene("redundant_parallelogram").multiplier_rank()
    assert redundant is not None and redundant["unique"] is False
    assert redundant["rows"] - redundant["determined"] == 1 and redundant["conditioning"] < 1e-14
    # The chain of 4 parallelogram windows (its default): unique swinging, 4 of its 8 rows
    # dependent laid flat.
    chain = lagrange.scene("parallelogram_chain")
    assert chain.multiplier_rank()["unique"] is True
    flat = chain.multiplier_rank(q=[0.0] * 9, qdot=[6.0, -6.0] * 4 + [6.0])
    assert (flat["rows"], flat["determined"], flat["unique"]) == (8, 4, False)
    assert lagrange.scene("double_pendulum").multiplier_rank() is None


def test_reactions_of_the_double_pendulum_are_newtons():
    # Each bob is a point mass: the constraint force on it is m a − m g, with a its
    # acceleration from (q, q̇, q̈): x₁ = l₁ sin θ₁, y₁ = −l₁ cos θ₁, x₂ = x₁ + l₂ sin θ₂, …
    # An independent formulation (Newton's) of the same motion; the rows come back per body.
    pendulum = lagrange.scene("double_pendulum")
    p = pendulum.parameters
    m, l, g = (p["mass_1"], p["mass_2"]), (p["length_1"], p["length_2"]), p["gravity"]
    q, qdot = np.array([0.8, -0.4]), np.array([1.5, -2.0])
    qddot = pendulum.accelerations(q, qdot)
    # Acceleration of the end of rod k relative to its start.
    rel = [
        l[k] * np.array([
            math.cos(q[k]) * qddot[k] - math.sin(q[k]) * qdot[k] ** 2,
            math.sin(q[k]) * qddot[k] + math.cos(q[k]) * qdot[k] ** 2,
        ])
        for k in range(2)
    ]
    accelerations = [rel[0], rel[0] + rel[1]]
    reactions = pendulum.reactions(q, qdot)
    assert reactions.shape == (2, 3) and len(pendulum.bodies()) == 2
    scale = max(m) * (g + max(l) * np.max(qdot) ** 2)
    for k in range(2):
        expected = m[k] * accelerations[k] - np.array([0.0, -m[k] * g])
        # Round-off of two exact formulations, relative to the forces' size.
        np.testing.assert_allclose(reactions[k, :2], expected, rtol=0, atol=1e-13 * scale)


def test_compare_equals_the_command_line(cli_json):
    expected = cli_json("compare", "four_bar", "--engine", "all", "--t-end", "0.5")
    rows = lagrange.scene("four_bar").compare(t_end=0.5)
    assert [r["engine"] for r in rows] == [r["engine"] for r in expected["rows"]]
    for row, want in zip(rows, expected["rows"]):
        if want["unbuildable"]:
            assert row["unbuildable"] == want["unbuildable"]
            continue
        for key in ("max_error", "final_error", "energy_drift", "constraint_violation", "force_error", "steps"):
            assert row[key] == want[key], (row["engine"], key)
        assert row["reference"] == want["reference"]


def test_modes_equal_the_command_line(cli_json):
    expected = cli_json("modes", "double_pendulum")
    modes = lagrange.scene("double_pendulum").modes()
    assert modes["equilibrium"].tolist() == expected["equilibrium"]
    assert modes["mass_matrix"].ravel().tolist() == expected["mass_matrix"]
    assert [m["omega"] for m in modes["modes"]] == [m["omega"] for m in expected["modes"]]
    assert [m["shape"].tolist() for m in modes["modes"]] == [m["shape"] for m in expected["modes"]]


def test_eom_equals_the_command_line(cli, cli_json):
    path = str(SCENES / "double_pendulum.toml")
    equations = lagrange.scene(path).eom()
    assert dict(equations) == cli_json("eom", path)
    assert str(equations) == cli("eom", path)[1].rstrip("\n")
    assert equations.latex.rstrip("\n") == cli("eom", path, "--latex")[1].rstrip("\n")
    # A built-in joint graph too.
    assert dict(lagrange.scene("andrews_squeezer").eom()) == cli_json("eom", "andrews_squeezer")


def test_a_scene_file_and_a_joint_graph(cli):
    path = SCENES / "four_bar.toml"
    from_file = lagrange.scene(path)
    assert from_file.simulate(0.5).q.shape[1] == len(from_file.coordinates())
    graph = {
        "name": "python_pendulum",
        "gravity": 9.81,
        "bodies": [{"name": "bob", "mass": 2.0, "inertia": 0.0}],
        "joints": [{"name": "pivot", "kind": "revolute", "parent": "ground", "child": "bob",
                    "parent_anchor": [0.0, 0.0], "child_anchor": [0.0, 1.5]}],
    }
    try:
        pendulum = lagrange.from_graph(graph, q=[0.4])
    except lagrange.GraphError as e:
        pytest.fail(f"the graph's serde form changed: {e}")
    run = pendulum.simulate(2.0, method="dop853", tol=1e-12)
    # Small-angle check is not exact; the energy is.
    assert run.energy_drift() < 1e-10
    # The same graph again is the same scene; pickled, it is rebuilt from its description.
    assert lagrange.from_graph(graph, q=[0.4]).id == "python_pendulum"
    again = pickle.loads(pickle.dumps(pendulum))
    assert again.simulate(2.0, method="dop853", tol=1e-12).q.tolist() == run.q.tolist()


def test_threads_run_in_parallel_and_agree():
    # The GIL is released during runs: results from threads equal the serial ones.
    scene = lagrange.scene("double_pendulum")
    angles = [0.1 * k for k in range(8)]
    serial = [scene.simulate(3.0, q=[a, 0.0], method="dop853").q[-1].tolist() for a in angles]
    results = [None] * len(angles)

    def work(k):
        results[k] = scene.simulate(3.0, q=[angles[k], 0.0], method="dop853").q[-1].tolist()

    threads = [threading.Thread(target=work, args=(k,)) for k in range(len(angles))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert results == serial


def test_the_gil_is_released_during_a_run():
    # While a long run goes on in a thread, this thread runs Python: with the GIL held by the
    # run, it could not count at all until the run returned.
    chain = lagrange.scene("chain")
    started, counted = threading.Event(), 0

    def work():
        started.set()
        chain.simulate(200.0, method="dop853", tol=1e-12, every=10.0)

    worker = threading.Thread(target=work)
    worker.start()
    started.wait()
    while worker.is_alive():
        counted += 1
    worker.join()
    assert counted > 10_000


def test_ctrl_c_stops_a_long_run():
    # A run of ten simulated hours (about 16 s of wall time) interrupted by SIGINT from another
    # thread a moment after it starts: KeyboardInterrupt, as for any Python code, not a wait
    # until the run returns.
    import os
    import signal

    chain = lagrange.scene("chain")
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            chain.simulate(36000.0, method="dop853", tol=1e-12, every=600.0)
    finally:
        timer.cancel()


def test_report_is_the_command_lines(cli, tmp_path):
    cli("report", "--quick", "--scene", "harmonic_oscillator", "--jobs", "1", "--out", tmp_path / "cli")
    import json

    expected = json.loads((tmp_path / "cli" / "report.json").read_text())
    report = lagrange.report(["harmonic_oscillator"], quick=True, jobs=1, out=tmp_path / "py")
    assert (tmp_path / "py" / "report.md").exists()
    assert [s["scene"] for s in report["scenes"]] == ["harmonic_oscillator"]
    # Errors and step counts are deterministic; wall times are not.
    def measured(r):
        return [
            (m["method"], m["status"], [(run["settings"], run["status"], run["max_error"], run["final_error"],
                                         run["energy_error"], run["steps"]) for run in m["runs"]])
            for s in r["scenes"] for m in s["methods"]
        ]

    assert measured(report) == measured(expected)
    assert report["stability"]["failed"] == 0 and report["stability"]["passed"] == expected["stability"]["passed"]
