"""LM-cut: admissible on every reachable state, at least h_max without ``when`` effects."""

from __future__ import annotations

import math
from fractions import Fraction

import pytest
from ssp_builders import ModelBuilder, random_conditional_model, random_model, reference_values

from stampc import api
from stampc.solvers import SolverOptions, solve
from stampc.solvers.heuristic_choice import make_heuristic

D = 50.0


def _single_when_model(seed: int):
    """Boxworld's shape: no precondition, the whole effect one ``when`` (with a nested
    one inside a probabilistic block)."""
    import random
    from stampc.ir.grounded import GEffect, GProb
    rng = random.Random(seed)
    names = [f"f{i}" for i in range(5)]
    b = ModelBuilder(names)
    for k in range(6):
        nested = (b.cond(rng.sample(names, 1)), b.effect(rng.sample(names, 1), []))
        block = GProb(((Fraction(3, 4), b.effect(rng.sample(names, 1), [], whens=[nested])),))
        inner = GEffect(add=b.mask(rng.sample(names, 1)), delete=b.mask(rng.sample(names, 1)),
                        blocks=(block,))
        cond = b.cond(rng.sample(names, rng.randint(1, 2)), rng.sample(names, rng.randint(0, 1)))
        b.action(f"w{k}", effect=GEffect(whens=((cond, inner),)), cost=rng.randint(1, 3))
    return b.build([n for n in names if rng.random() < 0.4], rng.sample(names, 2))


@pytest.mark.parametrize("make", [random_model, random_conditional_model, _single_when_model])
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
    # more informed without ``when`` effects, and where an action's sole ``when``
    # carries its cost
    if make is not random_conditional_model:
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
