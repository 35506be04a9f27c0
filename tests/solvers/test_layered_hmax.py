"""The layered h_max (``layered.py``) carries its counters from the previously evaluated
state: whatever the order of evaluation, it must give exactly the values of the
generalised-Dijkstra h_max, which counts every state from the initial one."""

from __future__ import annotations

import random

import pytest
from hypothesis import given, settings, strategies as st
from ssp_builders import breadth_first_states, ippc_model, shuffled_random_instance

from stampc.solvers.heuristics import RelaxedModel, _relaxed_cost


def _dijkstra_hmax(model, states: list[int]) -> list[float]:
    rm = RelaxedModel(model, True)
    rm.layered = None  # the generalised Dijkstra of _relaxed_cost
    return [_relaxed_cost(rm, s, "max") for s in states]


def _layered_hmax(model, states: list[int]) -> list[float]:
    rm = RelaxedModel(model, True)
    assert rm.layered is not None
    return [_relaxed_cost(rm, s, "max") for s in states]


@pytest.mark.parametrize("instance", ["mdplib-ex-blocksworld-fixed/p02.pddl",
                                      "ippc2008-blocksworld/p01.pddl",
                                      "ippc2006-elevators/p01.pddl",
                                      "ippc2008-triangle-tireworld/p02.pddl",
                                      "ippc2006-schedule/p02.pddl",
                                      "ippc2008-search-and-rescue/p01-z4.pddl"])
def test_layered_hmax_equals_dijkstra_in_any_order(ppddl_benchmarks, instance):
    model = ippc_model(ppddl_benchmarks, instance)
    states = breadth_first_states(model, 1500)
    shuffled = list(states)
    random.Random(0).shuffle(shuffled)
    for order in (states, shuffled, states[::-1]):
        assert _layered_hmax(model, order) == _dijkstra_hmax(model, order)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(min_value=0, max_value=10**6))
def test_layered_hmax_equals_dijkstra_on_random_models(seed):
    model, states = shuffled_random_instance(seed)
    assert _layered_hmax(model, states + states) == _dijkstra_hmax(model, states + states)
