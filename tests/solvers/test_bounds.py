"""Certified bounds (stampc.solvers.bounds): they bracket the exact optimal value."""

from __future__ import annotations

import json

import pytest
from ssp_builders import (ModelBuilder, _successors, random_conditional_model, random_model,
                          reference_finite, reference_from_above, reference_values)

from stampc import api
from stampc.cli import main
from stampc.solvers import SolverOptions, solve
from stampc.solvers.bounds import GapCheck, evaluate_policy, solve_bounded
from stampc.solvers.core import Search
from stampc.solvers.heuristics import make_heuristic
from stampc.solvers.space import Space
from stampc.solvers.successors import SuccessorCache

D = 50.0


@pytest.mark.parametrize("algorithm", ["lao", "lrtdp", "vi"])
@pytest.mark.parametrize("make", [random_model, random_conditional_model])
def test_bounds_bracket_exact_value_on_random_ssps(make, algorithm):
    for seed in range(60):
        model = make(seed)
        exact = reference_values(model, D)[model.init]
        _, b = solve_bounded(model, SolverOptions(algorithm=algorithm, dead_end_cost=D,
                                                  epsilon=1e-6))
        assert b.lower - 1e-9 <= exact <= b.upper + 1e-9, (seed, b)
        assert b.certified and b.gap <= 1e-6 * b.upper + 1e-12


def test_absolute_gap_mode_meets_absolute_target():
    for seed in range(30):
        model = random_model(seed)
        exact = reference_values(model, D)[model.init]
        sol, b = solve_bounded(model, SolverOptions(dead_end_cost=D, epsilon=1e-3),
                               relative=False)
        assert not b.relative and b.gap <= 1e-3 and sol.converged
        assert b.lower - 1e-9 <= exact <= b.upper + 1e-9


@pytest.mark.parametrize("heuristic,weight", [("hff", 1.0), ("hadd", 1.0), ("hmax", 3.0)])
def test_inadmissible_modes_report_policy_value_without_lower_bound(heuristic, weight):
    for seed in range(40):
        model = random_model(seed)
        exact = reference_values(model, D)[model.init]
        _, b = solve_bounded(model, SolverOptions(heuristic=heuristic, weight=weight,
                                                  dead_end_cost=D))
        assert b.lower is None and b.gap is None and not b.certified
        assert b.upper >= exact - 1e-9  # a real policy's cost: never below the optimum
        assert 0.0 <= b.goal_probability <= 1.0


def _policy_reference(model, solution, dead_end_cost):
    """(cost, goal probability) of ``solution``'s policy from the initial state, by Jacobi
    iteration on the model's exact outcome lists (give-up = D, as the bounds assume)."""
    succ, order, stack = {}, [model.init], [model.init]
    while stack:
        s = stack.pop()
        a = None if model.is_goal(s) else solution.action(s)
        if a is None:
            continue
        succ[s] = dict(_successors(model, s, False))[a]
        for _, n, _ in succ[s]:
            if n not in order:
                order.append(n)
                stack.append(n)
    V = {s: 0.0 for s in order}
    P = {s: float(model.is_goal(s)) for s in order}
    for s in order:
        if s not in succ and not model.is_goal(s):
            V[s] = dead_end_cost
    for _ in range(100_000):
        newV, newP = dict(V), dict(P)
        for s, outs in succ.items():
            q = sum(p * (c + V[n]) for p, n, c in outs)
            newV[s], newP[s] = (dead_end_cost, 0.0) if q >= dead_end_cost else \
                (q, sum(p * P[n] for p, n, _ in outs))
        change = max(abs(newV[s] - V[s]) + abs(newP[s] - P[s]) for s in order)
        V, P = newV, newP
        if change < 1e-13:
            break
    return V[model.init], P[model.init]


@pytest.mark.parametrize("heuristic,weight", [("hff", 1.0), ("hadd", 1.0), ("hmax", 3.0)])
@pytest.mark.parametrize("make", [random_model, random_conditional_model])
def test_inadmissible_modes_report_the_exact_value_of_their_policy(make, heuristic, weight):
    """policy_cost / policy_goal_probability are the returned policy's own figures (not
    V*), checked against an independent evaluation on exact outcome lists."""
    for seed in range(40):
        model = make(seed)
        sol, b = solve_bounded(model, SolverOptions(heuristic=heuristic, weight=weight,
                                                    dead_end_cost=D))
        cost, goal = _policy_reference(model, sol, D)
        assert abs(b.upper - cost) <= 1e-6 * max(1.0, cost), (seed, b.upper, cost)
        assert abs(b.goal_probability - goal) <= 1e-6, (seed, b.goal_probability, goal)


def test_policy_of_a_search_cut_short_is_still_an_upper_bound():
    """Unexpanded tips give up (cost D): the evaluated policy is real, its cost >= V*."""
    for seed in range(40):
        model = random_model(seed, n_facts=6, n_actions=9)
        exact = reference_values(model, D)[model.init]
        cache = SuccessorCache(model)
        search = Search(Space(cache, make_heuristic("hmax", model, False), D))
        search.seed(model.init)
        if model.init not in search.terminal:
            search.expand(model.init)
            if model.init not in search.terminal:
                search.backup(model.init)
        value = evaluate_policy(search, model.init)
        assert exact <= value.upper + 1e-9
        assert search.V[model.init] <= exact + 1e-9


def test_finite_horizon_bounds_bracket_backward_induction():
    for seed in range(30):
        model = random_model(seed)
        exact = reference_finite(model, D, horizon=4)
        _, b = solve_bounded(model, SolverOptions(dead_end_cost=D, horizon=4, epsilon=1e-8))
        assert b.lower - 1e-9 <= exact <= b.upper + 1e-9


def test_gap_is_closed_where_a_bellman_residual_stops_short():
    """A slowly mixing two-state cycle: a residual of 1e-3 stops LAO* far below V*; the
    certified loop keeps tightening until the bounds meet."""
    b = ModelBuilder(["x", "goal"])
    b.action("flip", neg=["x"], outcomes=[(0.98, ["x"], []), (0.02, ["goal"], [])])
    b.action("back", pre=["x"], outcomes=[(0.98, [], ["x"]), (0.02, ["goal"], [])])
    model = b.build(init=[], goal=["goal"])
    exact = reference_values(model, 500.0)[model.init]  # 50
    plain = solve(model, SolverOptions(dead_end_cost=500, epsilon=1e-3))
    assert exact - plain.expected_cost > 1e-3
    sol, bnd = solve_bounded(model, SolverOptions(dead_end_cost=500, epsilon=1e-8),
                             relative=False)
    assert bnd.lower - 1e-9 <= exact <= bnd.upper + 1e-9 and bnd.certified
    assert bnd.gap <= 1e-8 and bnd.rounds > 1 and sol.converged


def _trap_model():
    """a <-> b at zero cost; the delete relaxation believes `forge` (needs a and b at
    once) opens a cost-1 route, so LAO* first settles on the loop at value 1."""
    b = ModelBuilder(["a", "b", "key", "goal"])
    b.action("swap_ab", pre=["a"], outcomes=[(1, ["b"], ["a"])], cost=0)
    b.action("swap_ba", pre=["b"], outcomes=[(1, ["a"], ["b"])], cost=0)
    b.action("forge", pre=["a", "b"], outcomes=[(1, ["key"], [])], cost=0)
    b.action("use", pre=["key"], outcomes=[(1, ["goal"], [])], cost=1)
    exit_ = b.action("exit", pre=["a"], outcomes=[(1, ["goal"], [])], cost=10)
    return b.build(init=["a"], goal=["goal"]), exit_


def test_a_zero_cost_trap_is_eliminated_and_the_exit_certified():
    model, exit_ = _trap_model()
    assert solve(model, SolverOptions(dead_end_cost=D)).expected_cost == 1.0  # the trap
    sol, bnd = solve_bounded(model, SolverOptions(dead_end_cost=D))
    assert bnd.certified and bnd.lower == bnd.upper == 10.0 and bnd.goal_probability == 1.0
    assert sol.action(model.init) == exit_


def test_without_trap_elimination_a_trap_is_not_certified(monkeypatch):
    """The evaluation alone never certifies the loop: it gives up there (cost D)."""
    import stampc.solvers.bounds as bounds_module
    monkeypatch.setattr(bounds_module, "eliminate_traps", lambda search, init: 0)
    model, _ = _trap_model()
    _, bnd = solve_bounded(model, SolverOptions(dead_end_cost=D))
    assert bnd.lower == 1.0 and bnd.upper == D and not bnd.certified


@pytest.mark.parametrize("algorithm", ["lao", "lrtdp", "vi"])
def test_bounds_bracket_the_proper_optimum_with_zero_cost_cycles(algorithm):
    """Random models where half of the actions cost nothing: the interval contains the
    value iteration started from D (looping forever = failure), and with LAO* and VI the
    trap elimination closes the gap (LRTDP's solved labels keep raised values from
    propagating: bracketed, not always certified)."""
    zero_loops = 0
    for seed in range(60):
        model = random_model(seed, zero_cost_share=0.5)
        exact = reference_from_above(model, D)[model.init]
        zero_loops += reference_values(model, D)[model.init] < exact - 1e-6
        _, b = solve_bounded(model, SolverOptions(algorithm=algorithm, dead_end_cost=D,
                                                  epsilon=1e-6))
        assert b.lower - 1e-9 <= exact <= b.upper + 1e-9, (seed, b, exact)
        assert b.certified or algorithm == "lrtdp", (seed, b, exact)
    assert zero_loops > 0  # some models do have a zero-cost loop below the proper optimum


def test_gap_check_stops_lao_early_with_bracketing_bounds():
    """The between-pass check ends LAO* (residual 1e-9) as soon as the certified gap is
    1e-2; wherever it did, the bounds at that moment meet it and bracket V*."""
    stopped = 0
    for seed in range(60):
        model = random_model(seed)
        exact = reference_values(model, D)[model.init]
        check = GapCheck(relative=False, target=1e-2, deadline=None, min_interval=0.0)
        sol = solve(model, SolverOptions(dead_end_cost=D, epsilon=1e-9), stop=check)
        value = evaluate_policy(sol.search, sol.init)
        lower = sol.search.V[sol.init]
        assert lower - 1e-9 <= exact <= value.upper + 1e-9, seed
        if check.met:
            stopped += 1
            assert value.upper - lower <= 1e-2 + 1e-12, seed
    assert stopped > 0


PPDDL = ["ippc2006-tireworld/p03.pddl", "ippc2006-pitchcatch/p01.pddl",
         "ippc2008-blocksworld/p01.pddl", "ippc2008-triangle-tireworld/p01.pddl"]  # ex-blocksworld p01: VI at 1e-12 takes minutes


@pytest.mark.parametrize("instance", PPDDL)
def test_bounds_bracket_value_iteration_on_ippc_instances(ppddl_benchmarks, instance):
    model = api.ground(api.load_model([str(ppddl_benchmarks / instance)]))
    exact = solve(model, SolverOptions(algorithm="vi", heuristic="zero", unit_cost=True,
                                       epsilon=1e-12)).expected_cost
    _, b = solve_bounded(model, SolverOptions(unit_cost=True, epsilon=1e-4))
    assert b.lower - 1e-7 <= exact <= b.upper + 1e-7
    assert b.certified and b.gap <= 1e-4 * b.upper


from test_cli_solve import COIN  # noqa: E402  (the same coin, one definition)


def test_cli_json_reports_bounds_by_default(tmp_path, capsys):
    path = tmp_path / "coin.pddl"
    path.write_text(COIN)
    assert main(["solve", str(path), "--format", "json", "--dead-end-cost", "10"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["lower_bound"] <= 7.0 <= report["upper_bound"]
    assert report["gap"] <= 1e-4 * 7 and report["gap_mode"] == "relative"
    assert report["policy_goal_probability"] == pytest.approx(0.5)
    assert main(["solve", str(path), "--format", "json", "--no-bounds"]) == 0
    assert "lower_bound" not in json.loads(capsys.readouterr().out)
    assert main(["solve", str(path), "--format", "json", "--heuristic", "hff"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["lower_bound"] is None and report["policy_cost"] >= 7.0 - 1e-9
