"""End-to-end tests of the domino example on PyBullet + OMPL: the problem generator,
the topple executor, refinement to full coverage (k = 2 and k = 3) and replay with
every executed trajectory re-checked for collisions. Real worlds, no mocks; ~15 s."""

from __future__ import annotations

import random
from pathlib import Path

import pytest

from examples.domino import scene as dom
from stampc import refine_policy
from stampc.refine import RefineOptions
from stampc.refine.replay import replay
from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.bindings import resolve_model
from stampc.worlds.loading import open_world
from stampc.worlds.pybullet import domino, manipulation
from stampc.worlds.pybullet.values import as_traj

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "examples" / "domino"
DOMAIN = EXAMPLE / "domain.stamp"


def _checked(fn, failures: list[str]):
    """Wrap an executor: first sweep its trajectory in the current world state."""
    def run(ctx: Context, action: ConcreteAction) -> None:
        if "t" in action.args and not manipulation.trajectory_free(ctx, as_traj(action.args["t"])):
            failures.append(action.name)
        fn(ctx, action)
    return run


def _refine_and_replay(problem: Path, runs: int = 40):
    run = refine_policy([DOMAIN, problem], world="pybullet",
                        options=RefineOptions(seed=0, time_limit=60))
    policy = run.to_json()
    from stampc import load_model
    world = open_world("pybullet", policy["scene"], seed=1)
    finals: dict[int, tuple] = {}
    failures: list[str] = []
    try:
        execs = {n: _checked(f, failures)
                 for n, f in resolve_model(load_model(policy["files"]),
                                           world.package).executors.items()}
        report = replay(policy, world, execs, runs=runs, seed=1,
                        on_step=lambda r, s, w: finals.__setitem__(r, w.snapshot()))
        geometry = dict(world.geometry)
    finally:
        world.close()
    return run, report, finals, failures, geometry


def test_problem_file_matches_generator():
    text = (EXAMPLE / "problem.stamp").read_text(encoding="utf-8")
    assert text == dom.problem_text(10, 2, 0)


def test_generator_instances_and_bad_input():
    for n, k in ((10, 2), (15, 3), (20, 3)):
        for seed in range(5):
            inst = dom.instance(n, k, seed)
            assert k <= inst.target <= n - 1 - k  # k neighbours on both sides
    text = dom.problem_text(15, 3, 1)
    assert text.count("near3(") == 2 * (15 - 3) and "near4" not in text
    assert dom.problem_text(15, 3, 1) == text  # deterministic
    with pytest.raises(ValueError, match="topple reach"):
        dom.instance(10, 4, 0)
    with pytest.raises(ValueError, match="at least"):
        dom.instance(4, 2, 0)
    scene = dom.build(20, 0)
    ys = [o["position"][1] for o in scene["objects"]]
    assert len(ys) == 20 and max(ys) - min(ys) == pytest.approx(19 * dom.SPACING, abs=1e-6)
    assert all(abs(y) < 0.35 for y in ys)  # on the 0.7 m table


def test_topple_executor_lays_dominoes_down():
    world = open_world("pybullet", dom.build(7, 0), seed=0)
    try:
        ctx = Context(world=world, rng=random.Random(0))
        standing = world.object_pose("d3")
        g, q = next(iter(manipulation.grasp(ctx, "d3", standing)))
        adds = (("holding", ("d3",)), ("toppled", ("d2",)), ("toppled", ("d5",)))
        domino.pick(ctx, ConcreteAction("pick", {"o": "d3", "q": q}, adds=adds))
        assert world.state.held == "d3"
        thin, wide, tall = world.geometry["d2"].dims
        for name in ("d2", "d5"):
            pose = world.object_pose(name)
            assert pose.pos[2] == pytest.approx(thin / 2, abs=1e-3)  # lying on its face
            assert pose.pos[0] > 0.5 + tall / 2  # fallen away from the robot
        for name in ("d1", "d4"):  # untouched dominoes still stand
            assert world.object_pose(name).pos[2] == pytest.approx(tall / 2, abs=1e-3)
    finally:
        world.close()


@pytest.mark.parametrize("k", [2, pytest.param(3, marks=pytest.mark.slow)])
def test_refine_to_full_coverage_and_replay(tmp_path, k):
    problem = dom.write_problem(tmp_path / "p.stamp", 10 if k == 2 else 8, k, 0)
    inst = dom.instance(10 if k == 2 else 8, k, 0)
    run, report, finals, failures, geometry = _refine_and_replay(problem)
    assert run.result.coverage == pytest.approx(1.0)
    assert run.result.goal_probability == pytest.approx(1.0)
    assert report.count("success") == len(report.runs) == 40 and not failures
    target = f"d{inst.target}"
    tall = geometry[target].dims[2]
    for index, record in enumerate(report.runs):
        state = finals[index]
        assert state.held == target
        notified = {a[len("notify("):-1] for a in record.actions if a.startswith("notify(")}
        lying = {n for n, pose in state.poses if n != target and pose.pos[2] < tall / 4}
        assert lying == notified  # every fallen domino reported, nothing else
        assert all(abs(int(n[1:]) - inst.target) <= k for n in lying)
    # with 40 runs some neighbour must have fallen (P(no topple) = 1/9 or 1/64)
    assert any(a.startswith("notify(") for r in report.runs for a in r.actions)


def test_a_dead_end_needs_more_than_one_quick_sample(tmp_path):
    """n = 40, k = 3, seed 9 (a benchmark instance): with engine seed 9 the target's
    pick took UpdateAbstraction's quick mode three times and drew the same grasp each
    time, whose hand hit the dominoes two places away; three "proofs" then made the
    whole row a dead end (goal probability 0) although other grasps pick it. A dead end
    now stands only after the failing node searched every sample of its generators."""
    problem = dom.write_problem(tmp_path / "p.stamp", 40, 3, 9)
    run = refine_policy([DOMAIN, problem], world="pybullet",
                        options=RefineOptions(seed=9, time_limit=60, target_coverage=0.999))
    details = " ".join(e.detail for e in run.result.events)
    assert "searches every sample" in details  # the quick samples did fail here
    assert run.result.dead_end_mass == 0.0
    assert run.result.goal_probability == pytest.approx(1.0)
