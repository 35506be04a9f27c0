"""Shared fixtures: location of the external PPDDL benchmark set (../shared)."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
BENCHMARKS = (REPO.parent / "shared" / "benchmarks" / "ppddl").resolve()


@pytest.fixture(scope="session")
def ppddl_benchmarks() -> Path:
    if not BENCHMARKS.is_dir():
        pytest.skip(f"PPDDL benchmark folder not found at {BENCHMARKS} "
                    "(expected ../shared/benchmarks/ppddl beside the checkout)")
    return BENCHMARKS
