"""Shared fixtures: the repository's sample data, the built `pushlab` CLI, and copies to edit."""

import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
SAMPLE = REPO / "sample-data"
# The set the tests train and evaluate on: 27 offline and 9 online pushes of a box with a known COM.
SET = SAMPLE / "box1-paper-center-front"
MIT = REPO.parent / "shared" / "mit-push"


@pytest.fixture(scope="session")
def cli() -> Path:
    """The CLI binary scripts/test builds (`cargo test` builds it for the CLI tests)."""
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    binary = target / "debug" / "pushlab"
    if not binary.is_file():
        pytest.fail(f"{binary} is missing: build it with `cargo build` (scripts/test does)")
    return binary


def run_cli(cli: Path, *args: str) -> subprocess.CompletedProcess:
    """Runs the CLI, failing the test with its output when it fails."""
    done = subprocess.run([str(cli), *args], capture_output=True, text=True)
    assert done.returncode == 0, f"pushlab {' '.join(args)} failed:\n{done.stdout}\n{done.stderr}"
    return done


@pytest.fixture
def set_copy(tmp_path: Path) -> Path:
    """A copy of the sample set that a test may label and break."""
    copy = tmp_path / SET.name
    shutil.copytree(SET, copy)
    return copy
