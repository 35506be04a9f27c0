"""Successor cache against brute force; heuristic values on hand-made relaxations."""

from __future__ import annotations

import math
import random

import pytest

from ssp_builders import ModelBuilder, random_model
from stampc.ir.grounded import GAnd, GLit, GOr, GroundCondition
from stampc.solvers import SuccessorCache, make_heuristic


@pytest.mark.parametrize("seed", range(20))
def test_applicable_and_outcomes_match_brute_force(seed):
    model = random_model(seed, n_facts=6, n_actions=12)
    cache = SuccessorCache(model)
    rng = random.Random(seed)
    for _ in range(30):
        s = rng.getrandbits(6)
        expected = tuple(a.index for a in model.actions if a.precondition.holds(s))
        assert cache.applicable(s) == expected
        for a in expected:
            exact = model.actions[a].outcomes(s)
            got = cache.outcomes(s, a)
            assert [(p, n, c) for p, n, c in got] == \
                [(float(o.probability), o.apply(s), float(o.cost)) for o in exact]
            assert sum(p for p, _, _ in got) == pytest.approx(1.0)


def test_transitions_fold_self_loops():
    b = ModelBuilder(["x", "g"])
    # 1/4 goal (cost 1 + 3), 3/4 nothing (cost 1): expected cost per try 1.75,
    # tries until success 4 -> 7; after folding one transition to the goal.
    b.action("try", outcomes=[("1/4", ["g"], [], 3)], cost=1)
    model = b.build(init=[], goal=["g"])
    cache = SuccessorCache(model)
    ((a, cost, probs, nexts),) = cache.transitions(0)
    assert cost == pytest.approx(7.0)
    assert probs == (1.0,) and nexts == (model.init | 2,)
    ((_, raw_cost, raw_probs, raw_nexts),) = cache.transitions(0, eliminate_self_loops=False)
    assert raw_cost == pytest.approx(1.75)
    assert sorted(zip(raw_nexts, raw_probs)) == [(0, 0.75), (2, 0.25)]


def test_pure_noop_actions_are_dropped_and_unit_cost_applies():
    b = ModelBuilder(["x", "g"])
    b.action("noop", outcomes=[(1, [], ["g"])], cost=7)
    b.action("go", outcomes=[(1, ["g"], [])], cost=7)
    model = b.build(init=[], goal=["g"])
    trans = SuccessorCache(model, unit_cost=True).transitions(0)
    assert [(model.actions[a].name, c) for a, c, _, _ in trans] == [("go", 1.0)]


def test_non_conjunctive_preconditions_are_honoured():
    b = ModelBuilder(["a", "b", "g"])
    b.action("either", outcomes=[(1, ["g"], [])],
             precondition=GroundCondition(rest=(GOr((GLit(0), GLit(1))),)))
    model = b.build(init=[], goal=["g"])
    cache = SuccessorCache(model)
    assert cache.applicable(0b000) == ()
    assert cache.applicable(0b010) == (0,)
    assert cache.applicable(0b001) == (0,)


def chain_model(n: int):
    """Deterministic chain s0 -> s1 -> ... -> sn with unit costs."""
    b = ModelBuilder([f"s{i}" for i in range(n + 1)])
    for i in range(n):
        b.action(f"step{i}", pre=[f"s{i}"], outcomes=[(1, [f"s{i + 1}"], [f"s{i}"])])
    return b.build(init=["s0"], goal=[f"s{n}"])


def test_hmax_on_a_chain_is_its_length():
    model = chain_model(6)
    assert make_heuristic("hmax", model, False)(model.init) == 6
    assert make_heuristic("zero", model, False)(model.init) == 0


def test_hadd_sums_independent_goals_and_hmax_takes_the_max():
    b = ModelBuilder(["p", "q", "r"])
    b.action("get_p", outcomes=[("1/2", ["p"], [])], cost=2)
    b.action("get_q", outcomes=[(1, ["q"], [])], cost=3)
    model = b.build(init=[], goal=["p", "q"])
    assert make_heuristic("hmax", model, False)(0) == 3
    assert make_heuristic("hadd", model, False)(0) == 5
    assert make_heuristic("hmax", model, True)(0) == 1
    assert make_heuristic("hadd", model, True)(0) == 2


def test_relaxed_dead_end_is_infinite_and_conditional_effects_count():
    b = ModelBuilder(["key", "door", "g", "never"])
    b.action("open", effect=b.effect(whens=[(b.cond(["key"]), b.effect(["door"]))]))
    b.action("take", outcomes=[(1, ["key"], [])])
    b.action("enter", pre=["door"], outcomes=[(1, ["g"], [])])
    model = b.build(init=[], goal=["g"])
    assert make_heuristic("hmax", model, False)(0) == 3
    blocked = b.build(init=[], goal=["never"])
    assert make_heuristic("hmax", blocked, False)(0) == math.inf
    assert make_heuristic("hadd", blocked, False)(0) == math.inf


def test_goal_disjunction_is_relaxed_admissibly():
    b = ModelBuilder(["p", "q"])
    b.action("get_p", outcomes=[(1, ["p"], [])], cost=4)
    model = b.build(init=[], goal_condition=GroundCondition(
        rest=(GAnd((GOr((GLit(0), GLit(1))),)),)))
    # The disjunction is dropped: 0 is a lower bound of the true cost 4.
    assert make_heuristic("hmax", model, False)(0) == 0


@pytest.mark.parametrize("dense_bytes", [0, 64 << 20])
def test_applicable_matches_brute_force_with_sparse_preconditions(monkeypatch, tmp_path,
                                                                  dense_bytes):
    """Past DENSE_BITS facts, fact sets are sparse; the cache turns them into ints when
    they fit (``DENSE_CHECK_BYTES``) and must still agree with the conditions themselves."""
    from pathlib import Path

    from stampc import api
    from stampc.ir.masks import DENSE_BITS
    from stampc.solvers import successors

    monkeypatch.setattr(successors, "DENSE_CHECK_BYTES", dense_bytes)
    root = Path(__file__).resolve().parents[2] / "examples" / "cluttered_table"
    from examples.cluttered_table.scene import problem_text
    problem = tmp_path / "cluttered25.stamp"
    problem.write_text(problem_text(25, 1, "mid", "pybullet"))
    model = api.ground(api.load_model([str(root / "domain.stamp"), str(problem)]))
    assert len(model.facts) > DENSE_BITS
    assert any(a.precondition.pos_facts.__class__ is not int for a in model.actions)
    cache = SuccessorCache(model)
    rng = random.Random(0)
    state, seen = model.init, 0
    for _ in range(60):  # a random walk keeps the states plausible (and mostly applicable)
        expected = tuple(a.index for a in model.actions if a.precondition.holds(state))
        assert cache.applicable(state) == expected
        seen += len(expected)
        if not expected:
            break
        action = model.actions[rng.choice(expected)]
        outcomes = action.outcomes(state)
        state = rng.choice(outcomes).apply(state)
        # the learned facts refinement writes: an obstruction of a random trajectory
        if rng.random() < 0.3:
            state |= 1 << rng.randrange(len(model.facts))
    assert seen > 60


@pytest.mark.parametrize("dense", [False, True])
def test_condition_checks_of_sparse_conditions_with_a_remainder(dense):
    from stampc.ir.masks import DENSE_BITS, Sparse
    from stampc.solvers.float_effects import _holds, condition_check

    n = DENSE_BITS + 200
    rng = random.Random(1)
    for _ in range(40):
        pos = sorted(rng.sample(range(n), 3))
        neg = sorted(set(rng.sample(range(n), 2)) - set(pos))
        rest = (GOr((GLit(rng.randrange(n), True), GLit(rng.randrange(n), False))),)
        cond = GroundCondition(Sparse(pos) if pos[-1] >= DENSE_BITS else sum(1 << f for f in pos),
                               Sparse(neg), rest)
        check = condition_check(cond, dense)
        for _ in range(50):
            state = sum(1 << f for f in pos if rng.random() < 0.9) | \
                sum(1 << f for f in neg if rng.random() < 0.1) | rng.getrandbits(n)
            assert _holds(check, state) == cond.holds(state)


@pytest.mark.parametrize("dense", [False, True])
def test_a_never_condition_check_never_holds(dense):
    from stampc.solvers.float_effects import _holds, condition_check

    check = condition_check(GroundCondition(never=True), dense)
    assert not any(_holds(check, s) for s in (0, 1, 0b1011, (1 << 5000) - 1))
