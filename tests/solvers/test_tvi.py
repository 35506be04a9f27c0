"""Topological VI: same values as the oracle; components come successors first."""

from __future__ import annotations

import pytest
from ssp_builders import (random_conditional_model, random_model, reference_finite,
                          reference_values)

from stampc.solvers import SolverOptions, solve
from stampc.solvers.bounds import solve_bounded
from stampc.solvers.core import Search
from stampc.solvers.heuristics import make_heuristic
from stampc.solvers.space import Space
from stampc.solvers.successors import SuccessorCache
from stampc.solvers.tvi import components
from stampc.solvers.vi import reachable

D = 50.0


@pytest.mark.parametrize("make", [random_model, random_conditional_model])
def test_tvi_matches_reference_values(make):
    for seed in range(60):
        model = make(seed, n_facts=6, n_actions=9)
        exact = reference_values(model, D)[model.init]
        sol = solve(model, SolverOptions(algorithm="tvi", dead_end_cost=D, epsilon=1e-10))
        assert sol.expected_cost == pytest.approx(exact, abs=1e-6)
        _, b = solve_bounded(model, SolverOptions(algorithm="tvi", dead_end_cost=D))
        assert b.lower - 1e-9 <= exact <= b.upper + 1e-9 and b.certified


def test_tvi_finite_horizon_is_backward_induction():
    for seed in range(20):
        model = random_model(seed)
        sol = solve(model, SolverOptions(algorithm="tvi", dead_end_cost=D, horizon=4))
        assert sol.expected_cost == pytest.approx(reference_finite(model, D, 4), abs=1e-9)


def test_components_partition_nodes_in_reverse_topological_order():
    for seed in range(30):
        model = random_model(seed, n_facts=6, n_actions=9)
        search = Search(Space(SuccessorCache(model), make_heuristic("zero", model, False), D))
        nodes = reachable(search, model.init)
        comps = components(search, nodes)
        assert sorted(n for c in comps for n in c) == sorted(nodes)
        position = {n: i for i, c in enumerate(comps) for n in c}
        for x in nodes:  # every edge goes to the same or an earlier component
            for _, _, _, nexts in search.expanded[x]:
                for n in nexts:
                    if n in position:
                        assert position[n] <= position[x]
