"""End to end on real PyBullet: the domino example refined, then executed with physics,
the 10x re-check and the concrete goal check (toppled dominoes lie down and are all
notified)."""

from __future__ import annotations

from pathlib import Path

import pytest

from stampc.cli import main
from stampc.execute.session import execute_file

from .conftest import REPO


@pytest.fixture(scope="module")
def domino(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("domino")
    ex = REPO / "examples" / "domino"
    assert main(["refine", str(ex / "domain.stamp"), str(ex / "problem.stamp"), "--world",
                 "pybullet", "--quiet", "--time-limit", "60", "-o", str(out)]) == 0
    return out / "policy.json"


def test_domino_runs_are_checked_and_clean(domino: Path) -> None:
    report = execute_file(domino, runs=8, seed=3)
    assert report.count("success") == 8
    assert report.collisions == 0 and report.goal_failures == 0
    toppled = sum("topple" in s.outcome for r in report.runs for s in r.steps)  # as-labels
    assert toppled > 0  # the check had something to decide


def test_forgetting_a_notify_fails_the_concrete_goal(domino: Path, tmp_path: Path) -> None:
    import json
    policy = json.loads(domino.read_text())
    for node in policy["nodes"]:  # drop the notifications from the leaves' states
        node["state"] = [f for f in node["state"] if not f.startswith("notified(")]
    edited = domino.parent / "no-notify.json"
    edited.write_text(json.dumps(policy))
    try:
        report = execute_file(edited, runs=8, seed=3)
    finally:
        edited.unlink()
    failed = [r for r in report.runs if r.goal_failures]
    assert failed and all("toppled but was not notified" in r.detail for r in failed)
    assert report.count("success") + len(failed) == 8


@pytest.mark.slow
def test_keva_structure_is_built_and_stands(tmp_path: Path) -> None:
    """Keva 3π, two arms, physics on: every put plank stays at its role's pose (a plank
    stood upright by the hand is placed, not toppled), nothing collides at 10×."""
    ex = REPO / "examples" / "keva"
    assert main(["refine", str(ex / "domain.stamp"), str(ex / "problem.stamp"), "--world",
                 "pybullet", "--quiet", "--seed", "0", "--time-limit", "120",
                 "-o", str(tmp_path)]) == 0
    report = execute_file(tmp_path / "policy.json", runs=30, seed=1)
    assert report.count("success") == 30
    assert report.collisions == 0 and report.goal_failures == 0
