"""A shelf (plane2d) problem refined once per session into a temporary folder: fully
(``full``) and to half coverage (``partial``: the crushed branches stay unrefined)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from stampc.cli import main

REPO = Path(__file__).resolve().parents[2]
SHELF = REPO / "examples" / "shelf2d"


def refine(folder: Path, out: str, *extra: str) -> Path:
    code = main(["refine", str(folder / "domain.stamp"), str(folder / "problem.stamp"),
                 "--world", "plane2d", "--seed", "0", "--quiet", "-o", str(folder / out),
                 *extra])
    assert code == 0
    return folder / out / "policy.json"


@pytest.fixture(scope="session")
def shelf(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("shelf")
    for name in ("domain.stamp", "problem.stamp"):
        shutil.copy(SHELF / name, folder / name)
    refine(folder, "full")
    refine(folder, "partial", "--target-coverage", "0.5")
    return folder
