"""Recalling learned facts (stampc/refine/recall.py) on the PyBullet cluttered table: a
remembered fact is written back only where it still holds in the node's concrete state,
and a run that recalls facts still yields a policy the world executes."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import stampc
from examples.cluttered_table import scene as ct
from stampc.refine import Engine, RefineOptions
from stampc.refine.graph import Concrete
from stampc.refine.recall import FactMemory
from stampc.worlds.bindings import resolve_model
from stampc.worlds.loading import load_scene, open_world

DOMAIN = Path(ct.__file__).with_name("domain.stamp")


@pytest.fixture(scope="module")
def cluttered15(tmp_path_factory):
    """Cluttered-15 seed 6: its target cannot be grasped from every base."""
    problem = ct.write_problem(tmp_path_factory.mktemp("recall") / "p.stamp", 15, 6)
    model = stampc.load_model([DOMAIN, problem])
    world = open_world("pybullet", load_scene(model.problem, problem.parent), seed=0)
    try:
        engine = Engine(stampc.ground(model), world, resolve_model(model, world.package),
                        RefineOptions(seed=0))
        yield problem, engine
    finally:
        world.close()


def _grasps_from_each_base(engine: Engine) -> dict[int, bool]:
    """reaches(b, o, pose_o) of every can at its initial pose, evaluated in the world."""
    concrete = Concrete(engine.world.snapshot(), None)
    return {i: engine.concretizer.evaluate_at(concrete, i, engine.initial_values,
                                              node_uid=0, attempt=0)
            for i, f in enumerate(engine.model.facts)
            if f.predicate == "reaches" and f.args[2] == f"pose_{f.args[1]}"}


def test_only_remembered_facts_that_hold_here_are_recalled(cluttered15):
    _, engine = cluttered15
    truth = _grasps_from_each_base(engine)
    assert set(truth.values()) == {True, False}, "the scene has reachable and unreachable cans"
    concrete = Concrete(engine.world.snapshot(), None)
    memory = FactMemory(engine.concretizer)
    memory.remember([(f, False) for f in truth])  # "none reachable"
    optimistic = sum(1 << f for f in truth)  # the abstraction assumes every grasp reachable
    recalled = memory.recall(optimistic, concrete, engine.initial_values, node_uid=1, attempt=0)
    assert dict(recalled) == {f: False for f, holds in truth.items() if not holds}
    assert memory.recalled == len(recalled)
    # facts the abstract state already has right are not evaluated again
    settled = optimistic & ~sum(1 << f for f, _ in recalled)
    before = memory.evaluations
    assert memory.recall(settled, concrete, engine.initial_values, node_uid=2, attempt=0) == ()
    assert memory.evaluations - before == sum(truth.values())


def test_a_recalled_fact_follows_its_can(cluttered15):
    """The node's own value of a symbol wins over the remembered one: a grasp remembered
    unreachable at the can's old pose is recalled at the node only if it is still
    unreachable where the node's values put the can."""
    _, engine = cluttered15
    truth = _grasps_from_each_base(engine)
    facts = engine.model.facts
    unreachable = next(f for f, holds in truth.items() if not holds)
    b, o, p = facts[unreachable].args
    # a pose of another can that base b reaches: the node's value of p puts o there
    there = next(facts[f].args[2] for f, holds in truth.items()
                 if holds and facts[f].args[0] == b and facts[f].args[1] != o)
    memory = FactMemory(engine.concretizer)
    memory.remember([(unreachable, False)])
    moved = {**engine.initial_values, p: engine.initial_values[there]}
    concrete = Concrete(engine.world.snapshot(), None)
    state = 1 << unreachable
    at_old = memory.recall(state, concrete, engine.initial_values, node_uid=1, attempt=0)
    at_new = memory.recall(state, concrete, moved, node_uid=1, attempt=0)
    assert at_old == ((unreachable, False),)
    assert at_new == ()


def test_facts_about_values_unbound_at_the_node_are_not_recalled(cluttered15):
    """A fact about a symbol the node's path does not bind (a trajectory still to be
    sampled there) is not evaluated with a value sampled elsewhere."""
    _, engine = cluttered15
    truth = _grasps_from_each_base(engine)
    unreachable = next(f for f, holds in truth.items() if not holds)
    symbol = engine.model.facts[unreachable].args[2]
    unbound = {k: v for k, v in engine.initial_values.items() if k != symbol}
    memory = FactMemory(engine.concretizer)
    memory.remember([(unreachable, False)])
    concrete = Concrete(engine.world.snapshot(), None)
    state = 1 << unreachable
    assert memory.recall(state, concrete, unbound, node_uid=1, attempt=0) == ()
    assert memory.evaluations == 0
    assert memory.recall(state, concrete, engine.initial_values, node_uid=1,
                         attempt=0) == ((unreachable, False),)


def test_facts_about_the_checking_actions_own_sample_are_not_remembered(cluttered15):
    """``collision(o, t)`` is checked by the action that plans ``t``: a trajectory bound
    elsewhere says nothing about the motion it will plan, so such facts are not recalled;
    the reach of a grasp at a bound pose is."""
    _, engine = cluttered15
    facts = engine.model.facts
    sampled = engine.concretizer.sampled_checks()
    collisions = {i for i, f in enumerate(facts) if f.predicate == "collision"}
    reaches = set(_grasps_from_each_base(engine))
    assert sampled & collisions and not sampled & reaches
    fact = next(iter(sampled & collisions))
    memory = FactMemory(engine.concretizer)
    memory.remember([(fact, True)])
    values = {**engine.initial_values, **{a: None for a in facts[fact].args}}  # all bound
    concrete = Concrete(engine.world.snapshot(), None)
    assert memory.recall(0, concrete, values, node_uid=1, attempt=0) == ()
    assert memory.evaluations == 0


@pytest.mark.slow
def test_a_recalling_run_is_executed_cleanly_by_the_world(cluttered15, tmp_path):
    """Cluttered-15 seed 6, engine seed 6: by iteration 110 a fact learned in one branch
    (a grasp no base reaches) has been recalled in another. Each recalled fact was learned
    at an earlier revision, and the partial policy passes ``stampc execute``: outcomes
    sampled by the world, every trajectory re-swept, the goal tested on the concrete
    state (runs that reach an unrefined branch are counted apart, never as success)."""
    from stampc.execute.session import execute_file

    problem, _ = cluttered15
    # without re-drawing placements in the way (resample_placers), which solves this
    # seed in 20 refined nodes before any fact is recalled
    run = stampc.refine_policy([DOMAIN, problem], world="pybullet", options=RefineOptions(
        seed=6, time_limit=None, max_iterations=110, target_coverage=0.999,
        resample_placers=False))
    assert run.result.recalled_facts > 0
    learned_before: set[str] = set()
    recalled = 0
    for revision in run.history["revisions"]:
        for fact in revision.get("recalled", []):
            assert fact in learned_before, f"{fact} recalled before it was learned anywhere"
            assert fact.startswith("reaches(")  # decided before any sample, never collision
            recalled += 1
        learned_before.update(revision["facts"])
    assert recalled == run.result.recalled_facts
    path = tmp_path / "policy.json"
    path.write_text(json.dumps(run.to_json()))
    report = execute_file(path, runs=20, seed=1)
    assert report.collisions == 0 and report.goal_failures == 0
    assert report.count("failure") == 0
    assert report.count("success") >= 10  # most of the mass is refined by then
