"""Emission: numbers, name mangling, requirements, costs and stamp-specific constructs."""

from __future__ import annotations

import re
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from stampc.backends.ppddl import emit_ppddl, import_ppddl, import_ppddl_text
from stampc.backends.ppddl.mangle import legal_name, mangle_model
from stampc.backends.ppddl.render import number
from stampc.ir.grounded import GroundAtom
from stampc.ir.lifted import (
    TRUE, Action, And, Atom, Binding, Const, CostEffect, Domain, EffAnd, EffForall, Equals,
    Evaluator, Exists, Generator, GeneratorUse, Lit, Model, Not, Num, Object, Outcome, Param,
    Predicate, Probabilistic, Problem, Type, Unknown, Var, When,
)

from .canon import canonical_lifted


def _reimport(model: Model, **extras) -> tuple[Model, str, str]:
    d, p = emit_ppddl(model, **extras)
    return import_ppddl_text(p, "p.pddl", domain_text=d, domain_filename="d.pddl"), d, p


def _requirements(domain_text: str) -> list[str]:
    return re.search(r"\(:requirements ([^)]*)\)", domain_text).group(1).split()


# ------------------------------------------------------------------ numbers
@pytest.mark.parametrize("value, text", [
    (Fraction(4, 5), "0.8"), (Fraction(1, 3), "1/3"), (Fraction(2), "2"),
    (Fraction(1, 8), "0.125"), (Fraction(1, 1024), "1/1024"), (Fraction(-5, 2), "-2.5"),
    (Fraction(1, 20), "0.05"), (Fraction(0), "0"),
])
def test_number_literals(value, text):
    assert number(value) == text


@settings(derandomize=True)
@given(st.fractions(min_value=-1000, max_value=1000, max_denominator=5000))
def test_numbers_are_exact(value):
    assert Fraction(number(value)) == value


# ------------------------------------------------------------- a toy model
def _toy(requirements=(":typing",), cost=None, stamp=False) -> Model:
    """A small model with awkward names; ``stamp`` adds stamp-only flags."""
    x, y = Var("x"), Var("y")
    types = (Type("object"), Type("Block", "object"), Type("pose", "object", continuous=stamp))
    preds = (Predicate("on", (Param("x", "Block"), Param("y", "Block"))),
             Predicate("and", (Param("x", "Block"),)),  # a reserved word
             Predicate("At.Pose", (Param("x", "Block"), Param("p", "pose")), static=True),
             Predicate("collision", (Param("x", "Block"),), static=not stamp,
                       unknowable=stamp, optimistic=False))
    move = Action(
        "Move Block", (Param("x", "Block"), Param("1y", "Block")),
        And((Atom("and", (x,)), Not(Equals(x, Var("1y"))),
             Exists((Param("z", "Block"),), Atom("on", (Var("z"), x))))),
        EffAnd((Lit(Atom("on", (x, Var("1y")))),
                Probabilistic((Outcome(Fraction(1, 3), Lit(Atom("and", (x,)), False)),
                               Outcome(Fraction(1, 2), CostEffect(Num(Fraction(5, 2))))),),
                EffForall((Param("w", "Block"),),
                          When(Atom("on", (Var("w"), x)), Lit(Atom("on", (Var("w"), y)), False))))),
        cost=cost)
    move = Action(move.name, move.params + (Param("y", "Block"),), move.precondition,
                  move.effect, cost=cost)
    domain = Domain("Toy Domain", types, (Object("Table", "Block"),), preds, (), (move,),
                    requirements=requirements)
    problem = Problem("P 1", "Toy Domain",
                      (Object("Can.1", "Block"), Object("can_1", "Block"), Object("CAN_1", "Block")),
                      (Atom("and", (Const("Can.1"),)),),
                      goal=Atom("on", (Const("can_1"), Const("Table"))), goal_reward=Fraction(10))
    return Model(domain, problem)


def test_legal_names():
    assert legal_name("Can.1") == "can_1"
    assert legal_name("and") == "and_"
    assert legal_name("1y") == "x1y"
    assert legal_name("pick up") == "pick_up"


def test_mangled_round_trip_and_collisions():
    model = _toy()
    again, d, p = _reimport(model)
    assert canonical_lifted(again, mangle=False) == canonical_lifted(model)
    names = [o.name for o in again.problem.objects]
    # the already-legal can_1 keeps its name; the others get -2, -3 in order
    assert names == ["can_1-2", "can_1", "can_1-3"]
    assert {pr.name for pr in again.domain.predicates} == {"on", "and_", "at_pose", "collision"}
    assert again.domain.actions[0].name == "move_block"
    assert [q.name for q in again.domain.actions[0].params] == ["x", "x1y", "y"]
    assert "; renamed object 'Can.1' -> can_1-2" in d
    assert again.domain.name == "toy_domain" and again.problem.domain == "toy_domain"


def test_requirements_are_computed_from_constructs():
    _, d, _ = _reimport(_toy())
    # (not (= ..)) needs only :equality; the deletes are not negative preconditions
    assert _requirements(d) == [":typing", ":equality", ":existential-preconditions",
                                ":conditional-effects", ":probabilistic-effects", ":rewards"]


def test_requirements_of_benchmarks(ppddl_benchmarks):
    """Declared-but-unused flags disappear, :mdp becomes what it stands for."""
    rect = import_ppddl(ppddl_benchmarks / "ippc2008-rectangle-tireworld/p01-x5-y5-h2-v2-u0-s1.pddl")
    assert _requirements(emit_ppddl(rect)[0]) == [
        ":typing", ":negative-preconditions", ":conditional-effects",
        ":probabilistic-effects", ":rewards"]
    sar = import_ppddl(ppddl_benchmarks / "ippc2008-search-and-rescue/p01-z4.pddl")
    assert _requirements(emit_ppddl(sar)[0]) == [
        ":typing", ":equality", ":negative-preconditions", ":disjunctive-preconditions",
        ":conditional-effects", ":probabilistic-effects", ":rewards"]
    tire = import_ppddl(ppddl_benchmarks / "ippc2006-tireworld/p01.pddl")
    # declares :strips :equality but uses neither equality nor negative preconditions
    assert _requirements(emit_ppddl(tire)[0]) == [":typing", ":probabilistic-effects"]
    assert "(:metric" not in emit_ppddl(tire)[1]


def test_base_cost_becomes_reward_decrease():
    model = _toy(cost=Num(Fraction(3)))
    again, d, p = _reimport(model)
    eff = again.domain.actions[0].effect
    assert eff.effects[0] == CostEffect(Num(Fraction(3)))
    assert again.domain.actions[0].cost is None
    assert "(decrease (reward) 3)" in d and "(decrease (reward) 2.5)" in d
    assert "(:goal-reward 10)" in p


def test_stamp_default_cost_is_explicit():
    """A model with no PPDDL requirements is a stamp model: default base cost 1."""
    model = _toy(requirements=())
    again, d, p = _reimport(model)
    assert again.domain.actions[0].effect.effects[0] == CostEffect(Num(Fraction(1)))
    assert "(:metric maximize (reward))" in p
    negative = _toy(cost=Num(Fraction(-4)))
    assert "(increase (reward) 4)" in emit_ppddl(negative)[0]


def test_stamp_constructs():
    base = _toy(stamp=True)
    unknown_effect = EffAnd(base.domain.actions[0].effect.effects
                            + (Unknown(Atom("collision", (Var("x"),))),))
    action = Action(base.domain.actions[0].name, base.domain.actions[0].params,
                    base.domain.actions[0].precondition, unknown_effect,
                    generated=(GeneratorUse("grasp", ("x",), ("1y",)),),
                    executes=Binding(".manipulation:move"))
    gen = Generator("grasp", (Param("x", "Block"),), (Param("p", "pose"),),
                    (Atom("At.Pose", (Var("x"), Var("p"))),), Binding(".manipulation:grasp"))
    domain = Domain(base.domain.name, base.domain.types, base.domain.constants,
                    base.domain.predicates, (), (action,), (gen,),
                    (Evaluator("collision", Binding(".manipulation:collides")),),
                    requirements=base.domain.requirements)
    model = Model(domain, base.problem)
    again, d, p = _reimport(model, extra_objects=[("g_move_can1", "pose")],
                            extra_init=[GroundAtom("At.Pose", ("Can.1", "g_move_can1"))])
    # '?' effect → its optimistic literal (false), with a comment
    assert "; ? (collision ?x): unknown after the action" in d
    assert Lit(Atom("collision", (Var("x"),)), False) in again.domain.actions[0].effect.effects
    assert "generator grasp" in d and ".manipulation:grasp" in d and "[binding" in d
    assert "executes .manipulation:move [binding dropped]" in d
    assert "type pose is continuous" in d
    assert Type("pose", "object") in again.domain.types  # an ordinary type now
    assert Object("g_move_can1", "pose") in again.problem.objects
    assert Atom("at_pose", (Const("can_1-2"), Const("g_move_can1"))) in again.problem.init
    assert "symbolic objects (continuous values): g_move_can1" in p


def test_round_trip_detects_changes(ppddl_benchmarks):
    """Negative control: the canonical comparison notices a changed probability."""
    model = import_ppddl(ppddl_benchmarks / "ippc2008-rectangle-tireworld/p01-x5-y5-h2-v2-u0-s1.pddl")
    d, p = emit_ppddl(model)
    changed = import_ppddl_text(p, "p", domain_text=d.replace("0.8 ", "0.7 ", 1))
    assert canonical_lifted(changed, mangle=False) != canonical_lifted(model)
    same = import_ppddl_text(p, "p", domain_text=d)
    assert canonical_lifted(same, mangle=False) == canonical_lifted(model)


def test_mangle_is_identity_on_legal_models(ppddl_benchmarks):
    model = import_ppddl(ppddl_benchmarks / "ippc2006-schedule/p01.pddl")
    mangled = mangle_model(model)
    assert mangled.renames == () and mangled.model == model


def test_goal_true_and_empty_effects():
    domain = Domain("d", (Type("object"),), (), (Predicate("p", (), static=True),),
                    (), (Action("noop", (), TRUE, EffAnd(())),), requirements=(":strips",))
    model = Model(domain, Problem("q", "d", (), (), goal=TRUE))
    again, d, p = _reimport(model)
    assert again == model
    assert _requirements(d) == [":strips"]


def test_zero_base_cost_emits_nothing():
    model = _toy(cost=Num(Fraction(0)))
    d, _ = emit_ppddl(model)
    assert "(decrease (reward) 0)" not in d
    assert _requirements(d)[-1] == ":rewards"  # the toy still has a 5/2 cost effect


def test_docs_table_lists_every_code():
    from pathlib import Path

    from stampc.backends.ppddl.codes import DESCRIPTIONS

    docs = (Path(__file__).resolve().parents[2] / "docs" / "ppddl.md").read_text()
    table = set(re.findall(r"^\| (P[12]\d\d) \|", docs, flags=re.M))
    assert table == set(DESCRIPTIONS)


@pytest.mark.parametrize("optimistic", [True, False])
def test_unknown_as_whole_effect(optimistic):
    """A '?' comment never swallows the literal, even when it is the whole effect."""
    pred = Predicate("c", (Param("x", "object"),), unknowable=True, optimistic=optimistic)
    action = Action("a", (Param("x", "object"),), TRUE, Unknown(Atom("c", (Var("x"),))))
    domain = Domain("d", (Type("object"),), (), (pred,), (), (action,), requirements=(":strips",))
    model = Model(domain, Problem("q", "d", (Object("o", "object"),), (),
                                  goal=Atom("c", (Const("o"),))))
    again, d, _ = _reimport(model)
    assert again.domain.actions[0].effect == Lit(Atom("c", (Var("x"),)), optimistic)
    comment_line = next(line for line in d.splitlines() if "; ?" in line)
    assert comment_line.rstrip().endswith(f"optimistic value ({str(optimistic).lower()})")
