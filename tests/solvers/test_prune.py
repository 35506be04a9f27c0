"""LAO* with ``prune_probability``: tips the greedy policy reaches with less probability
stay unexpanded (a partial policy the refinement engine completes lazily)."""

from __future__ import annotations

import pytest

from ssp_builders import ModelBuilder
from stampc.diagnostics import StampcError
from stampc.solvers import SolverOptions, policy_tree, solve
from stampc.solvers.tree import iter_paths


def rare_detour_model():
    """``go``: the goal with 0.97, a rare detour (3 more steps) with 0.03."""
    b = ModelBuilder(["start", "goal", "d0", "d1", "d2"])
    b.action("go", pre=["start"], outcomes=[("97/100", ["goal"], ["start"]),
                                            ("3/100", ["d0"], ["start"])])
    b.action("d0_d1", pre=["d0"], outcomes=[(1, ["d1"], ["d0"])])
    b.action("d1_d2", pre=["d1"], outcomes=[(1, ["d2"], ["d1"])])
    b.action("d2_goal", pre=["d2"], outcomes=[(1, ["goal"], ["d2"])])
    return b, b.build(init=["start"], goal=["goal"])


def state(b: ModelBuilder, *facts: str) -> int:
    return b.mask(facts)


@pytest.mark.parametrize("heuristic", ("zero", "hmax", "hadd"))
def test_a_rare_outcome_below_the_threshold_is_left_unplanned(heuristic):
    b, model = rare_detour_model()
    full = solve(model, SolverOptions(heuristic=heuristic, epsilon=1e-9))
    pruned = solve(model, SolverOptions(heuristic=heuristic, epsilon=1e-9,
                                        prune_probability=0.05))
    detour = state(b, "d0")
    assert full.planned(detour) and full.planned(state(b, "d2"))
    assert not pruned.planned(detour)  # reached with 0.03 < 0.05
    assert pruned.planned(model.init)
    assert model.actions[pruned.action(model.init)].name == "go"
    assert pruned.states_expanded < full.states_expanded
    assert full.expected_cost == pytest.approx(1 + 0.03 * 3)
    # the partial policy reaches the goal on the planned branch only
    assert pruned.goal_probability == pytest.approx(0.97)
    assert full.goal_probability == pytest.approx(1.0)


def test_a_threshold_below_every_outcome_changes_nothing():
    b, model = rare_detour_model()
    full = solve(model, SolverOptions(heuristic="hmax", epsilon=1e-9))
    same = solve(model, SolverOptions(heuristic="hmax", epsilon=1e-9, prune_probability=0.01))
    assert same.planned(state(b, "d2"))
    assert same.expected_cost == pytest.approx(full.expected_cost)
    assert same.states_expanded == full.states_expanded


def test_unplanned_tips_become_horizon_leaves_of_the_policy_tree():
    b, model = rare_detour_model()
    pruned = solve(model, SolverOptions(heuristic="hadd", prune_probability=0.05))
    tree = policy_tree(model, pruned, depth=10, planned_only=True)
    leaves = {path[-1].leaf: p for p, path in iter_paths(tree)}
    assert leaves == {"goal": pytest.approx(0.97), "horizon": pytest.approx(0.03)}


@pytest.mark.parametrize("bad", (-0.1, 1.0, float("nan")))
def test_a_prune_probability_outside_zero_one_is_a_located_error(bad):
    _, model = rare_detour_model()
    with pytest.raises(StampcError) as err:
        solve(model, SolverOptions(prune_probability=bad))
    assert {d.code for d in err.value.diagnostics} == {"S010"}
