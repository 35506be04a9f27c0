"""The layered h_max (``layered.py``) carries its counters from the previously evaluated
state: whatever the order of evaluation, it must give exactly the values of the
generalised-Dijkstra h_max, which counts every state from the initial one."""

from __future__ import annotations

import random

import pytest
from hypothesis import given, settings, strategies as st
from ssp_builders import random_model, reachable_states

from stampc import api
from stampc.solvers.heuristics import RelaxedModel, _relaxed_cost
from stampc.solvers.successors import SuccessorCache


def _dijkstra_hmax(model, states: list[int]) -> list[float]:
    rm = RelaxedModel(model, True)
    rm.layered = None  # the generalised Dijkstra of _relaxed_cost
    return [_relaxed_cost(rm, s, "max") for s in states]


def _layered_hmax(model, states: list[int]) -> list[float]:
    rm = RelaxedModel(model, True)
    assert rm.layered is not None
    return [_relaxed_cost(rm, s, "max") for s in states]


def _reachable(model, limit: int) -> list[int]:
    """Up to ``limit`` states reachable from the initial state, breadth-first."""
    cache = SuccessorCache(model, True)
    seen, order = {model.init}, [model.init]
    for s in order:
        if len(order) >= limit:
            break
        for _, _, _, nexts in cache.transitions(s):
            for n in nexts:
                if n not in seen:
                    seen.add(n)
                    order.append(n)
    return order[:limit]


@pytest.mark.parametrize("instance", ["mdplib-ex-blocksworld-fixed/p02.pddl",
                                      "ippc2008-blocksworld/p01.pddl",
                                      "ippc2006-elevators/p01.pddl",
                                      "ippc2008-triangle-tireworld/p02.pddl",
                                      "ippc2006-schedule/p02.pddl",
                                      "ippc2008-search-and-rescue/p01-z4.pddl"])
def test_layered_hmax_equals_dijkstra_in_any_order(ppddl_benchmarks, instance):
    path = ppddl_benchmarks / instance
    if not path.is_file():
        pytest.skip(f"{instance} not found")
    model = api.ground(api.load_model([str(path)]))
    states = _reachable(model, 1500)
    shuffled = list(states)
    random.Random(0).shuffle(shuffled)
    for order in (states, shuffled, states[::-1]):
        assert _layered_hmax(model, order) == _dijkstra_hmax(model, order)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(min_value=0, max_value=10**6))
def test_layered_hmax_equals_dijkstra_on_random_models(seed):
    model = random_model(seed)
    states = reachable_states(model)
    random.Random(seed).shuffle(states)
    assert _layered_hmax(model, states + states) == _dijkstra_hmax(model, states + states)
