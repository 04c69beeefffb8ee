"""Shared fixtures of flapwing's Python tests: the `flapwing` binary that `cargo test` built."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def flapwing_bin() -> pathlib.Path:
    """Path of the release `flapwing` binary (FLAPWING_BIN, set by scripts/test)."""
    path = pathlib.Path(os.environ.get("FLAPWING_BIN", ROOT / "target" / "release" / "flapwing"))
    if not path.is_file():
        pytest.fail(f"no flapwing binary at {path}: run scripts/test (it builds it first)")
    return path


@pytest.fixture(scope="session")
def run_flapwing(flapwing_bin):
    """Runs the binary with arguments, returning the CompletedProcess (text mode)."""

    def run(*args, check=True, **kw):
        proc = subprocess.run([str(flapwing_bin), *map(str, args)], capture_output=True, text=True, **kw)
        if check and proc.returncode != 0:
            raise AssertionError(f"flapwing {' '.join(map(str, args))} exited {proc.returncode}: {proc.stderr}")
        return proc

    return run
