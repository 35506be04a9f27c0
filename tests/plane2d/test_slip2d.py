"""Outcome-aware executors on examples/slip2d: a mobile robot whose drives may slip."""

from __future__ import annotations

import random
import subprocess
import sys
from pathlib import Path

import pytest

import stampc
from stampc.refine import RefineOptions
from stampc.worlds.base import ConcreteAction, Context, Outcome, accepts_outcome, call_executor
from stampc.worlds.plane2d import aerial
from stampc.worlds.plane2d import open_world as open_plane2d
from stampc.worlds.plane2d.scenes import aircraft

ROOT = Path(__file__).resolve().parents[2]
SLIP = [ROOT / "examples" / "slip2d" / "domain.stamp", ROOT / "examples" / "slip2d" / "problem.stamp"]


@pytest.fixture(scope="module")
def slip_run():
    return stampc.refine_policy(SLIP, world="plane2d", options=RefineOptions(seed=0, time_limit=60))


def test_slip_example_reaches_full_coverage_with_refined_slip_cycles(slip_run):
    result = slip_run.result
    assert result.coverage == pytest.approx(1.0, abs=1e-9)
    assert result.goal_mass == pytest.approx(1.0, abs=1e-9) and result.dead_end_mass == 0.0
    nodes = slip_run.to_json()["nodes"]
    drives = [n for n in nodes if n.get("action_name") == "drive"]
    assert len(drives) == 4 and all(n["refined"] for n in drives)
    for n in drives:  # the slip outcome is named and loops back to the same node
        names = {o.get("name"): o["child"] for o in n["outcomes"]}
        assert set(names) == {"moved", "slip"}
        assert names["slip"] == n["id"] and names["moved"] != n["id"]


def test_every_replay_that_stays_on_refined_branches_succeeds(slip_run, replay_policy):
    report = replay_policy(slip_run.to_json(), "plane2d", runs=80, seed=3, world_seed=0)
    assert report.on_refined == 80 and report.count("success") == 80
    assert any(len(r.actions) > 6 for r in report.runs)  # some runs slipped and retried


def test_stampc_execute_on_the_slip_example_succeeds(tmp_path):
    out = tmp_path / "out"
    cli = [sys.executable, "-m", "stampc"]
    refine = subprocess.run(cli + ["refine", *map(str, SLIP), "--world", "plane2d", "--seed", "1",
                                   "-o", str(out), "--quiet"], capture_output=True, text=True,
                            cwd=ROOT, timeout=120)
    assert refine.returncode == 0, refine.stderr
    run = subprocess.run(cli + ["execute", str(out / "policy.json"), "--runs", "25", "--seed", "2"],
                         capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert run.returncode == 0, run.stderr
    assert "success 25" in run.stdout


def _hangar():
    return open_plane2d(aircraft(seed=1, obstacles=0), seed=0)


def test_drive_moves_only_when_the_outcome_moves_the_robot():
    world = _hangar()
    ctx = Context(world=world, rng=random.Random(0))
    pose, path = next(aerial.fly(ctx, "tail"))
    action = ConcreteAction("drive", {"u": "uav", "a": "charger", "b": "tail", "p": pose, "t": path})
    start = world.snapshot()
    aerial.drive(ctx, action, outcome=Outcome("slip", 1, 0.2))
    assert world.fingerprint(world.snapshot()) == world.fingerprint(start)
    moved = Outcome("moved", 0, 0.8, adds=(("robot_at", ("uav", "tail")),))
    aerial.drive(ctx, action, outcome=moved)
    assert world.uav == pytest.approx(path.end)


def test_two_argument_executors_are_called_as_before():
    calls = []

    def old_style(ctx, action):
        calls.append(("old", action.name))

    def new_style(ctx, action, outcome):
        calls.append(("new", outcome.name, outcome.changes_nothing))

    assert not accepts_outcome(old_style) and accepts_outcome(new_style)
    ctx = Context(world=None, rng=random.Random(0))
    call_executor(old_style, ctx, ConcreteAction("a", {}), Outcome("x", 0, 1.0))
    call_executor(new_style, ctx, ConcreteAction("a", {}), Outcome("x", 0, 1.0))
    assert calls == [("old", "a"), ("new", "x", True)]
