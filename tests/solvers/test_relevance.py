"""Irrelevant facts (``relevance.py``): a state and its reduction have the same optimal
value, on random SSPs against the independent oracle and on triangle-tireworld."""

from __future__ import annotations

import dataclasses

import pytest

from ssp_builders import (ModelBuilder, random_conditional_model, random_model,
                          reachable_states, reference_values)
from stampc import api
from stampc.solvers import SolverOptions, solve
from stampc.solvers.bounds import solve_bounded
from stampc.solvers.relevance import Relevance

D = 50.0


def _value_from(model, state: int, unit: bool) -> float:
    return reference_values(dataclasses.replace(model, init=state), D, unit_cost=unit)[state]


def _check_reductions(model, unit: bool) -> int:
    """Asserts V*(s) = V*(c(s)) for every reachable s, and V*(t) = V*(t reduced with
    its parent s's clearable facts) for every next state t; returns how many differ."""
    relevance = Relevance(model)
    values = reference_values(model, D, unit_cost=unit)
    from_reduced: dict[int, float] = {}  # V* from each reduced state, solved once
    reduced = 0
    for s in reachable_states(model):
        pairs = [(s, relevance.canonical(s))]
        if not model.is_goal(s):
            for a in model.actions:
                if a.precondition.holds(s):
                    outs = [(1.0, o.apply(s), 0.0) for o in a.outcomes(s)]
                    pairs += [(t, c) for (_, t, _), (_, c, _) in
                              zip(outs, relevance.reduce(s, outs))]
        for t, c in pairs:
            assert c & ~t == 0  # facts are only cleared
            if c != t:
                reduced += 1
                if c not in from_reduced:
                    from_reduced[c] = _value_from(model, c, unit)
                assert from_reduced[c] == pytest.approx(values[t], abs=1e-7), (t, c)
    return reduced


@pytest.mark.parametrize("builder", [random_model, random_conditional_model])
def test_reduced_states_keep_the_oracle_value(builder):
    reduced = sum(_check_reductions(builder(seed, n_facts=6), unit=seed % 2 == 0)
                  for seed in range(60))
    assert reduced > 20  # the reduction does happen on these models


def test_a_fact_whose_absence_enables_an_action_is_kept():
    # p holds and nothing deletes it, so no reachable action reads it — but clearing it
    # would enable the cheap shortcut needing (not p): V would drop from 5 to 1
    b = ModelBuilder(["p", "g", "x"])
    b.action("slow", outcomes=[(1, ["g"], [])], cost=5)
    b.action("shortcut", neg=["p"], outcomes=[(1, ["g"], [])], cost=1)
    b.action("touch-x", outcomes=[(1, ["x"], [])], cost=1)
    model = b.build(init=["p"], goal=["g"])
    relevance = Relevance(model)
    assert relevance.canonical(model.init) == model.init
    # x is read by nothing at all, and its absence enables nothing: cleared
    with_x = model.init | 1 << b.index["x"]
    assert relevance.canonical(with_x) == model.init


def _model(ppddl_benchmarks, instance: str):
    path = ppddl_benchmarks / instance
    if not path.is_file():
        pytest.skip(f"{instance} not found")
    return api.ground(api.load_model([str(path)]))


@pytest.mark.parametrize("instance", ["ippc2008-triangle-tireworld/p01.pddl",
                                      "mdplib-triangle-tireworld-60/p02.pddl"])
def test_triangle_tireworld_values_match_the_full_ssp(ppddl_benchmarks, instance):
    model = _model(ppddl_benchmarks, instance)
    opts = dict(algorithm="vi", heuristic="zero", unit_cost=True, epsilon=1e-10)
    full = solve(model, SolverOptions(**opts))
    reduced = solve(model, SolverOptions(**opts, relevance=True))
    assert reduced.expected_cost == pytest.approx(full.expected_cost, abs=1e-7)
    assert len(reduced.search.V) < len(full.search.V)  # the spares left behind merged
    checked = 0
    for s, v in reduced.search.V.items():  # a reduced state is worth its full value
        if s in reduced.search.expanded and s in full.search.V:
            checked += 1
            assert v == pytest.approx(full.search.V[s], abs=1e-7), s
    assert checked > 10


def test_triangle_tireworld_p04_certifies_the_reference_value(ppddl_benchmarks):
    model = _model(ppddl_benchmarks, "ippc2008-triangle-tireworld/p04.pddl")
    sol, bounds = solve_bounded(model, SolverOptions(unit_cost=True, relevance=True,
                                                     time_limit=60))
    assert bounds.certified and sol.states_expanded < 1000  # 74,917 without
    assert bounds.lower - 1e-4 <= 27.054626 <= bounds.upper + 1e-4  # the C++ LAO* V0
