"""Sparse fact sets of the grounded IR (stampc.ir.masks): same values as int bitsets,
memory linear in the model when every action touches facts of its own."""

from __future__ import annotations

import random
import sys
from pathlib import Path

import pytest

from stampc.api import import_ppddl
from stampc.ir.ground import ground
from stampc.ir.grounded import GEffect, GroundAtom, GroundCondition, GroundModel
from stampc.ir.json_io import grounded_from_json, grounded_to_json
from stampc.ir.masks import (DENSE_BITS, Sparse, as_int, from_indices, indices, list_to_int,
                             pack, union_all)
from stampc.solvers.successors import SuccessorCache

CHAIN = """(define (domain chain)
  (:requirements :strips :typing)
  (:types node)
  (:predicates (at ?x - node) (visited ?x - node) (next ?x ?y - node))
  (:action step :parameters (?x ?y - node)
    :precondition (and (at ?x) (next ?x ?y))
    :effect (and (not (at ?x)) (at ?y) (visited ?y))))
"""


def chain_model(tmp_path: Path, n: int) -> GroundModel:
    """A chain of ``n`` step actions over ``2 (n + 1)`` facts: action i touches at(i),
    at(i+1) and visited(i+1), so its facts sit as far up as the model is large."""
    nodes = [f"n{i:05d}" for i in range(n + 1)]
    problem = (f"(define (problem chain{n}) (:domain chain)\n(:objects {' '.join(nodes)} - node)\n"
               f"(:init (at n00000) {' '.join(f'(next {a} {b})' for a, b in zip(nodes, nodes[1:]))})\n"
               f"(:goal (visited {nodes[-1]})))\n")
    (tmp_path / "domain.pddl").write_text(CHAIN)
    (tmp_path / f"p{n}.pddl").write_text(problem)
    return ground(import_ppddl(tmp_path / "domain.pddl", tmp_path / f"p{n}.pddl"))


def stored_bytes(model: GroundModel, as_ints: bool = False) -> int:
    """Bytes of every action's stored fact sets (a Sparse tuple with its index ints), or
    with ``as_ints`` what int bitsets of the same sets take."""
    def size(facts) -> int:
        if as_ints:
            return sys.getsizeof(as_int(facts))
        if facts.__class__ is Sparse:
            return sys.getsizeof(facts) + sum(sys.getsizeof(i) for i in facts)
        return sys.getsizeof(facts)

    return sum(size(f) for a in model.actions
               for f in (a.precondition.pos_facts, a.precondition.neg_facts,
                         a.effect.add_facts, a.effect.delete_facts, a.effect.unknown_facts))


def random_set(rng: random.Random) -> set[int]:
    top = rng.choice((100, DENSE_BITS, 5 * DENSE_BITS, 200_000))
    return {rng.randrange(top) for _ in range(rng.choice((0, 1, 3, 200, 5000)))}


def test_fact_sets_are_canonical_and_agree_with_int_bitsets():
    rng = random.Random(3)
    for _ in range(300):
        a, b = random_set(rng), random_set(rng)
        fa, fb = from_indices(a), from_indices(b)
        ia, ib = list_to_int(sorted(a)), list_to_int(sorted(b))
        assert fa == pack(ia) and as_int(fa) == ia and list(indices(fa)) == sorted(a)
        assert union_all([fa, fb, 0]) == pack(ia | ib)
        # int exactly when compact: a few high facts become a tuple
        compact = not a or max(a) < DENSE_BITS or max(a) + 1 <= 64 * len(a)
        assert isinstance(fa, int) == compact
    assert from_indices([7 * DENSE_BITS, 3]) == Sparse((3, 7 * DENSE_BITS))
    with pytest.raises(TypeError):
        pack((1, 2))  # a plain tuple is not a fact set


def test_conditions_and_effects_keep_int_semantics():
    high = 1 << (10 * DENSE_BITS)
    cond = GroundCondition(pos=high | 1, neg=2)
    assert isinstance(cond.pos_facts, Sparse) and cond.pos == high | 1 and cond.neg == 2
    assert cond == GroundCondition(pos=Sparse((0, 10 * DENSE_BITS)), neg=2)
    assert hash(cond) == hash(GroundCondition(high | 1, 2))
    assert cond.holds(high | 1) and not cond.holds(high | 3) and not cond.holds(1)
    effect = GEffect(add=high, delete=1)
    assert effect.add == high and effect.delete == 1 and effect.unknown == 0


def test_chain_action_fact_sets_grow_linearly(tmp_path):
    small = chain_model(tmp_path, 1000)
    large = chain_model(tmp_path, 4000)
    assert len(large.facts) == 2 * 4000 + 1 > DENSE_BITS
    # int bitsets: 4x the actions, each mask up to 4x larger (about 16x); fact sets stay
    # ints below DENSE_BITS, which still grow, so the stored ratio is above 4
    assert stored_bytes(large, as_ints=True) / stored_bytes(small, as_ints=True) > 12
    ratio = stored_bytes(large) / stored_bytes(small)
    assert ratio < 8, ratio
    biggest = max(sys.getsizeof(f) for a in large.actions
                  for f in (a.precondition.pos_facts, a.effect.add_facts, a.effect.delete_facts))
    assert biggest <= DENSE_BITS // 8 + 64
    assert any(isinstance(a.effect.add_facts, Sparse) for a in large.actions)


def test_sparse_model_round_trips_and_solver_checks_agree(tmp_path):
    model = chain_model(tmp_path, DENSE_BITS + 20)
    text = grounded_to_json(model)
    again = grounded_from_json(text)
    assert again.actions == model.actions and again.goal == model.goal
    assert grounded_to_json(again) == text
    cache = SuccessorCache(model)
    start = DENSE_BITS - 10
    state = model.state_of([GroundAtom("at", (f"n{start:05d}",))])
    for _ in range(20):  # walk from int preconditions into sparse ones
        (action,) = cache.applicable(state)
        assert model.actions[action].precondition.holds(state)
        (outcome,) = cache.outcomes(state, action)
        state = outcome[1]
    assert isinstance(model.actions[action].precondition.pos_facts, Sparse)
    assert model.state_facts(state)[0] == GroundAtom("at", (f"n{start + 20:05d}",))


def test_conflict_check_on_index_sets_matches_int_bitsets():
    """G203's check gives the same conflicts whether it works on ints or on index sets."""
    from fractions import Fraction

    from stampc.ir.ground_checks import effect_conflicts
    from stampc.ir.grounded import GProb

    rng = random.Random(7)
    for _ in range(300):
        def leaf() -> GEffect:
            return GEffect(add=rng.getrandbits(6), delete=rng.getrandbits(6))

        effect = GEffect(add=rng.getrandbits(6), delete=rng.getrandbits(6),
                         whens=tuple((GroundCondition(pos=1), leaf())
                                     for _ in range(rng.randint(0, 3))),
                         blocks=tuple(GProb(((Fraction(1, 2), leaf()), (Fraction(1, 3), leaf())))
                                      for _ in range(rng.randint(0, 3))))
        as_ints = effect_conflicts(effect, n_facts=6)
        assert isinstance(as_ints, int)
        assert effect_conflicts(effect) == as_ints  # no fact count: works on index sets
