"""Which failed sample's facts UpdateAbstraction writes back (``learn_cheapest``): the
full search reports every sample's violated facts, and the engine writes the set that
leaves the abstract goal cheapest, not merely the smallest. Real PyBullet + OMPL world,
the cluttered table's fixed-base example (its target starts behind arranged blockers,
which the Panda's four top grasps meet differently)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import stampc
from stampc.refine import Engine, RefineOptions
from stampc.refine.concretize import Failure
from stampc.refine.graph import path_values
from stampc.worlds.bindings import resolve_model
from stampc.worlds.loading import load_scene, open_world

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "cluttered_table"
FILES = [EXAMPLE / "domain_fixed.stamp", EXAMPLE / "problem_fixed.stamp"]


@pytest.fixture()
def engine_at_root():
    """An engine on the fixed-base table, started (its root policy planned)."""
    model = stampc.load_model(FILES)
    world = open_world("pybullet", load_scene(model.problem, EXAMPLE), seed=0)
    engine = Engine(stampc.ground(model), world, resolve_model(model, world.package),
                    RefineOptions(seed=0, time_limit=30))
    events = engine.run()
    next(events)  # the start: the root policy
    yield engine
    events.close()  # before the world goes: the engine's loop ends with the world
    world.close()


def _fact(engine: Engine, name: str) -> int:
    return next(i for i, f in enumerate(engine.model.facts) if str(f) == name)


def _pick_target(engine: Engine):
    action = next(a for a in engine.model.actions
                  if a.label.startswith("pick(can0, pose_can0,"))
    graph = engine.prg.nodes[engine.current]["graph"]
    root = graph[graph.root]
    values = path_values(graph, (), engine.initial_values)
    return action, root, values


@pytest.mark.parametrize("quick", [False, True])
def test_a_failed_search_reports_every_samples_violations(engine_at_root, quick):
    engine = engine_at_root
    action, root, values = _pick_target(engine)
    failure = engine.concretizer.concretize(action, root.concrete.snapshot,
                                            dict(root.concrete.cache), values,
                                            node_uid=root.uid, attempt=0, quick=quick)
    assert isinstance(failure, Failure) and failure.violated  # the blockers are arranged
    assert failure.violated in failure.alternatives
    assert len(set(failure.alternatives)) == len(failure.alternatives)
    assert all(facts for facts in failure.alternatives)
    sizes = [len(facts) for facts in failure.alternatives]
    assert sizes == sorted(sizes) and sizes[0] == len(failure.violated)
    if quick:  # one sample only
        assert failure.alternatives == (failure.violated,)
    else:  # the arranged blockers stand in the way of different grasps differently
        assert len(failure.alternatives) >= 2 and failure.samples >= 2


def test_the_facts_leaving_the_goal_cheapest_are_written(engine_at_root):
    """can0's pick blocked by can1 (whose own pick can0 blocks: a relaxed dead end) or
    by can1 and can2 (both movable): the second set is larger and the one to learn."""
    engine = engine_at_root
    state = engine.model.init | (1 << _fact(engine, "collision(can0, t_pick_can1_pose_can1)"))
    stuck = ((_fact(engine, "collision(can1, t_pick_can0_pose_can0)"), True),)
    movable = ((_fact(engine, "collision(can2, t_pick_can0_pose_can0)"), True),
               (_fact(engine, "collision(can3, t_pick_can0_pose_can0)"), True))
    failure = Failure(stuck, {}, 2, alternatives=(stuck, movable))
    assert engine._to_learn(state, failure) == movable
    # the relaxed costs behind the choice: the stuck set leaves no way at all
    cost = engine._learning_cost
    assert cost(engine._with_facts(state, stuck)) == math.inf
    assert cost(engine._with_facts(state, movable)) < math.inf
    # among sets of equal cost the smaller one; and off, the smallest (the old choice)
    assert engine._to_learn(state, Failure(movable, {}, 2, alternatives=(movable,))) == movable
    engine.options = RefineOptions(seed=0, learn_cheapest=False)
    assert engine._to_learn(state, failure) == stuck
