"""Shared fixtures of flapwing's Python tests: the `flapwing` binary that `cargo test` built."""

import os
import pathlib
import subprocess
import tempfile

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session", autouse=True)
def _temporary_files_stay_in_the_session_folder(tmp_path_factory):
    """Every temporary file of the tests and of the processes they start (tempfile.mkstemp,
    mkdtemp, the Rust side's tempdir) goes into pytest's own temporary folder for the
    session, which pytest cleans, never loose into /tmp: TMPDIR is pointed there."""
    folder = tmp_path_factory.mktemp("tmp")
    old = os.environ.get("TMPDIR")
    os.environ["TMPDIR"] = str(folder)
    tempfile.tempdir = None  # re-read TMPDIR
    yield folder
    if old is None:
        os.environ.pop("TMPDIR", None)
    else:
        os.environ["TMPDIR"] = old
    tempfile.tempdir = None


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
