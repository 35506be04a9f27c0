"""The ATM-MDP engine end to end on the 2-D world, from real .stamp inputs."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

import stampc
from stampc.refine import Engine, RefineOptions, run_refinement
from stampc.worlds.bindings import resolve_model
from stampc.worlds.loading import load_scene, open_world

DATA = Path(__file__).parent / "data"
SHELF = [DATA / "shelf.stamp", DATA / "shelf5.stamp"]
STORE = [DATA / "store.stamp", DATA / "store1.stamp"]


def refine(files, **options):
    return stampc.refine_policy(files, world="plane2d", options=RefineOptions(**options))


def learned_facts(policy: dict) -> list[str]:
    return [f["fact"] for n in policy["nodes"] for f in n["learned"] if f["value"]]


@pytest.fixture(scope="module")
def shelf_run():
    return refine(SHELF, seed=1, time_limit=60)


def open_for(files):
    model = stampc.load_model(files)
    world = open_world("plane2d", load_scene(model.problem, Path(files[-1]).parent), seed=0)
    return model, world, resolve_model(model, world.package)


def test_obstructions_are_learned_and_policy_is_fully_refined(shelf_run):
    result = shelf_run.result
    assert result.coverage == pytest.approx(1.0, abs=1e-9)
    assert result.goal_probability == pytest.approx(1.0, abs=1e-9)
    policy = shelf_run.to_json()
    blamed = {re.match(r"collision\((\w+),", f).group(1) for f in learned_facts(policy)}
    # the scene builder puts exactly can1 and can2 in the target's corridor
    assert blamed and blamed <= {"can1", "can2"}
    assert result.abstract_solves >= 2          # replanned after learning


def test_refined_policy_reaches_goal_in_every_sampled_run(shelf_run, replay_policy):
    report = replay_policy(shelf_run.to_json(), "plane2d", runs=60, seed=5, world_seed=0)
    assert report.count("unrefined") == 0
    assert report.count("success") == 60
    assert any(len(r.actions) > 1 for r in report.runs)   # blockers were moved first


def test_same_seed_gives_identical_policy_json():
    a = refine(SHELF, seed=7, time_limit=60).to_json()
    b = refine(SHELF, seed=7, time_limit=60).to_json()
    assert json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)


def test_iteration_limit_returns_a_valid_partial_policy(replay_policy):
    run = refine(SHELF, seed=1, max_iterations=2, time_limit=60)
    assert run.result.stop_reason == "iteration limit"
    assert 0.0 <= run.result.coverage < 1.0
    policy = run.to_json()
    ids = {n["id"] for n in policy["nodes"]}
    assert policy["root"] in ids
    for node in policy["nodes"]:
        for outcome in node.get("outcomes", ()):
            assert outcome["child"] in ids
    report = replay_policy(policy, "plane2d", runs=30, seed=2, world_seed=0)
    assert report.count("failure") == 0        # partial, but never wrong
    assert report.count("unrefined") > 0


def test_interrupt_returns_best_policy_so_far():
    seen = []

    def interrupt_after_three(event):
        seen.append(event)
        if len(seen) == 3:
            raise KeyboardInterrupt

    model, world, bindings = open_for(SHELF)
    try:
        refined = run_refinement(stampc.ground(model), world, bindings, RefineOptions(seed=1),
                                 on_event=interrupt_after_three)
    finally:
        world.close()
    assert refined.result.stop_reason == "interrupted"
    assert refined.graph is not None
    assert refined.result.coverage == pytest.approx(seen[-1].coverage)


def test_explore_escapes_a_policy_without_feasible_refinement():
    # never ban: only the explore step can replace the infeasible store_cheap action
    run = refine(STORE, seed=3, explore_probability=0.5, max_attempts=10**6, time_limit=60)
    assert run.result.coverage == pytest.approx(1.0)
    actions = [n["action_name"] for n in run.to_json()["nodes"] if n.get("refined")]
    assert "store" in actions and "store_cheap" not in actions
    assert any(e.kind == "explore" for e in run.result.events)


def test_infeasible_action_is_banned_after_attempts():
    run = refine(STORE, seed=3, explore_probability=0.0, max_attempts=2, time_limit=60)
    assert run.result.coverage == pytest.approx(1.0)
    assert not any(e.kind == "explore" for e in run.result.events)
    assert any(e.kind == "ban" for e in run.result.events)


def test_horizon_grows_until_the_policy_is_covered():
    run = refine(SHELF, seed=1, horizon=1, time_limit=60)
    assert run.result.coverage == pytest.approx(1.0, abs=1e-9)
    depths = [n["depth"] for n in run.to_json()["nodes"] if n["refined"]]
    # two blockers are moved first: pick, place, pick, place, pick — far past horizon 1
    assert max(depths) >= 4


# Of seeds 0-9 only seed 7 updates below an already refined prefix on this problem; the
# default run checks it (and seed 0), the slow run all ten.
@pytest.mark.parametrize("seeds", [(7, 0), pytest.param(tuple(range(10)), marks=pytest.mark.slow)],
                         ids=["seeds-7-0", "seeds-0-9"])
def test_refined_nodes_survive_every_update(seeds):
    """UpdateAbstraction replans below a failing node only: every node refined in the
    parent PRG node is still refined, with the same concretization, in the child.
    Checked over several seeds in UpdateAbstraction mode (at least one updates below
    an already refined prefix)."""
    model, world, bindings = open_for(SHELF)
    ground = stampc.ground(model)
    checked = 0
    try:
        for seed in seeds:
            # placements in the way re-sampled instead (resample_placers) would turn
            # these seeds' updates below a refined prefix into re-samples
            engine = Engine(ground, world, bindings,
                            RefineOptions(seed=seed, update_probability=1.0, time_limit=60,
                                          resample_placers=False))
            prg_size = 1
            for _ in engine.run():
                if engine.prg.number_of_nodes() > prg_size:
                    prg_size = engine.prg.number_of_nodes()
                    parent = engine.prg.nodes[prg_size - 1]["parent"]
                    before = engine.prg.nodes[parent]["graph"]
                    after = engine.prg.nodes[prg_size - 1]["graph"]
                    for uid, node in before.nodes.items():
                        if node.refined:
                            assert uid in after.nodes and after[uid].sigma is node.sigma
                            checked += 1
            assert engine.best[0] == pytest.approx(1.0, abs=1e-9)
    finally:
        world.close()
    assert checked > 0
