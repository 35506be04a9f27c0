"""Policy trees, Monte Carlo simulation and warm re-solving."""

from __future__ import annotations

import pytest
from hypothesis import given, settings, strategies as st

from ssp_builders import ModelBuilder, random_model
from stampc.diagnostics import StampcError
from stampc.solvers import (SolverOptions, count_leaves, iter_paths, policy_tree, simulate,
                            solve)


def two_stage_model():
    """move (1/2 ok, 1/2 flat tyre); change the tyre if a spare is on board."""
    b = ModelBuilder(["at_a", "at_b", "flat", "spare"])
    b.action("move", pre=["at_a"], neg=["flat"],
             outcomes=[("1/2", ["at_b"], ["at_a"]), ("1/2", ["at_b", "flat"], ["at_a"])])
    b.action("change", pre=["flat", "spare"], outcomes=[(1, [], ["flat", "spare"])])
    return b


def test_tree_leaves_and_probabilities():
    b = two_stage_model()
    model = b.build(init=["at_a"], goal=["at_b"], goal_neg=["flat"])
    sol = solve(model)
    root = policy_tree(model, sol, depth=5)
    assert model.actions[root.action].name == "move"
    paths = list(iter_paths(root))
    assert sum(p for p, _ in paths) == pytest.approx(1.0)
    assert count_leaves(root) == {"goal": pytest.approx(0.5), "dead_end": pytest.approx(0.5)}
    for prob, nodes in paths:
        assert nodes[0] is root and nodes[-1].leaf is not None
        assert [n.depth for n in nodes] == list(range(len(nodes)))
    # The edge order follows action.outcomes(state).
    outs = model.actions[root.action].outcomes(model.init)
    for edge in root.children:
        assert edge.child.state == outs[edge.outcome].apply(model.init)
        assert edge.probability == float(outs[edge.outcome].probability)


def test_tree_from_another_state_and_horizon_leaves():
    b = two_stage_model()
    model = b.build(init=["at_a", "spare"], goal=["at_b"], goal_neg=["flat"])
    sol = solve(model)
    assert sol.goal_probability == pytest.approx(1.0)
    assert sol.expected_cost == pytest.approx(1.5)
    shallow = policy_tree(model, sol, depth=1)
    assert count_leaves(shallow) == {"goal": pytest.approx(0.5), "horizon": pytest.approx(0.5)}
    flat_state = b.mask(["at_b", "flat", "spare"])
    sub = policy_tree(model, sol, init=flat_state, depth=3)
    assert model.actions[sub.action].name == "change"
    assert count_leaves(sub) == {"goal": pytest.approx(1.0)}


def test_tree_of_finite_horizon_policy_ends_at_horizon():
    b = ModelBuilder(["done"])
    b.action("try", outcomes=[("1/2", ["done"], [])])
    model = b.build(init=[], goal=["done"])
    sol = solve(model, SolverOptions(dead_end_cost=10, horizon=3))
    root = policy_tree(model, sol, depth=10)
    mass = count_leaves(root)
    assert mass["goal"] == pytest.approx(1 - 0.5 ** 3) == pytest.approx(sol.goal_probability)
    assert mass["horizon"] == pytest.approx(0.5 ** 3)
    assert max(len(nodes) for _, nodes in iter_paths(root)) == 4


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(min_value=0, max_value=10**6), algorithm=st.sampled_from(["lao", "lrtdp"]))
def test_simulated_cost_agrees_with_expected_cost(seed, algorithm):
    model = random_model(seed)
    sol = solve(model, SolverOptions(algorithm=algorithm, dead_end_cost=50, epsilon=1e-8))
    sim = simulate(model, sol, runs=1500, seed=seed)
    # 4.5 standard errors: a wrong expectation is caught, sampling noise essentially never.
    se = max(sim.cost_stderr, 1e-9)
    assert abs(sim.mean_cost - sol.expected_cost) <= 4.5 * se + 1e-6
    lo, hi = sim.goal_rate_ci95
    assert lo - 0.03 <= sol.goal_probability <= hi + 0.03


def test_simulation_is_seeded_and_inside_ci():
    b = ModelBuilder(["done"])
    b.action("try", outcomes=[("1/4", ["done"], [])])
    model = b.build(init=[], goal=["done"])
    sol = solve(model, SolverOptions(epsilon=1e-9))
    a = simulate(model, sol, runs=4000, seed=7)
    assert a == simulate(model, sol, runs=4000, seed=7)
    assert a != simulate(model, sol, runs=4000, seed=8)
    assert a.cost_ci95[0] <= sol.expected_cost <= a.cost_ci95[1]
    assert a.goal_rate == 1.0 and a.truncated == 0
    with pytest.raises(StampcError):
        simulate(model, sol, runs=0, seed=1)


def test_simulation_stops_at_its_deadline():
    import time
    b = ModelBuilder(["done"])
    b.action("try", outcomes=[("1/4", ["done"], [])])
    model = b.build(init=[], goal=["done"])
    sol = solve(model, SolverOptions(epsilon=1e-9))
    past = simulate(model, sol, runs=50, seed=7, deadline=time.perf_counter() - 1.0)
    assert past.runs == 0 and past.stopped_at_deadline
    later = simulate(model, sol, runs=50, seed=7, deadline=time.perf_counter() + 60.0)
    assert later == simulate(model, sol, runs=50, seed=7)  # an unreached deadline changes nothing
    assert later.runs == 50 and not later.stopped_at_deadline


def test_warm_resolve_reuses_values():
    b = ModelBuilder([f"s{i}" for i in range(12)])
    for i in range(11):
        b.action(f"step{i}", pre=[f"s{i}"], outcomes=[("2/3", [f"s{i + 1}"], [f"s{i}"])])
    model = b.build(init=["s0"], goal=["s11"])
    first = solve(model, SolverOptions(heuristic="zero", epsilon=1e-9))
    assert first.expected_cost == pytest.approx(11 * 1.5)
    later = b.mask(["s4"])
    cold = solve(model, SolverOptions(heuristic="zero", epsilon=1e-9), init=later)
    warm = solve(model, SolverOptions(heuristic="zero", epsilon=1e-9), init=later, warm=first)
    assert warm.expected_cost == pytest.approx(cold.expected_cost) == pytest.approx(7 * 1.5)
    # Nothing new to expand: every state below s4 was already solved.
    assert cold.states_expanded == 7 and warm.states_expanded == 0
    assert first.value(model.init) == pytest.approx(16.5)  # the old solution is untouched


def test_warm_resolve_with_more_forbidden_actions():
    b = ModelBuilder(["start", "goal", "mid"])
    b.action("direct", pre=["start"], outcomes=[(1, ["goal"], ["start"])], cost=2)
    b.action("detour", pre=["start"], outcomes=[(1, ["mid"], ["start"])], cost=1)
    b.action("finish", pre=["mid"], outcomes=[(1, ["goal"], ["mid"])], cost=3)
    model = b.build(init=["start"], goal=["goal"])
    first = solve(model)
    assert first.expected_cost == 2
    banned = frozenset({(model.init, 0)})
    second = solve(model, SolverOptions(forbidden=banned), warm=first)
    assert second.expected_cost == 4
    assert model.actions[second.action(model.init)].name == "detour"
    # Allowing the action again must not reuse the (now too high) values.
    third = solve(model, SolverOptions(), warm=second)
    assert third.expected_cost == 2
