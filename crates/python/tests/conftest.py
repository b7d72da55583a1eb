"""Shared fixtures: the command line under test (LAGRANGE_BIN, set by crates/cli/tests/cli/python.rs;
target/debug/lagrange when run by hand), whose numbers the bindings must reproduce."""

import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]
SCENES = ROOT / "examples" / "scenes"


def _binary() -> str:
    binary = os.environ.get("LAGRANGE_BIN") or str(ROOT / "target" / "debug" / "lagrange")
    if not os.path.exists(binary):
        raise RuntimeError(f"no lagrange binary at {binary}: set LAGRANGE_BIN (cargo test sets it)")
    return binary


@pytest.fixture(scope="session")
def cli():
    """Run the command line; returns (exit code, stdout, stderr)."""

    def run(*args, check=True):
        done = subprocess.run([_binary(), *map(str, args)], capture_output=True, text=True)
        if check and done.returncode != 0:
            raise AssertionError(f"lagrange {' '.join(map(str, args))} failed:\n{done.stderr}")
        return done.returncode, done.stdout, done.stderr

    return run


@pytest.fixture(scope="session")
def cli_json(cli):
    """Run the command line with --json and parse what it prints."""

    def run(*args):
        return json.loads(cli(*args, "--json")[1])

    return run
