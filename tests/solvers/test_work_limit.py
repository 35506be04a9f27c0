"""Work limits: a solve capped by ``SolverOptions.work_limit`` (``Search.work``) stops at
the same point every time, whatever the machine's speed — unlike a time limit."""

from __future__ import annotations

import pytest

from ssp_builders import random_model, reachable_states
from stampc.diagnostics import StampcError
from stampc.solvers import SolverOptions, make_heuristic, solve
from stampc.solvers.core import expansion_work
from stampc.solvers.determinized import with_greedy_plan

#: random models whose h_max LAO* needs thousands of work units (seed: units measured)
SEEDS = (1, 2, 5, 7)


def _model(seed: int):
    return random_model(seed, n_facts=14, n_actions=40)


def _fingerprint(solution):
    search = solution.search
    return (solution.converged, solution.states_expanded, search.work, solution.expected_cost,
            tuple(sorted(search.best.items())))


@pytest.mark.parametrize("seed", SEEDS)
def test_a_capped_solve_stops_at_the_same_point_every_time(seed):
    model = _model(seed)
    full = solve(model, SolverOptions(heuristic="hmax"))
    assert full.converged and full.search.work > 1000
    limit = full.search.work // 3
    capped = [solve(model, SolverOptions(heuristic="hmax", work_limit=limit)) for _ in range(3)]
    assert not capped[0].converged
    assert len({_fingerprint(s) for s in capped}) == 1
    # stopped at the first check past the limit: at most one check interval (8
    # expansions and their backups) beyond it
    assert limit < capped[0].search.work < full.search.work
    assert capped[0].states_expanded < full.states_expanded


@pytest.mark.parametrize("seed", SEEDS)
def test_a_limit_above_the_solves_work_changes_nothing(seed):
    model = _model(seed)
    full = solve(model, SolverOptions(heuristic="hmax"))
    roomy = solve(model, SolverOptions(heuristic="hmax", work_limit=full.search.work + 1))
    assert _fingerprint(roomy) == _fingerprint(full)


def test_work_counts_heuristic_evaluations_expansions_and_backups():
    full = solve(_model(2), SolverOptions(heuristic="hmax"))
    search = full.search
    assert search.generated == len(search.V) - 1  # every node but the root was generated
    assert search.expansions == len(search.expanded) == full.states_expanded
    assert search.backed_up >= sum(len(t) for t in search.expanded.values())
    # a small model: every evaluation is cheaper than a unit, and counts one
    assert search.space.h.effort() == 0.0 and search.expansion_work == 1.0
    assert search.work == search.expansions + search.generated + search.backed_up // 50


def test_an_evaluation_costlier_than_a_unit_counts_its_cost():
    # the same kind of model with 100 times the actions (680 relaxed ones): an evaluation
    # scans and updates over a thousand counters and counts ~1.8 units, not one (its CPU
    # time measured: ~285 µs, 2.2 units of 130 µs)
    for n_actions, low, high in ((20, 0.0, 0.0), (2000, 0.5, 3.0)):
        model = random_model(3, n_facts=10, n_actions=n_actions)
        h = make_heuristic("hadd", model, False)
        states = reachable_states(model)[:40]
        for s in states:
            h(s)
        assert low <= h.effort() / len(states) <= high, n_actions
    before = h.effort()
    h(states[0])  # cached: costs nothing
    assert h.effort() == before


def test_a_search_counts_its_costlier_evaluations_beyond_one_unit_each():
    model = random_model(3, n_facts=10, n_actions=2000)
    solution = solve(model, SolverOptions(heuristic="hadd"))
    search = solution.search
    plain = search.expansions + search.generated + search.backed_up // 50
    excess = search.space.h.effort()  # the solve's own heuristic: all of it is this search's
    assert excess > 0.5 * search.generated
    assert search.work == int(plain + excess)


def test_an_expansion_counts_by_the_width_of_the_state():
    assert expansion_work(100) == 1.0
    assert expansion_work(5_463) == 1.0  # 25 cans, where the units were fitted
    assert expansion_work(36_483) == pytest.approx(6.63, abs=0.01)  # 60 cans


@pytest.mark.parametrize("seed", (1, 2))
def test_the_determinized_plan_of_a_capped_solve_respects_its_own_work_cap(seed):
    """Without a heuristic the greedy plan search needs thousands of units here: a cap
    of a tenth of them gives no plan, the same way every time, and stops near it."""
    def capped():
        return solve(_model(seed), SolverOptions(heuristic="zero", work_limit=1))

    solution = capped()
    before = solution.search.work
    planned = with_greedy_plan(solution, 60.0)
    assert planned is not None and planned[1] > 1
    needed = solution.search.work - before
    assert needed > 1000
    works = set()
    for _ in range(2):
        solution = capped()
        start = solution.search.work
        assert with_greedy_plan(solution, 60.0, work_limit=needed // 10) is None
        works.add(solution.search.work)
        assert needed // 10 < solution.search.work - start < needed
    assert len(works) == 1


@pytest.mark.parametrize("bad", (0, -5))
def test_a_work_limit_below_one_is_a_located_error(bad):
    with pytest.raises(StampcError) as err:
        solve(_model(1), SolverOptions(work_limit=bad))
    assert {d.code for d in err.value.diagnostics} == {"S006"}
    assert "work limit" in err.value.diagnostics[0].message
