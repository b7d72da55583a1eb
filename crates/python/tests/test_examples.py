"""The studies in examples/python run, small: each on a LocalCluster of its own, and the
parameter sweep once more against the scheduler address of a cluster started here (what
`--scheduler tcp://…` does on a real cluster)."""

import subprocess
import sys

import pytest
from distributed import LocalCluster

from conftest import ROOT

EXAMPLES = ROOT / "examples" / "python"


def run(script, *args, cwd):
    done = subprocess.run([sys.executable, EXAMPLES / script, *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, timeout=300)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_four_bar_tolerance(tmp_path):
    out = run("four_bar_tolerance.py", "--samples", 24, "--t-end", 0.5, "--out", "h.png", cwd=tmp_path)
    assert "24 of 24 samples ran" in out
    assert (tmp_path / "h.png").stat().st_size > 10_000


def test_double_pendulum_flip_map(tmp_path):
    out = run("double_pendulum_flip_map.py", "--size", 5, "--t-end", 3, "--out", "map.png", cwd=tmp_path)
    assert "5×5 starts, 0 failed" in out
    assert (tmp_path / "map.png").stat().st_size > 10_000


def test_parameter_sweep_on_a_cluster_given_by_address(tmp_path):
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        out = run("parameter_sweep.py", "--scheduler", cluster.scheduler_address, "--amplitudes", 3,
                  "--frequencies", 2, "--t-end", 2, "--csv", "sweep.csv", cwd=tmp_path)
    assert f"6 runs on {cluster.scheduler_address}" in out and "0 failed" in out
    local = run("parameter_sweep.py", "--amplitudes", 3, "--frequencies", 2, "--t-end", 2, cwd=tmp_path)
    assert "6 runs on a LocalCluster" in local
    # The same table either way.
    assert out.split("(rad) by drive")[1].split("results:")[0].strip() == local.split("(rad) by drive")[1].strip()
