"""Fixtures for running the installed ``stampc`` console script as a user would.

The script is the one installed beside the running interpreter (``pip install -e .``
puts it there), else the first ``stampc`` on ``PATH``; a missing script is a test
failure, not a skip. Each run starts in a fresh temporary directory outside the
repository, so the current directory is not on ``sys.path`` and ``examples`` is not
importable: exactly a user's situation. ``PYTHONPATH`` names a folder holding only a
``stampc`` symlink to this checkout's package, so that the script runs the code under
test even when another checkout is the one installed.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from .paths import EXAMPLES, REPO


def console_script() -> Path:
    beside = Path(sys.executable).parent / "stampc"
    if beside.is_file():
        return beside
    found = shutil.which("stampc")
    if found is None:
        pytest.fail("the `stampc` console script is not installed (looked beside "
                    f"{sys.executable} and on PATH); run `pip install -e .` first")
    return Path(found)


@dataclass(frozen=True)
class Result:
    code: int
    out: str
    err: str


@dataclass(frozen=True)
class Cli:
    """Runs ``stampc ARGS`` (or a Python script) in ``cwd`` with the checkout's package."""

    script: Path
    env: dict

    def run(self, *args: str, cwd: Path, timeout: float = 300) -> Result:
        done = subprocess.run([str(self.script), *args], cwd=cwd, env=self.env,
                              capture_output=True, text=True, timeout=timeout)
        return Result(done.returncode, done.stdout, done.stderr)

    def python(self, script: Path, cwd: Path, timeout: float = 300) -> Result:
        done = subprocess.run([sys.executable, str(script)], cwd=cwd, env=self.env,
                              capture_output=True, text=True, timeout=timeout)
        return Result(done.returncode, done.stdout, done.stderr)


@pytest.fixture(scope="session")
def cli(tmp_path_factory) -> Cli:
    site = tmp_path_factory.mktemp("site")
    (site / "stampc").symlink_to(REPO / "stampc", target_is_directory=True)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(site)
    env["MPLBACKEND"] = "Agg"
    return Cli(console_script(), env)


@pytest.fixture()
def checkout(tmp_path) -> Path:
    """A folder outside the repository holding a copy of ``examples/`` (a fresh clone's
    layout for the README's relative paths); run commands from it."""
    root = tmp_path / "clone"
    shutil.copytree(EXAMPLES, root / "examples",
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    return root


@pytest.fixture()
def elsewhere(tmp_path) -> Path:
    """An empty working directory outside the repository (for absolute paths)."""
    folder = tmp_path / "elsewhere"
    folder.mkdir()
    return folder
