"""Refine runs for the report tests, made once per session: a plane2d example (with PRG
revisions: shelf2d learns obstructions) and a PyBullet one (domino) with execution
results and rendered frames, as a user would put them in the run directory."""

from __future__ import annotations

from pathlib import Path

import pytest

from stampc.cli import main

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples"


def refine(tmp: Path, name: str, world: str) -> Path:
    out = tmp / name
    folder = EXAMPLES / name
    code = main(["refine", str(folder / "domain.stamp"), str(folder / "problem.stamp"),
                 "--world", world, "--quiet", "--time-limit", "60", "-o", str(out)])
    assert code == 0
    return out


@pytest.fixture(scope="session")
def shelf_run(tmp_path_factory) -> Path:
    return refine(tmp_path_factory.mktemp("view"), "shelf2d", "plane2d")


@pytest.fixture(scope="session")
def domino_run(tmp_path_factory) -> Path:
    import contextlib
    import io

    out = refine(tmp_path_factory.mktemp("view"), "domino", "pybullet")
    report = io.StringIO()
    with contextlib.redirect_stdout(report):
        code = main(["execute", str(out / "policy.json"), "--runs", "3", "--format", "json",
                     "--render", str(out / "frames")])
    assert code == 0
    (out / "execute.json").write_text(report.getvalue())  # "wrote N frames" goes to stderr
    return out
