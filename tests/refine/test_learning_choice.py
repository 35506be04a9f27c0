"""Which failed sample's facts UpdateAbstraction writes back (``learn_lock_free``,
stampc/refine/learning.py): the full search reports every sample's violated facts, and
the engine writes a set that locks no action, not merely the smallest. Real PyBullet + OMPL world,
the cluttered table's fixed-base example (its target starts behind arranged blockers,
which the Panda's four top grasps meet differently)."""

from __future__ import annotations

import dataclasses
import functools
import math
from pathlib import Path

import pytest

import stampc
from stampc.refine import Engine, RefineOptions
from stampc.refine.concretize import Failure
from stampc.refine.graph import path_values
from stampc.refine.learning import LearningChoice
from stampc.refine.update import with_facts
from stampc.solvers.heuristics import make_heuristic
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
    return _index(engine.model, name)


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


def _mobile():
    """The mobile-base table (target can12, four base poses), ground, and its choice."""
    model = stampc.ground(stampc.load_model([EXAMPLE / "domain.stamp",
                                             EXAMPLE / "problem.stamp"]))
    choice = LearningChoice(model, make_heuristic("hadd", model, False))
    return model, choice


def _written(model):
    return functools.partial(with_facts, model)


def _index(model, name: str) -> int:
    return next(i for i, f in enumerate(model.facts) if str(f) == name)


def test_an_obstruction_by_a_can_that_the_picked_can_obstructs_is_learned_last():
    """The pick of can12 from b3 fails: one grasp meets can1, whose own pick from b3
    can12 is known to block (a lock from that base); another meets can2 and can3. The
    relaxed goal cost is finite either way (other bases), so h_add cannot tell; the
    larger, lock-free set is learned, and without the rule the smaller one."""
    model, choice = _mobile()
    written = _written(model)
    pick = next(a.index for a in model.actions if a.label.startswith("pick(can12, pose_can12, b3,"))
    t12 = "t_pick_can12_pose_can12_b3"
    state = model.init | (1 << _index(model, "collision(can12, t_pick_can1_pose_can1_b3)"))
    lock = ((_index(model, f"collision(can1, {t12})"), True),)
    free = ((_index(model, f"collision(can2, {t12})"), True),
            (_index(model, f"collision(can3, {t12})"), True))
    mine = {"can12", "b3"}
    assert choice.locks(state, mine, lock) == 1 and choice.locks(state, mine, free) == 0
    assert choice.cost(written(state, lock)) < math.inf  # the relaxation goes round it
    assert choice.best(state, pick, (lock, free), written) == free
    # the same obstruction is no lock while can12 does not block can1's pick
    assert choice.locks(model.init, mine, lock) == 0
    assert choice.best(model.init, pick, (lock, free), written) == lock
    # blocked from another base only: b1's pick of can1 is not this lock
    other = model.init | (1 << _index(model, "collision(can12, t_pick_can1_pose_can1_b1)"))
    assert choice.locks(other, mine, lock) == 0


def test_a_relaxed_dead_end_is_learned_last():
    """On the fixed-base table (one robot pose) the same lock leaves the goal no relaxed
    way at all: ranked behind the other set before anything else."""
    model = stampc.ground(stampc.load_model(FILES))
    choice = LearningChoice(model, make_heuristic("hadd", model, False))
    written = _written(model)
    pick = next(a.index for a in model.actions if a.label.startswith("pick(can0, pose_can0,"))
    state = model.init | (1 << _index(model, "collision(can0, t_pick_can1_pose_can1)"))
    stuck = ((_index(model, "collision(can1, t_pick_can0_pose_can0)"), True),)
    free = ((_index(model, "collision(can2, t_pick_can0_pose_can0)"), True),
            (_index(model, "collision(can3, t_pick_can0_pose_can0)"), True))
    assert choice.cost(written(state, stuck)) == math.inf
    assert choice.cost(written(state, free)) < math.inf
    assert choice.best(state, pick, (stuck, free), written) == free


def test_the_engine_learns_by_the_choice_unless_told_otherwise(engine_at_root):
    engine = engine_at_root
    graph = engine.prg.nodes[engine.current]["graph"]
    node = graph[graph.root]
    state = node.state | (1 << _fact(engine, "collision(can0, t_pick_can1_pose_can1)"))
    node = dataclasses.replace(node, state=state, action=_pick_target(engine)[0].index)
    stuck = ((_fact(engine, "collision(can1, t_pick_can0_pose_can0)"), True),)
    free = ((_fact(engine, "collision(can2, t_pick_can0_pose_can0)"), True),
            (_fact(engine, "collision(can3, t_pick_can0_pose_can0)"), True))
    failure = Failure(stuck, {}, 2, alternatives=(stuck, free))
    assert engine._to_learn(node, failure) == free
    engine.options = RefineOptions(seed=0, learn_lock_free=False)
    assert engine._to_learn(node, failure) == stuck


def test_a_quick_sample_that_would_lock_an_action_is_searched_fully_first(engine_at_root):
    engine = engine_at_root
    graph = engine.prg.nodes[engine.current]["graph"]
    node = graph.own(graph.root)
    node.state |= 1 << _fact(engine, "collision(can0, t_pick_can1_pose_can1)")
    node.action = _pick_target(engine)[0].index
    stuck = ((_fact(engine, "collision(can1, t_pick_can0_pose_can0)"), True),)
    values = path_values(graph, (), engine.initial_values)
    kind, detail = engine._on_failure(graph, (node.uid,),
                                      Failure(stuck, {}, 1, quick=True, alternatives=(stuck,)),
                                      values)
    assert kind == "retry" and "every sample" in detail
    assert engine._concretize_quickly(node, 0.0) is False  # the next try searches all
    # another node in the same abstract state, with the same action: searched once is enough
    twin = dataclasses.replace(node, uid=node.uid + 10_000)
    assert not engine._locks_on_one_sample(
        twin, Failure(stuck, {}, 1, quick=True, alternatives=(stuck,)))
    # a full search's facts are learned, lock or not (no other sample was better)
    kind, _ = engine._on_failure(graph, (node.uid,),
                                 Failure(stuck, {}, 4, alternatives=(stuck,)), values)
    assert kind != "retry"
