"""Shared fixtures: the rgc command line, to compare the module against."""

import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli():
    """Runs the rgc binary (``RGC_BIN``, or the release build) and returns its stdout."""
    binary = Path(os.environ.get("RGC_BIN", ROOT / "target" / "release" / "rgc"))
    if not binary.is_file():
        pytest.fail(f"{binary} is missing: build it with `cargo build --release` (.ci/run does)")

    def run(*args, cwd=None):
        out = subprocess.run([str(binary), *map(str, args)], capture_output=True, text=True, cwd=cwd)
        if out.returncode != 0:
            raise AssertionError(f"rgc {' '.join(map(str, args))}: {out.stderr}")
        return out.stdout

    return run


@pytest.fixture(scope="session")
def root():
    return ROOT
