"""Shared fixtures of the Python tests: the repository's folders and the stiffmsa command they
compare against (STIFFMSA_CLI, as scripts/test.sh sets it; else build/stiffmsa)."""

import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


@pytest.fixture(scope="session")
def cli() -> Path:
    path = Path(os.environ.get("STIFFMSA_CLI", ROOT / "build" / "stiffmsa"))
    if not os.access(path, os.X_OK):
        pytest.fail(f"the stiffmsa command is not at {path}; build it (cmake --build build) or set STIFFMSA_CLI")
    return path


def run_cli(cli: Path, *args, check: bool = True) -> subprocess.CompletedProcess:
    """Runs the stiffmsa command; `check` demands exit code 0."""
    completed = subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True)
    if check and completed.returncode != 0:
        raise AssertionError(f"stiffmsa {' '.join(map(str, args))} failed ({completed.returncode}):\n{completed.stderr}")
    return completed
