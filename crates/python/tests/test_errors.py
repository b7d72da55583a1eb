"""Bad input raises a subclass of lagrange.Error with the command line's message for the same
request (the CLI names its flags, `--param`, `--q`; Python its arguments, `params`, `q`: the
rest of the message is the same text), and nothing panics."""

import math

import numpy as np
import pytest

import lagrange
from conftest import SCENES


def cli_message(cli, *args):
    code, _, stderr = cli(*args, check=False)
    assert code != 0
    return stderr.strip().removeprefix("error: ")


def test_unknown_scene(cli):
    with pytest.raises(lagrange.ArgumentError) as raised:
        lagrange.scene("no_such_scene")
    assert str(raised.value) == cli_message(cli, "accel", "no_such_scene")
    assert isinstance(raised.value, ValueError)


def test_nan_parameter(cli):
    with pytest.raises(lagrange.ArgumentError) as raised:
        lagrange.scene("double_pendulum").accelerations(params={"mass_1": math.nan})
    expected = cli_message(cli, "accel", "double_pendulum", "--param", "mass_1=NaN")
    assert str(raised.value).removeprefix("params: ") == expected.removeprefix("--param: ")
    with pytest.raises(lagrange.ArgumentError, match="unknown parameter"):
        lagrange.scene("double_pendulum").simulate(1.0, params={"mass": 1.0})


def test_wrong_array_length(cli):
    with pytest.raises(lagrange.ArgumentError) as raised:
        lagrange.scene("double_pendulum").accelerations(q=np.zeros(3))
    expected = cli_message(cli, "accel", "double_pendulum", "--q", "0,0,0")
    assert str(raised.value) == expected.removeprefix("--")
    with pytest.raises(lagrange.ArgumentError, match="one-dimensional"):
        lagrange.scene("double_pendulum").accelerations(q=np.zeros((2, 2)))


def test_non_finite_state_and_bad_settings():
    pendulum = lagrange.scene("double_pendulum")
    with pytest.raises(lagrange.ArgumentError, match="not finite"):
        pendulum.simulate(1.0, qdot=[math.inf, 0.0])
    with pytest.raises(lagrange.ArgumentError, match="tol does not apply to the rk4 method"):
        pendulum.simulate(1.0, method="rk4", tol=1e-6)
    with pytest.raises(lagrange.ArgumentError, match="unknown method `euler`"):
        pendulum.simulate(1.0, method="euler")
    with pytest.raises(lagrange.ArgumentError, match="must be positive"):
        pendulum.simulate(1.0, method="rk4", dt=-1e-3)
    with pytest.raises(lagrange.ArgumentError, match="unknown engine"):
        pendulum.compare(["bullet"])


def test_a_loop_that_cannot_assemble(cli):
    # A four-bar whose coupler is too short to reach the rocker from the crank's position.
    four_bar = lagrange.scene("four_bar")
    with pytest.raises(lagrange.ConstraintError) as raised:
        four_bar.simulate(0.1, q=[0.0, 0.0, 0.0], hold="θ2", params={"coupler": 0.05})
    expected = cli_message(cli, "simulate", "four_bar", "--t-end", "0.1", "--q", "0,0,0", "--hold", "θ2",
                           "--param", "coupler=0.05")
    assert str(raised.value) == expected
    assert isinstance(raised.value, lagrange.EngineError)


def test_a_graph_whose_loop_does_not_close():
    # Two cranks 1 m apart on the ground joined by a coupler of 3 m: no closed configuration.
    rod = lambda name: {"name": name, "mass": 1.0, "inertia": 0.1}
    pins = iter(range(4))
    pin = lambda parent, at_parent, child, at_child: {
        "name": f"pin{next(pins)}", "kind": "revolute", "parent": parent, "child": child,
        "parent_anchor": at_parent, "child_anchor": at_child,
    }
    graph = {
        "name": "open_loop",
        "gravity": 9.81,
        "bodies": [rod("left"), rod("coupler"), rod("right")],
        "joints": [
            pin("ground", [0.0, 0.0], "left", [0.0, 0.0]),
            pin("left", [1.0, 0.0], "coupler", [0.0, 0.0]),
            pin("coupler", [3.0, 0.0], "right", [1.0, 0.0]),
            pin("ground", [1.0, 0.0], "right", [0.0, 0.0]),
        ],
    }
    with pytest.raises(lagrange.GraphError, match="does not close"):
        lagrange.from_graph(graph, q=[0.5, 0.0, 0.0])


def test_a_malformed_scene_file(cli, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('version = 1\nid = "bad scene"\n')
    with pytest.raises(lagrange.FileError) as raised:
        lagrange.scene(bad)
    assert str(raised.value) == cli_message(cli, "simulate", bad, "--t-end", "1")
    with pytest.raises(lagrange.FileError, match="cannot read"):
        lagrange.scene(tmp_path / "missing.toml")


def test_a_drifting_run_raises_with_its_trajectory(cli):
    # RK4 at a step too long for the four-bar: its energy drifts 6 % (the command line's own
    # test of this check, crates/cli/tests/cli/outputs.rs).
    four_bar = lagrange.scene("four_bar")
    with pytest.raises(lagrange.UnhealthyRunError) as raised:
        four_bar.simulate(10.0, method="rk4", dt=0.05)
    expected = cli_message(cli, "simulate", "four_bar", "--t-end", "10", "--integrator", "rk4", "--dt", "0.05",
                           "--out", "/dev/null")
    # After the line saying where the samples went.
    expected = expected.split("\n")[-1].removeprefix("error: ")
    # The same findings and bound; the command line names its flags (--dt, --allow-drift).
    python = str(raised.value).replace("smaller dt, or allow_drift=True", "smaller --dt, or --allow-drift")
    assert python == expected
    assert raised.value.trajectory is not None and not raised.value.trajectory.healthy
    kept = four_bar.simulate(10.0, method="rk4", dt=0.05, allow_drift=True)
    assert kept.q.tolist() == raised.value.trajectory.q.tolist()


def test_no_panic_crosses_into_python():
    # Extreme but finite inputs: an error or a result, never a crash of the interpreter.
    pendulum = lagrange.scene("double_pendulum")
    for params in ({"mass_1": 1e-300, "mass_2": 1e-300}, {"length_1": 1e300}, {"gravity": 1e308}):
        try:
            pendulum.accelerations(params=params)
        except lagrange.Error:
            pass
