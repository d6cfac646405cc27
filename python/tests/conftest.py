"""Shared fixtures: the repository's scenes and the `sprung` command the
Python runs are compared with."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes"


def sprung_command():
    """The `sprung` binary: $SPRUNG_BIN (scripts/test.sh sets it), else the
    workspace's build, else the one on the PATH."""
    given = os.environ.get("SPRUNG_BIN")
    if given:
        return given
    for profile in ("debug", "release"):
        candidate = REPO / "target" / profile / "sprung"
        if candidate.is_file():
            return str(candidate)
    found = shutil.which("sprung")
    if found is None:
        pytest.skip("no sprung binary (build it with cargo build -p sprung-cli)")
    return found


@pytest.fixture(scope="session")
def cli():
    """Run `sprung ARGS...`, failing the test on a non-zero exit."""
    binary = sprung_command()

    def run(*args):
        done = subprocess.run([binary, *map(str, args)], capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        return done
    return run


@pytest.fixture(scope="session")
def scenes():
    return SCENES
