"""Interchangeable objects (``symmetry.py``): the representatives' values are the full
SSP's, representatives are orbit-invariant, and asymmetric objects are not merged."""

from __future__ import annotations

import random

import pytest

from stampc import api
from stampc.solvers import SolverOptions, solve
from stampc.solvers.bounds import solve_bounded
from stampc.solvers.symmetry import find_symmetry

SYMMETRIC = ["ippc2008-search-and-rescue/p01-z4.pddl", "ippc2008-search-and-rescue/p02-z5.pddl",
             "ippc2006-schedule/p01.pddl", "ippc2006-schedule/p02.pddl",
             "ippc2008-search-and-rescue/p03-z6.pddl"]
#: larger ones (several classes in zenotravel): certified intervals, reduced and full
LARGER = ["ippc2008-zenotravel/p01.pddl", "ippc2006-schedule/p04.pddl",
          "ippc2006-elevators/p02.pddl"]


def _model(ppddl_benchmarks, instance: str):
    path = ppddl_benchmarks / instance
    if not path.is_file():
        pytest.skip(f"{instance} not found")
    return api.ground(api.load_model([str(path)]))


def _permute(model, symmetry, state: int, rng: random.Random) -> int:
    """``state`` with each class's objects shuffled (an automorphism's image)."""
    for _, slots in symmetry.classes:
        order = list(range(len(slots)))
        rng.shuffle(order)
        cleared = state
        for row in slots:
            for f in row:
                cleared &= ~(1 << f)
        for src, dst in enumerate(order):
            for f_src, f_dst in zip(slots[src], slots[dst]):
                if (state >> f_src) & 1:
                    cleared |= 1 << f_dst
        state = cleared
    return state


@pytest.mark.parametrize("instance", SYMMETRIC)
def test_representative_values_equal_the_full_ssp(ppddl_benchmarks, instance):
    model = _model(ppddl_benchmarks, instance)
    symmetry = find_symmetry(model)
    assert symmetry, "no interchangeable objects found"
    opts = dict(algorithm="vi", heuristic="zero", unit_cost=True, epsilon=1e-10)
    full = solve(model, SolverOptions(**opts))
    reduced = solve(model, SolverOptions(**opts, symmetry=True))
    assert reduced.expected_cost == pytest.approx(full.expected_cost, abs=1e-6)
    assert len(reduced.search.V) <= len(full.search.V)
    # every state of the full SSP is worth what its representative is worth
    for s, v in full.search.V.items():
        c = symmetry.canonical(s)
        if c in reduced.search.V and c in reduced.search.expanded:
            assert reduced.search.V[c] == pytest.approx(v, abs=1e-6), s
    # certified LAO* bounds on the reduced SSP bracket the exact full value
    _, bounds = solve_bounded(model, SolverOptions(unit_cost=True, symmetry=True))
    assert bounds.lower - 1e-9 <= full.expected_cost <= bounds.upper + 1e-9


@pytest.mark.parametrize("instance", LARGER)
def test_certified_intervals_with_and_without_symmetry_overlap(ppddl_benchmarks, instance):
    model = _model(ppddl_benchmarks, instance)
    assert find_symmetry(model)
    opts = dict(unit_cost=True, epsilon=1e-6)
    _, full = solve_bounded(model, SolverOptions(**opts))
    sol, reduced = solve_bounded(model, SolverOptions(**opts, symmetry=True))
    assert full.certified and reduced.certified
    assert reduced.lower <= full.upper + 1e-9 and full.lower <= reduced.upper + 1e-9


@pytest.mark.parametrize("instance", SYMMETRIC[:4])
def test_representatives_are_orbit_invariant(ppddl_benchmarks, instance):
    model = _model(ppddl_benchmarks, instance)
    symmetry = find_symmetry(model)
    full = solve(model, SolverOptions(algorithm="vi", heuristic="zero", unit_cost=True))
    rng = random.Random(0)
    for s in list(full.search.V)[:500]:
        c = symmetry.canonical(s)
        assert symmetry.canonical(c) == c
        assert symmetry.canonical(_permute(model, symmetry, s, rng)) == c
        assert c.bit_count() == s.bit_count()


def test_asymmetric_objects_stay_apart(ppddl_benchmarks):
    # search-and-rescue's base is a zone unlike the others; blocksworld's blocks share
    # facts (on a b); no class at all there
    rescue = find_symmetry(_model(ppddl_benchmarks, "ippc2008-search-and-rescue/p01-z4.pddl"))
    assert [objs for objs, _ in rescue.classes] == [("z1", "z2", "z3", "z4")]
    assert not find_symmetry(_model(ppddl_benchmarks, "ippc2008-blocksworld/p01.pddl"))


def test_simulation_and_actions_follow_representatives(ppddl_benchmarks):
    from stampc.solvers import simulate
    model = _model(ppddl_benchmarks, "ippc2008-search-and-rescue/p02-z5.pddl")
    sol, bounds = solve_bounded(model, SolverOptions(unit_cost=True, symmetry=True))
    assert bounds.certified
    sim = simulate(model, sol, runs=300, seed=1)
    assert sim.mean_cost == pytest.approx(sol.expected_cost, rel=0.25)
    # a state off the representatives still gets an applicable action
    full = solve(model, SolverOptions(algorithm="vi", heuristic="zero", unit_cost=True))
    cache = sol.search.space.cache
    for s in list(full.search.V)[:200]:
        a = sol.action(s)
        assert a is None or a in cache.applicable(s)


@pytest.mark.parametrize("instance", ["ippc2008-zenotravel/p01.pddl",
                                      "ippc2006-schedule/p02.pddl",
                                      "ippc2008-search-and-rescue/p02-z5.pddl"])
def test_incremental_representative_equals_the_full_one(ppddl_benchmarks, instance):
    # successor(parent, s) re-reads only the objects whose facts changed: it must give
    # canonical(s) for representatives and non-representatives as parents alike
    from stampc.solvers.successors import SuccessorCache
    model = _model(ppddl_benchmarks, instance)
    symmetry = find_symmetry(model)
    raw = SuccessorCache(model, True)
    rng = random.Random(1)
    states, seen = [model.init], {model.init}
    for s in states:
        if len(states) > 400:
            break
        for parent in (s, symmetry.canonical(s), _permute(model, symmetry, s, rng)):
            for a in raw.applicable(parent):
                for _, nxt, _ in raw.float_outcomes(parent, a):
                    assert symmetry.successor(parent, nxt) == symmetry.canonical(nxt)
                    if nxt not in seen:
                        seen.add(nxt)
                        states.append(nxt)
