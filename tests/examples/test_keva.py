"""End-to-end tests of the keva example on PyBullet + OMPL: target structures, the
deterministic slot placements that let the engine merge branches, refinement to full
coverage and replay with every executed trajectory re-checked and the built structure
compared with its slots. Real worlds, no mocks; ~25 s."""

from __future__ import annotations

import math
import random
from pathlib import Path

import pytest

from examples.keva import scene as kv
from stampc import load_model, refine_policy
from stampc.diagnostics import StampcError
from stampc.refine import RefineOptions
from stampc.refine.replay import replay
from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.bindings import resolve_model
from stampc.worlds.loading import open_world
from stampc.worlds.pybullet import keva, manipulation
from stampc.worlds.pybullet.values import Pose, as_traj, quat_rotate

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "examples" / "keva"
DOMAIN = EXAMPLE / "domain.stamp"
LENGTH, WIDTH, THICK = kv.PLANK


def _extent(pose: Pose) -> tuple[float, float, float]:
    """World-axis half extents of a plank at ``pose`` (an orientation-free signature)."""
    axes = [quat_rotate(pose.quat, a) for a in ((1, 0, 0), (0, 1, 0), (0, 0, 1))]
    half = (LENGTH / 2, WIDTH / 2, THICK / 2)
    return tuple(sum(abs(ax[i]) * h for ax, h in zip(axes, half)) for i in range(3))


def _same_place(a: Pose, b: Pose) -> bool:
    return a.distance(b) < 1e-6 and all(abs(x - y) < 1e-6
                                        for x, y in zip(_extent(a), _extent(b)))


def test_problem_file_matches_generator():
    text = (EXAMPLE / "problem.stamp").read_text(encoding="utf-8")
    assert text == kv.problem_text("pi", 3, 0)


def test_structures_are_stacked_consistently():
    assert len(kv.slots("pi", 3)) == 9 and len(kv.slots("tower", 12)) == 24
    for structure in ("tower", "twisted"):
        slots = kv.slots(structure, 12)
        for i, slot in enumerate(slots):
            level = i // 2
            assert slot.pose.pos[2] == pytest.approx(THICK / 2 + level * THICK)
            if i % 2:  # the two planks of a level do not overlap
                assert slot.pose.distance(slots[i - 1].pose) >= WIDTH
    twisted = kv.slots("twisted", 3)
    assert twisted[2].pose.angle(kv.slots("tower", 3)[2].pose) == pytest.approx(kv.TWIST)
    legs_and_top = kv.slots("pi", 2)
    for leg in legs_and_top[:2]:  # upright legs: the plank's length is vertical
        assert _extent(leg.pose)[2] == pytest.approx(LENGTH / 2)
        assert _extent(leg.pose)[1] == pytest.approx(THICK / 2)
    top = legs_and_top[2].pose
    assert top.pos[2] - THICK / 2 == pytest.approx(LENGTH)  # rests on the legs' tops
    assert legs_and_top[3].pose.pos[2] - LENGTH / 2 == pytest.approx(top.pos[2] + THICK / 2)
    with pytest.raises(ValueError, match="unknown structure"):
        kv.slots("arch", 2)
    with pytest.raises(ValueError, match="at least one level"):
        kv.slots("tower", 0)


def test_bad_slot_or_feed_is_a_located_error():
    world = open_world("pybullet", kv.build("tower", 1), seed=0)
    try:
        ctx = Context(world=world, rng=random.Random(0))
        with pytest.raises(StampcError) as err:
            list(keva.feed_grasp(ctx, "k0", "feed9"))
        assert err.value.diagnostics[0].code == "PB050"
        with pytest.raises(StampcError) as err:
            keva.slot_pose(world, "s7")
        assert "s7" in err.value.diagnostics[0].message
    finally:
        world.close()


def test_slot_placement_is_deterministic():
    """Same slot and grip → same config, whatever the arm did before (branch merging)."""
    world = open_world("pybullet", kv.build("pi", 1), seed=0)
    try:
        ctx = Context(world=world, rng=random.Random(0))
        g, q = next(iter(keva.feed_grasp(ctx, "k0", "feed1")))
        keva.pick(ctx, ConcreteAction("pick_plank", {"k": "k0", "q": q, "g": g},
                                      adds=(("holding", ("k0",)),)))
        first = next(iter(keva.slot_placement(Context(world, random.Random(1)), "k0", "s1")))
        world.update(q=tuple(v + 0.1 for v in world.state.q))
        again = next(iter(keva.slot_placement(Context(world, random.Random(2)), "k0", "s1")))
        assert first == again
        assert _same_place(first[0], kv.slots("pi", 1)[1].pose)
    finally:
        world.close()


def _checked(fn, failures: list[str]):
    def run(ctx: Context, action: ConcreteAction) -> None:
        if not manipulation.trajectory_free(ctx, as_traj(action.args["t"])):
            failures.append(action.name)
        fn(ctx, action)
    return run


@pytest.mark.parametrize("structure,levels",
                         [("pi", 1), pytest.param("tower", 3, marks=pytest.mark.slow)])
def test_refine_to_full_coverage_and_replay(tmp_path, structure, levels):
    problem = kv.write_problem(tmp_path / "p.stamp", structure, levels, 0)
    run = refine_policy([DOMAIN, problem], world="pybullet",
                        options=RefineOptions(seed=0, time_limit=60))
    n = len(kv.slots(structure, levels))
    assert run.result.coverage == pytest.approx(1.0)
    assert run.result.goal_probability == pytest.approx(1.0)
    # merged branches: at most 2 picks + 2 placements per plank, not 2^n paths
    assert run.result.refined_nodes <= 4 * n
    policy = run.to_json()
    world = open_world("pybullet", policy["scene"], seed=1)
    finals: dict[int, object] = {}
    failures: list[str] = []
    try:
        execs = {name: _checked(fn, failures) for name, fn in
                 resolve_model(load_model(policy["files"]), world.package).executors.items()}
        report = replay(policy, world, execs, runs=30, seed=1,
                        on_step=lambda r, s, w: finals.__setitem__(r, w.snapshot()))
    finally:
        world.close()
    assert report.count("success") == 30 and not failures
    feeds = [a for r in report.runs for a in r.actions if a.startswith("pick_plank")]
    assert any("feed2" in a for a in feeds) and any("feed1" in a for a in feeds)
    targets = kv.slots(structure, levels)
    for state in finals.values():
        assert state.held is None
        for i, slot in enumerate(targets):  # plank k_i sits in slot s_i
            assert _same_place(state.pose(f"k{i}"), slot.pose)
