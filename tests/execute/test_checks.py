"""Concrete goal checks and the 10x re-check decide on the world's concrete state."""

from __future__ import annotations

import json
from pathlib import Path

from stampc.execute.goals import goal_check_for, plane2d_goal
from stampc.execute.recheck import plane2d_recheck
from stampc.execute.session import execute_file
from stampc.worlds.base import ConcreteAction
from stampc.worlds.loading import open_world
from stampc.worlds.plane2d.values import Traj2


def _world(shelf: Path):
    scene = json.loads((shelf / "full" / "policy.json").read_text())["scene"]
    return open_world("plane2d", scene, seed=0)


def test_goal_leaf_with_the_target_on_the_table_fails(shelf: Path) -> None:
    world = _world(shelf)
    leaf = {"goal_facts": [{"predicate": "holding", "args": ["can0"]}], "state": []}
    assert plane2d_goal(world, leaf) == ["holding(can0) does not hold concretely"]
    world.attach("can0")
    assert plane2d_goal(world, leaf) == []


def test_a_bound_goal_check_replaces_the_default(shelf: Path, tmp_path: Path) -> None:
    (tmp_path / "mycheck.py").write_text(
        "def never(world, leaf):\n    return ['the customer wanted can4']\n")
    world = _world(shelf)
    check = goal_check_for(world, {"meta": {"goal_check": "mycheck:never"}}, tmp_path)
    assert check(world, {}) == ["the customer wanted can4"]


def test_goal_check_failures_are_failed_runs_with_reasons(shelf: Path, tmp_path: Path) -> None:
    policy = json.loads((shelf / "full" / "policy.json").read_text())
    for node in policy["nodes"]:  # claim a goal the world cannot show
        if node["leaf"] == "goal":
            node["goal_facts"] = [{"predicate": "holding", "args": ["can4"]}]
    edited = shelf / "full" / "wrong-goal.json"
    edited.write_text(json.dumps(policy))
    try:
        report = execute_file(edited, runs=5, seed=0)
    finally:
        edited.unlink()
    assert report.count("success") == 0 and report.goal_failures == 5
    assert "holding(can4) does not hold concretely" in report.runs[0].detail
    assert not report.ok


def test_recheck_names_what_a_path_sweeps_through(shelf: Path) -> None:
    world = _world(shelf)
    pose = world.pose("can1")
    start = world.gripper
    through = Traj2((start, (pose.x, pose.y)), None, "can0")
    around = Traj2((start, start), None, "can0")
    assert "can1" in plane2d_recheck(world, ConcreteAction("pick", {"t": through}))
    assert plane2d_recheck(world, ConcreteAction("pick", {"t": around})) == []


def test_executed_shelf_policy_is_clean(shelf: Path) -> None:
    report = execute_file(shelf / "full" / "policy.json", runs=40, seed=2)
    assert report.collisions == 0 and report.goal_failures == 0
    assert report.count("success") == 40 and report.ok
