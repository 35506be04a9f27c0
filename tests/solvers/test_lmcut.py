"""LM-cut: admissible on every reachable state, at least h_max without ``when`` effects."""

from __future__ import annotations

import math

import pytest
from ssp_builders import random_conditional_model, random_model, reference_values

from stampc import api
from stampc.solvers import SolverOptions, solve
from stampc.solvers.heuristic_choice import make_heuristic

D = 50.0


@pytest.mark.parametrize("make", [random_model, random_conditional_model])
@pytest.mark.parametrize("unit_cost", [True, False])
def test_lmcut_never_exceeds_optimal_cost_on_any_state(make, unit_cost):
    stronger = 0
    for seed in range(60):
        model = make(seed)
        exact = reference_values(model, D, unit_cost=unit_cost)
        lm = make_heuristic("lmcut", model, unit_cost)
        hmax = make_heuristic("hmax", model, unit_cost)
        for state, value in exact.items():
            h = lm(state)
            assert min(h, D) <= value + 1e-9, (seed, state)
            assert h >= hmax(state) - 1e-9
            assert (h == math.inf) == (hmax(state) == math.inf)  # same dead ends
            stronger += h > hmax(state) + 1e-9
    if make is random_model:  # without ``when`` effects it is strictly more informed
        assert stronger > 0


@pytest.mark.parametrize("instance", ["ippc2006-tireworld/p03.pddl",
                                      "ippc2008-blocksworld/p01.pddl",
                                      "ippc2006-elevators/p01.pddl"])
def test_lmcut_admissible_on_ippc_states_and_same_optimum(ppddl_benchmarks, instance):
    model = api.ground(api.load_model([str(ppddl_benchmarks / instance)]))
    vi = solve(model, SolverOptions(algorithm="vi", heuristic="zero", unit_cost=True,
                                    epsilon=1e-10))
    lm = make_heuristic("lmcut", model, True)
    for x, value in vi.search.V.items():
        assert min(lm(x), 500.0) <= value + 1e-6
    lao = solve(model, SolverOptions(heuristic="lmcut", unit_cost=True, epsilon=1e-8))
    assert lao.expected_cost == pytest.approx(vi.expected_cost, abs=1e-5)
