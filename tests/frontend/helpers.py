"""Shared helpers for the front-end tests."""

from __future__ import annotations

import argparse
import contextlib
import io
import os
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = ("cluttered_table", "domino", "keva", "aircraft_inspection", "warehouse", "kitchen")


def run_command(module, argv: list[str], cwd: Path = REPO) -> tuple[int, str, str]:
    """Run a ``stampc.commands`` module in-process; returns (exit code, stdout, stderr)."""
    parser = argparse.ArgumentParser()
    module.add_arguments(parser)
    args = parser.parse_args(argv)
    out, err = io.StringIO(), io.StringIO()
    old = Path.cwd()
    os.chdir(cwd)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = module.run(args)
    finally:
        os.chdir(old)
    return code, out.getvalue(), err.getvalue()
