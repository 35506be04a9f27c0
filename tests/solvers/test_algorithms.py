"""Hand-computed SSPs: values, dead ends, goal probability, horizon, forbidden actions."""

from __future__ import annotations

import pytest

from ssp_builders import ModelBuilder
from stampc.diagnostics import StampcError
from stampc.solvers import SolverOptions, solve
from stampc.solvers.space import ANY_STATE

ALGOS = ("lao", "lrtdp", "vi")


def geometric_model():
    """``try`` reaches the goal with probability 1/4, otherwise nothing happens."""
    b = ModelBuilder(["done"])
    b.action("try", outcomes=[("1/4", ["done"], [])], cost=1)
    return b.build(init=[], goal=["done"])


def risky_or_safe_model():
    """risky: cost 1, goal or dead end with 1/2 each; safe: cost 10, goal for sure."""
    b = ModelBuilder(["start", "goal", "broken"])
    b.action("risky", pre=["start"], outcomes=[("1/2", ["goal"], ["start"]),
                                                ("1/2", ["broken"], ["start"])], cost=1)
    b.action("safe", pre=["start"], outcomes=[(1, ["goal"], ["start"])], cost=10)
    return b.build(init=["start"], goal=["goal"])


@pytest.mark.parametrize("algorithm", ALGOS)
@pytest.mark.parametrize("heuristic", ("zero", "hmax"))
def test_geometric_expected_cost_is_inverse_probability(algorithm, heuristic):
    sol = solve(geometric_model(), SolverOptions(algorithm=algorithm, heuristic=heuristic,
                                                 epsilon=1e-9))
    assert sol.expected_cost == pytest.approx(4.0, abs=1e-6)
    assert sol.goal_probability == pytest.approx(1.0)
    assert sol.converged


@pytest.mark.parametrize("algorithm", ALGOS)
def test_dead_end_cost_decides_between_risky_and_safe(algorithm):
    model = risky_or_safe_model()
    high = solve(model, SolverOptions(algorithm=algorithm, dead_end_cost=500))
    assert high.expected_cost == pytest.approx(10.0)
    assert model.actions[high.action(model.init)].name == "safe"
    assert high.goal_probability == pytest.approx(1.0)
    # With D = 10 the gamble costs 1 + 10/2 = 6 < 10.
    low = solve(model, SolverOptions(algorithm=algorithm, dead_end_cost=10))
    assert low.expected_cost == pytest.approx(6.0)
    assert model.actions[low.action(model.init)].name == "risky"
    assert low.goal_probability == pytest.approx(0.5)


def test_unit_cost_ignores_declared_costs():
    model = risky_or_safe_model()
    sol = solve(model, SolverOptions(unit_cost=True, dead_end_cost=500))
    assert sol.expected_cost == pytest.approx(1.0)  # safe now costs 1
    assert model.actions[sol.action(model.init)].name == "safe"


@pytest.mark.parametrize("algorithm", ALGOS)
def test_forbidden_action_is_avoided(algorithm):
    model = risky_or_safe_model()
    safe = next(a.index for a in model.actions if a.name == "safe")
    sol = solve(model, SolverOptions(algorithm=algorithm,
                                     forbidden=frozenset({(model.init, safe)})))
    assert model.actions[sol.action(model.init)].name == "risky"
    assert sol.expected_cost == pytest.approx(1 + 0.5 * 500)
    assert sol.goal_probability == pytest.approx(0.5)


def test_no_applicable_action_costs_dead_end_cost():
    b = ModelBuilder(["a", "g"])
    b.action("needs_a", pre=["a"], outcomes=[(1, ["g"], [])])
    model = b.build(init=[], goal=["g"])
    for algorithm in ALGOS:
        for heuristic in ("zero", "hmax"):
            sol = solve(model, SolverOptions(algorithm=algorithm, heuristic=heuristic,
                                             dead_end_cost=77))
            assert sol.expected_cost == 77
            assert sol.goal_probability == 0
            assert sol.action(model.init) is None


def test_goal_at_init_costs_nothing():
    b = ModelBuilder(["g"])
    b.action("noop", outcomes=[(1, [], [])])
    sol = solve(b.build(init=["g"], goal=["g"]))
    assert sol.expected_cost == 0 and sol.goal_probability == 1
    assert sol.action(sol.init) is None


def test_conditional_effects_are_state_dependent():
    b = ModelBuilder(["key", "door", "goal"])
    # open: with the key the door opens for sure, without it with probability 1/5.
    b.action("open", effect=b.effect(whens=[(b.cond(["key"]), b.effect(["door"]))]), cost=1)
    b.action("lucky", neg=["key"], outcomes=[("1/5", ["door"], [])], cost=1)
    b.action("take_key", outcomes=[(1, ["key"], [])], cost=1)
    b.action("enter", pre=["door"], outcomes=[(1, ["goal"], [])], cost=1)
    model = b.build(init=[], goal=["goal"])
    for algorithm in ALGOS:
        sol = solve(model, SolverOptions(algorithm=algorithm, epsilon=1e-9))
        # take_key, open, enter = 3 beats lucky (5 expected) + enter = 6.
        assert sol.expected_cost == pytest.approx(3.0)


@pytest.mark.parametrize("algorithm", ALGOS)
def test_finite_horizon_backward_induction(algorithm):
    # V(t=1) = min(D, 1 + D/2) = 6 with D = 10; V(t=0) = 1 + 6/2 = 4; P(goal) = 3/4.
    b = ModelBuilder(["done"])
    b.action("try", outcomes=[("1/2", ["done"], [])])
    model = b.build(init=[], goal=["done"])
    sol = solve(model, SolverOptions(algorithm=algorithm, dead_end_cost=10, horizon=2))
    assert sol.expected_cost == pytest.approx(4.0)
    assert sol.value(model.init, 1) == pytest.approx(6.0)
    assert sol.value(model.init, 2) == 10.0
    assert sol.goal_probability == pytest.approx(0.75)
    assert sol.action(model.init, 2) is None
    assert sol.action(model.init, 1) == 0


def test_finite_horizon_policy_is_non_stationary():
    # Early on, the slow sure route (2 steps) wins; with one step left only the gamble can
    # still reach the goal.
    b = ModelBuilder(["mid", "goal"])
    b.action("gamble", outcomes=[("1/2", ["goal"], [])], cost=2)
    b.action("step1", neg=["mid"], outcomes=[(1, ["mid"], [])], cost=1)
    b.action("step2", pre=["mid"], outcomes=[(1, ["goal"], [])], cost=1)
    model = b.build(init=[], goal=["goal"], horizon=3)
    sol = solve(model, SolverOptions(algorithm="vi", dead_end_cost=100))
    assert sol.horizon == 3
    assert model.actions[sol.action(model.init, 0)].name == "step1"
    assert model.actions[sol.action(model.init, 2)].name == "gamble"


def test_bad_options_raise_located_diagnostics():
    model = geometric_model()
    with pytest.raises(StampcError) as err:
        solve(model, SolverOptions(algorithm="dfs", heuristic="magic", epsilon=0))
    codes = {d.code for d in err.value.diagnostics}
    assert codes == {"S001", "S002", "S003"}


def test_time_limit_reports_not_converged():
    b = ModelBuilder([f"b{i}" for i in range(14)] + ["goal"])
    for i in range(14):
        b.action(f"flip{i}", outcomes=[("1/2", [f"b{i}"], []), ("1/2", [], [f"b{i}"])])
    b.action("finish", pre=[f"b{i}" for i in range(14)], outcomes=[(1, ["goal"], [])])
    sol = solve(b.build(init=[], goal=["goal"]),
                SolverOptions(algorithm="vi", heuristic="zero", time_limit=0.05, epsilon=1e-12))
    assert not sol.converged


def test_horizon_shorter_than_any_plan_costs_dead_end_without_search():
    b = ModelBuilder([f"s{i}" for i in range(8)])
    for i in range(7):
        b.action(f"step{i}", pre=[f"s{i}"], outcomes=[("1/2", [f"s{i + 1}"], [f"s{i}"])])
    model = b.build(init=["s0"], goal=["s7"])
    for algorithm in ALGOS:
        sol = solve(model, SolverOptions(algorithm=algorithm, horizon=6, dead_end_cost=40))
        # Seven steps are needed, six are left: the goal is out of reach.
        assert sol.expected_cost == 40 and sol.goal_probability == 0
        assert sol.states_expanded == 0


def _locked_model(switches: int = 10):
    """``unlock`` is the only way to the goal; ``switches`` independent toggles make
    2**switches states from which no other action leads there."""
    names = [f"s{i}" for i in range(switches)]
    b = ModelBuilder(names + ["open", "g"])
    for name in names:
        b.action(f"on_{name}", neg=[name], outcomes=[(1, [name], [])])
        b.action(f"off_{name}", pre=[name], outcomes=[(1, [], [name])])
    unlock = b.action("unlock", outcomes=[(1, ["open"], [])])
    b.action("finish", pre=["open"], outcomes=[(1, ["g"], [])])
    return b.build(init=[], goal=["g"]), unlock


@pytest.mark.parametrize("heuristic", ("hmax", "hadd", "hff"))
def test_a_state_needing_an_action_banned_everywhere_is_a_recognised_dead_end(heuristic):
    model, unlock = _locked_model()
    free = solve(model, SolverOptions(heuristic=heuristic))
    assert free.goal_probability == 1
    everywhere = solve(model, SolverOptions(heuristic=heuristic,
                                            forbidden=frozenset({(ANY_STATE, unlock)})))
    assert everywhere.goal_probability == 0 and everywhere.converged
    assert len(everywhere.search.V) == 1  # the relaxation, not the 1,024 states, says so
    # the same from a warm start whose tables knew no ban
    warm = solve(model, SolverOptions(heuristic=heuristic,
                                      forbidden=frozenset({(ANY_STATE, unlock)})), warm=free)
    assert warm.goal_probability == 0 and len(warm.search.V) == 1
    # a ban in one state is no ban in the relaxation: the search has to look around
    here = solve(model, SolverOptions(heuristic=heuristic,
                                      forbidden=frozenset({(model.init, unlock)})))
    assert here.goal_probability == 1 and len(here.search.V) > 1
