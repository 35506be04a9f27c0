"""The grounded model behaves exactly like the lifted model on reachable states.

Oracle: :mod:`lifted_reference`, a naive interpreter of the lifted semantics. On states
reached by seeded random walks through the grounded model, every lifted binding must
agree with the ground model: applicable iff a ground action exists whose precondition
holds, with the same outcome distribution (successor states and costs); goals agree.
"""

from __future__ import annotations

import random
from fractions import Fraction
from itertools import product

import pytest
from ir_builders import AND, EFF, NOT, OR, action, add, atom, delete, model, params, pred
from lifted_reference import Reference
from test_ground_effects import coins_model
from test_ground_generators import pick_place

from stampc.ir import lifted as L
from stampc.ir.ground import ground
from stampc.ir.grounded import GroundModel

#: The slowest random walks (5-15 s each) run in the slow run (`-m slow`).
SLOW = pytest.mark.slow
INSTANCES = (
    "ippc2008-boxworld/p01-b10-c5-dc0-fc0-dr0-gr1.pddl",
    pytest.param("ippc2008-sysadmin-slp/p01-n4-l1-s1.pddl", marks=SLOW),
    "ippc2006-schedule/p01.pddl",
    "ippc2008-search-and-rescue/p01-z4.pddl",
    "ippc2006-pitchcatch/p01.pddl",
    "ippc2008-ex-blocksworld/p01.pddl",
    pytest.param("ippc2006-drive/p01.pddl", marks=SLOW),
    "ippc2008-zenotravel/p01.pddl",
    "ippc2006-elevators/p01.pddl",
    pytest.param("ippc2006-random/p01.pddl", marks=SLOW),
    "ippc2008-rectangle-tireworld/p01-x5-y5-h2-v2-u0-s1.pddl",
    "ippc2008-blocksworld/p01.pddl",
)


def atoms_of(gm: GroundModel, state: int) -> set:
    fluents = {(f.predicate, f.args) for f in gm.state_facts(state)}
    return fluents | {(f.predicate, f.args) for f in gm.static_facts}


def compare_state(model: L.Model, gm: GroundModel, ref: Reference, state: int,
                  rng: random.Random) -> list:
    """Check every binding in ``state``; return the applicable ground actions."""
    atoms = atoms_of(gm, state)
    static = {(f.predicate, f.args) for f in gm.static_facts}
    by_key = {(a.schema, a.args): a for a in gm.actions}
    applicable = []
    assert gm.is_goal(state) == ref.holds(model.problem.goal, {}, atoms)
    for schema, schema_action in enumerate(model.domain.actions):
        for args in product(*(ref.of_type(p.type) for p in schema_action.params)):
            env = dict(zip((p.name for p in schema_action.params), args))
            lifted_ok = ref.holds(schema_action.precondition, env, atoms)
            ground_action = by_key.get((schema, args))
            ground_ok = ground_action is not None and ground_action.precondition.holds(state)
            assert lifted_ok == ground_ok, (schema_action.name, args)
            if ground_ok:
                applicable.append(ground_action)
    for a in rng.sample(applicable, min(len(applicable), 12)):
        expected = {(nxt - static, cost): p for (nxt, cost), p in
                    ref.successors(model.domain.actions[a.schema], a.args, atoms).items()}
        got: dict = {}
        for s in a.outcomes(state):
            key = (frozenset(atoms_of(gm, s.apply(state)) - static), s.cost - a.base_cost)
            got[key] = got.get(key, Fraction(0)) + s.probability
        assert got == expected, a.label
    return applicable


def random_walk(model: L.Model, seed: int, steps: int = 12) -> None:
    gm = ground(model)
    ref = Reference(model)
    rng = random.Random(seed)
    state = gm.init
    for _ in range(steps):
        applicable = compare_state(model, gm, ref, state, rng)
        if not applicable:
            state = gm.init
            continue
        outcomes = rng.choice(applicable).outcomes(state)
        pick = rng.random()
        for s in outcomes:
            pick -= s.probability
            if pick <= 0:
                break
        state = s.apply(state)


@pytest.mark.parametrize("rel", INSTANCES)
def test_benchmark_semantics_match_reference(ppddl_benchmarks, rel):
    importer = pytest.importorskip("stampc.backends.ppddl.importer")
    random_walk(importer.import_ppddl(ppddl_benchmarks / rel), seed=7)


def quantifier_zoo() -> L.Model:
    """Quantifiers over a static predicate in every polarity, in conditions and effects."""
    b = params(("b", "box"))
    red, opn = atom("red", "?b"), atom("open", "?b")
    pres = {
        "all-red-and-open": L.Forall(b, AND(red, opn)),
        "all-red-open": L.Forall(b, L.Imply(red, opn)),
        "some-red-closed": L.Exists(b, AND(red, NOT(opn))),
        "no-plain-or-open": NOT(L.Exists(b, OR(NOT(red), opn))),
        "not-all-plain-open": NOT(L.Forall(b, L.Imply(NOT(red), opn))),
        "some-plain-open": L.Exists(b, AND(NOT(red), opn)),
        "not-some-red-open": NOT(L.Exists(b, AND(red, opn))),
    }
    acts = [action(name, (), pre, add("seen")) for name, pre in pres.items()]
    acts.append(action("toggle", b, L.TRUE, EFF(L.When(opn, delete("open", "?b")),
                                                   L.When(NOT(opn), add("open", "?b")))))
    acts.append(action("sweep", (), L.TRUE, EFF(
        L.EffForall(b, L.When(AND(red, opn), prob_close())),
        L.EffForall(b, L.When(NOT(red), L.CostEffect(L.Num(Fraction(1))))),
        L.EffForall(b, L.When(OR(NOT(red), opn), add("seen"))))))
    return model(types=(L.Type("box"),), preds=(pred("red", "box"), pred("open", "box"),
                                               pred("seen")),
                 actions=tuple(acts), objs="b1 b2 b3 b4 - box",
                 init=(atom("red", "b1"), atom("red", "b2"), atom("open", "b3")),
                 goal=L.Forall(params(("b", "box")), L.Imply(atom("red", "?b"),
                                                             atom("open", "?b"))))


def prob_close() -> L.Probabilistic:
    return L.Probabilistic((L.Outcome(Fraction(1, 2), delete("open", "?b")),))


@pytest.mark.parametrize("seed", range(4))
def test_quantifier_zoo_matches_reference(seed):
    random_walk(quantifier_zoo(), seed=seed, steps=15)


def test_hand_models_semantics_match_reference():
    random_walk(coins_model(), seed=1, steps=4)
    gm = ground(pick_place(), max_symbol_depth=1)
    assert len(gm.actions) == 1  # generator models need Skolem symbols: not in the oracle
