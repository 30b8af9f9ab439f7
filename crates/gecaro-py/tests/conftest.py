"""Shared fixtures of the gecaro Python tests.

The tests compare the package with the command line: ``GECARO_CLI`` names the
``gecaro`` binary (default: the workspace's ``target/debug/gecaro``, which
``crates/gecaro-py/test.sh`` builds first). Without it the comparisons fail
rather than skip: they are the point of the suite.
"""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest

REPOSITORY = Path(__file__).resolve().parents[3]


def cli_path() -> Path:
    return Path(os.environ.get("GECARO_CLI", REPOSITORY / "target" / "debug" / "gecaro"))


class Cli:
    """Runs the ``gecaro`` command line."""

    def __init__(self, binary: Path, cwd: Path) -> None:
        if not binary.is_file():
            raise RuntimeError(
                f"the gecaro binary {binary} is missing: build it with "
                "`cargo build --bin gecaro` or set GECARO_CLI"
            )
        self.binary = binary
        self.cwd = cwd

    def run(self, *args: object, expect: int = 0) -> subprocess.CompletedProcess[str]:
        done = subprocess.run(
            [str(self.binary), *map(str, args)],
            cwd=self.cwd,
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert done.returncode == expect, (
            f"gecaro {' '.join(map(str, args))} exited {done.returncode}, expected {expect}\n"
            f"stdout: {done.stdout}\nstderr: {done.stderr}"
        )
        return done

    def json(self, *args: object, expect: int = 0) -> dict:
        return json.loads(self.run(*args, "--json", expect=expect).stdout)


@pytest.fixture
def cli(tmp_path: Path) -> Cli:
    return Cli(cli_path(), tmp_path)


@pytest.fixture(scope="session")
def repository() -> Path:
    return REPOSITORY
