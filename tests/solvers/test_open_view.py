"""h_add, h_max and h_FF derive each state's open literals, counts and adds from the
state evaluated before it (``open_view.py``): whatever the order of evaluation, every
value must equal the one a fresh relaxed model gives, whose view starts at the initial
state — and the view itself must equal one built from scratch."""

from __future__ import annotations

import random

import pytest
from hypothesis import given, settings, strategies as st
from ssp_builders import (breadth_first_states, ippc_model, random_model,
                          reachable_states, shuffled_random_instance)

from stampc.solvers.heuristics import RelaxedModel, _relaxed_cost, relaxed_state
from stampc.solvers.successors import iter_bits

MODES = ("add", "max", "ff")


def _fresh(model, state: int, mode: str) -> float:
    rm = RelaxedModel(model, False)
    rm.layered = None  # the generalised Dijkstra, whose view is the initial state's
    return _relaxed_cost(rm, state, mode)


def _carried(model, states: list[int], mode: str) -> list[float]:
    rm = RelaxedModel(model, False)
    rm.layered = None
    return [_relaxed_cost(rm, s, mode) for s in states]


def _view_from_scratch(rm: RelaxedModel, state: int):
    literals = relaxed_state(state & rm.full, rm.n, rm.full)
    open_literals = set(iter_bits(rm.useful & ~literals))
    counts = [(m & ~literals).bit_count() for m in rm.pre_masks]
    adds: dict[int, set[int]] = {}
    for g in open_literals:
        for i in rm.adders.get(g, ()):
            adds.setdefault(i, set()).add(g)
    return open_literals, counts, adds


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(min_value=0, max_value=10**6))
def test_carried_values_equal_fresh_ones_on_random_models(seed):
    model, states = shuffled_random_instance(seed)
    order = states + states[::-1]
    for mode in MODES:
        assert _carried(model, order, mode) == [_fresh(model, s, mode) for s in order]


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(min_value=0, max_value=10**6))
def test_the_carried_view_equals_one_built_from_scratch(seed):
    model = random_model(seed)
    rm = RelaxedModel(model, False)
    states = reachable_states(model)
    random.Random(seed).shuffle(states)
    for s in states:
        rm.view.move(s)
        open_literals, counts, adds = _view_from_scratch(rm, s)
        assert rm.view.open == open_literals
        assert rm.view.counts == counts
        assert {i: a for i, a in rm.view.adds.items() if a} == adds


@pytest.mark.parametrize("instance", ["ippc2008-blocksworld/p01.pddl",
                                      "ippc2006-elevators/p01.pddl",
                                      "ippc2006-schedule/p02.pddl"])
def test_carried_values_equal_fresh_ones_on_ippc_instances(ppddl_benchmarks, instance):
    model = ippc_model(ppddl_benchmarks, instance)
    states = breadth_first_states(model, 300)
    random.Random(0).shuffle(states)
    for mode in MODES:
        assert _carried(model, states, mode) == [_fresh(model, s, mode) for s in states]
