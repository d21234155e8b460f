"""Shared fixtures: the repository's sample and the `omnicloud` command line built by
`cargo build`/`cargo test` (the CLI the Python renders are compared with)."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "data" / "autzen_trim.laz"


def cli_path():
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return target / "debug" / "omnicloud"


@pytest.fixture(scope="session")
def cli():
    """Runs `omnicloud ARGS...` and fails the test with its stderr when it fails."""
    exe = cli_path()
    if not exe.exists():
        pytest.fail(f"{exe} is missing: build the CLI first (cargo build)")

    def run(*args):
        done = subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        return done

    return run


@pytest.fixture(scope="session")
def sample():
    import omnicloud

    return omnicloud.read(SAMPLE)
