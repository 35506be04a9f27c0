"""Import details checked on real IPPC files (expected values read off the files)."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest

from stampc.backends.ppddl import import_domain_only, import_ppddl, import_ppddl_text
from stampc.diagnostics import StampcError
from stampc.ir.lifted import (
    TRUE, Atom, Const, CostEffect, EffAnd, EffForall, Lit, Num, Object, Param,
    Probabilistic, Var, When,
)

from .benchmarks import manifest_rows


def _load(root: Path, rel: str):
    return import_ppddl(root / rel)


def _action(model, name):
    return next(a for a in model.domain.actions if a.name == name)


def _find(effect, kind):
    """All sub-effects of class ``kind`` (depth first)."""
    found = [effect] if isinstance(effect, kind) else []
    children = []
    if isinstance(effect, EffAnd):
        children = list(effect.effects)
    elif isinstance(effect, (When, EffForall)):
        children = [effect.effect]
    elif isinstance(effect, Probabilistic):
        children = [o.effect for o in effect.outcomes]
    for c in children:
        found += _find(c, kind)
    return found


RECT = "ippc2008-rectangle-tireworld/p01-x5-y5-h2-v2-u0-s1.pddl"
SYSADMIN_P15 = "ippc2008-sysadmin-slp/p15-n1920-l960-s15.pddl"


@pytest.mark.parametrize("rel", [
    "ippc2008-triangle-tireworld/p01.pddl", RECT, SYSADMIN_P15,
    "ippc2008-zenotravel/p11-c11-p10-a6-s21350.pddl", "ippc2008-boxworld/p01-b10-c5-dc0-fc0-dr0-gr1.pddl",
    "ippc2006-elevators/p11.pddl", "ippc2008-search-and-rescue/p01-z4.pddl",
])
def test_object_counts_match_manifest(ppddl_benchmarks, rel):
    rows = {r["path"]: r for r in manifest_rows()}
    model = _load(ppddl_benchmarks, rel)
    assert len(model.problem.objects) == int(rows[rel]["objects"])


def test_rectangle_tireworld(ppddl_benchmarks):
    m = _load(ppddl_benchmarks, RECT)
    assert [t.name for t in m.domain.types] == ["object", "int"]  # a type named int
    assert [a.name for a in m.domain.actions] == [
        "move-u", "move-d", "move-r", "move-l", "move-ur", "move-ul", "move-dr", "move-dl",
        "ghostteleport"]  # ghostTeleport lower-cased
    move_l = _action(m, "move-l")
    # ":parameters (?X ?y ?x2 - int)" with ?x used in the body: names are case-insensitive
    assert move_l.params == (Param("x", "int"), Param("y", "int"), Param("x2", "int"))
    (prob,) = _find(move_l.effect, Probabilistic)
    assert [o.probability for o in prob.outcomes] == [Fraction(4, 5), Fraction(1, 5)]  # .8 .2
    assert _find(move_l.effect, CostEffect) == [CostEffect(Num(Fraction(10)))]
    # "(when (unsafe ?x ?y) dead)": a bare 0-ary atom as effect
    when = _find(move_l.effect, When)[0]
    assert when.effect == Lit(Atom("dead", ()), True)
    static = {p.name: p.static for p in m.domain.predicates}
    assert static == {"xpos": False, "ypos": False, "next": True, "safex": True,
                      "safey": True, "unsafe": True, "dead": False}
    assert m.problem.goal_reward == 1000 and m.problem.metric == "maximize (reward)"
    assert ":rewards" in m.domain.requirements


def test_sysadmin_p15_large(ppddl_benchmarks):
    m = _load(ppddl_benchmarks, SYSADMIN_P15)
    assert len(m.problem.objects) == 1920
    assert {o.type for o in m.problem.objects} == {"comp"}
    (reboot,) = m.domain.actions
    assert reboot.precondition == TRUE  # no :precondition
    # (forall (?d - comp) (when (up ?d) (increase (reward) 1))): a negative cost
    assert CostEffect(Num(Fraction(-1))) in _find(reboot.effect, CostEffect)
    probs = sorted(o.probability for p in _find(reboot.effect, Probabilistic) for o in p.outcomes)
    assert probs == [Fraction(1, 20), Fraction(1, 5), Fraction(9, 10)]


def test_probabilities_summing_below_one(ppddl_benchmarks):
    m = _load(ppddl_benchmarks, "ippc2008-blocksworld/p01.pddl")
    eff = _action(m, "pick-up-from-table").effect
    assert isinstance(eff, Probabilistic)
    assert sum(o.probability for o in eff.outcomes) == Fraction(3, 4)  # rest: no-op


def test_mdp_requirement_constants_and_reward_increase(ppddl_benchmarks):
    m = _load(ppddl_benchmarks, "ippc2008-search-and-rescue/p01-z4.pddl")
    assert ":mdp" in m.domain.requirements
    assert m.domain.constants == (Object("base", "zone"),)
    end = _action(m, "end-mission")
    assert end.params == ()
    land = _action(m, "land")
    costs = _find(land.effect, CostEffect)
    assert CostEffect(Num(Fraction(-1000))) in costs  # (increase (reward) 1000)
    assert CostEffect(Num(Fraction(1000))) in costs  # (decrease (reward) 1000)
    assert all(a.cost is None for a in m.domain.actions)


def test_actions_without_parameters_and_precondition(ppddl_benchmarks):
    m = _load(ppddl_benchmarks, "ippc2006-pitchcatch/p01.pddl")
    deposit = _action(m, "deposit-ball")
    assert deposit.params == () and deposit.precondition == TRUE
    assert isinstance(deposit.effect, EffAnd) and len(deposit.effect.effects) == 2


def test_nested_probabilistic(ppddl_benchmarks):
    m = _load(ppddl_benchmarks, "ippc2008-boxworld/p01-b10-c5-dc0-fc0-dr0-gr1.pddl")
    blocks = _find(_action(m, "drive-truck").effect, Probabilistic)
    assert [[o.probability for o in b.outcomes] for b in blocks] == [
        [Fraction(1, 5), Fraction(4, 5)], [Fraction(1, 3)] * 3]
    assert m.problem.goal_reward == 1


def test_ippc2006_has_no_rewards(ppddl_benchmarks):
    m = _load(ppddl_benchmarks, "ippc2006-tireworld/p01.pddl")
    assert m.problem.goal_reward is None and m.problem.metric is None
    assert m.problem.name == "tire_17_0_28460" and m.problem.domain == "tire"
    assert Atom("vehicle-at", (Const("n2"),)) in m.problem.init
    assert m.problem.goal == Atom("vehicle-at", (Const("n0"),))


def test_problem_only_file_with_explicit_domain(ppddl_benchmarks):
    rel = ppddl_benchmarks / "ippc2008-zenotravel/p12-c13-p5-a3-s14893.pddl"
    beside = import_ppddl(rel)
    explicit = import_ppddl(rel, ppddl_benchmarks / "ippc2008-zenotravel/domain.pddl")
    reversed_order = import_ppddl(ppddl_benchmarks / "ippc2008-zenotravel/domain.pddl", rel)
    assert beside == explicit == reversed_order
    assert beside.domain == import_domain_only(ppddl_benchmarks / "ippc2008-zenotravel/domain.pddl")


def test_uppercase_random_domain(ppddl_benchmarks):
    m = _load(ppddl_benchmarks, "ippc2006-random/p01.pddl")
    assert m.problem.objects == ()  # everything is a constant
    names = [o.name for o in m.domain.constants]
    assert names[:3] == ["po", "oz", "ef"] and all(n == n.lower() for n in names)
    cmw = _action(m, "cmw")
    assert [o.probability for o in cmw.effect.outcomes] == [
        Fraction(51, 100), Fraction(22, 100), Fraction(27, 100)]


TWO_PROBLEMS = """
(define (domain d) (:predicates (p ?x)) (:action a :parameters (?x) :effect (p ?x)))
(define (problem one) (:domain d) (:objects o1) (:init) (:goal (p o1)))
(define (problem Two) (:domain d) (:objects o2 o3) (:init (p o3)) (:goal (p o2)))
"""


def test_select_problem_by_name():
    two = import_ppddl_text(TWO_PROBLEMS, "two.pddl", problem_name="TWO")
    assert two.problem.name == "two"
    assert [o.name for o in two.problem.objects] == ["o2", "o3"]
    assert two.problem.init == (Atom("p", (Const("o3"),)),)
    assert two.domain.actions[0].effect == Lit(Atom("p", (Var("x"),)))
    one = import_ppddl_text(TWO_PROBLEMS, "two.pddl", problem_name="one")
    assert one.problem.objects == (Object("o1", "object"),)
    with pytest.raises(StampcError) as info:
        import_ppddl_text(TWO_PROBLEMS, "two.pddl")
    assert info.value.diagnostics[0].code == "P105"
    assert "one, two" in info.value.diagnostics[0].message


def test_total_cost_and_fractions():
    text = """
    (define (domain c) (:requirements :action-costs :typing)
      (:types t) (:predicates (p ?x - t)) (:functions (total-cost) - number)
      (:action a :parameters (?x - t)
        :effect (and (increase (total-cost) 2.5)
                     (probabilistic 1/3 (p ?x) .25 (not (p ?x))))))
    (define (problem q) (:domain c) (:objects o - t) (:init) (:goal (p o))
      (:metric minimize (total-cost)))
    """
    m = import_ppddl_text(text, "c.pddl")
    eff = m.domain.actions[0].effect
    assert eff.effects[0] == CostEffect(Num(Fraction(5, 2)))
    assert [o.probability for o in eff.effects[1].outcomes] == [Fraction(1, 3), Fraction(1, 4)]
    assert m.domain.functions == ()  # total-cost is built in
    assert m.problem.metric == "minimize (total-cost)"
