"""Lowering rules of docs/architecture.md, on small hand-written models."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest

from stampc.diagnostics import StampcError
from stampc.ir import lifted as ir
from stampc.ir.lower import lower, lower_domain
from stampc.semantics.api import load

DOMAIN = """domain d
continuous type pose
continuous type conf
type block
constant home: pose
static predicate reach(b: block, p: pose, q: conf)
static predicate link(q: conf, r: conf)
predicate at(b: block, p: pose)
predicate seen(b: block)
predicate free(q: conf)
function weight(b: block)
generator reach_gen(b: block, p: pose) -> (q: conf)
    certifies reach(b, p, q)
    binds ".w:reach"
    budget 3
    option noise = 0.5
generator link_gen(q: conf) -> (r: conf)
    certifies link(q, r)
    binds "pkg.mod:link"
evaluator free binds ".w:free"
action move(b: block, p: pose, r: conf, q: conf)
    pre  link(q, r), reach(b, p, q), at(b, p), free(r)
    eff  seen(b), ? free(r)
    cost 2 * weight(b)
action look(b: block)
    pre  not seen(b) or b = b
    eff  when not seen(b): seen(b)
         probabilistic 1/3: not seen(b)
"""
PROBLEM = """problem p for d
object b0..b2: block
object start: pose
init at(b0, start), weight(b0) = 3/2
goal seen(b0)
horizon 7
scene "scenes/one.json"
"""


def write(tmp_path: Path, text: str, name: str = "m.stamp") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_lowering_details(tmp_path: Path) -> None:
    m = lower(load(write(tmp_path, DOMAIN + "\n" + PROBLEM)))
    move = next(a for a in m.domain.actions if a.name == "move")
    # q comes from reach(b, p) (p selected by at); r needs q first: dependency order
    assert move.generated == (ir.GeneratorUse("reach_gen", ("b", "p"), ("q",)),
                              ir.GeneratorUse("link_gen", ("q",), ("r",)))
    assert move.cost == ir.BinOp("*", ir.Num(Fraction(2)), ir.FuncTerm("weight", (ir.Var("b"),)))
    look = next(a for a in m.domain.actions if a.name == "look")
    assert look.cost == ir.Num(Fraction(1))
    assert look.precondition == ir.Or((ir.Not(ir.Atom("seen", (ir.Var("b"),))),
                                       ir.Equals(ir.Var("b"), ir.Var("b"))))
    assert look.effect.effects[1] == ir.Probabilistic(
        (ir.Outcome(Fraction(1, 3), ir.Lit(ir.Atom("seen", (ir.Var("b"),)), False)),))
    gens = {g.name: g for g in m.domain.generators}
    assert gens["reach_gen"].options == (("budget", 3), ("noise", 0.5))
    assert gens["reach_gen"].certifies == (ir.Atom("reach", (ir.Var("b"), ir.Var("p"), ir.Var("q"))),)
    free = next(p for p in m.domain.predicates if p.name == "free")
    assert free.unknowable and free.optimistic is True
    assert [o.name for o in m.problem.objects] == ["b0", "b1", "b2", "start"]
    assert m.problem.init_values == ((ir.Atom("weight", (ir.Const("b0"),)), Fraction(3, 2)),)
    assert m.problem.horizon == 7 and m.problem.scene == ir.SceneRef("file", "scenes/one.json")
    assert m.domain.constants == (ir.Object("home", "pose", True),)


def test_lower_needs_a_problem(tmp_path: Path) -> None:
    loaded = load(write(tmp_path, DOMAIN))
    with pytest.raises(StampcError) as info:
        lower(loaded)
    assert info.value.diagnostics[0].code == "E501"
    assert lower_domain(loaded).name == "d"


def test_load_raises_on_errors(tmp_path: Path) -> None:
    with pytest.raises(StampcError) as info:
        load(write(tmp_path, "domain d\ntype t\npredicate p(x: u)\n"))
    # the error plus the lints that hold for this tiny domain (t and p are unused)
    assert [d.code for d in info.value.diagnostics] == ["W402", "W401", "E101"]


def test_both_polarities_make_the_predicate_pessimistic(tmp_path: Path) -> None:
    text = ("domain d\ntype t\npredicate w(x: t)\naction a(x: t)\n    pre  w(x)\n    eff  ? w(x)\n"
            "action b(x: t)\n    pre  not w(x)\n    eff  w(x)\n")
    loaded = load(write(tmp_path, text))
    assert [d.code for d in loaded.diagnostics] == ["W405"]
    w = next(p for p in lower_domain(loaded).predicates if p.name == "w")
    assert w.unknowable and w.optimistic is False


def test_load_together_pairs_domain_and_problem(tmp_path: Path) -> None:
    from stampc.semantics.api import load_together

    dom = write(tmp_path, DOMAIN, "dom.stamp")
    sub = tmp_path / "elsewhere"
    sub.mkdir()
    prob = write(sub, PROBLEM, "prob.stamp")
    loaded = load_together([dom, prob])
    assert loaded.problem is not None and loaded.problem.name == "p" and loaded.domain.name == "d"
    assert lower(loaded).problem.horizon == 7
    bad = write(sub, PROBLEM.replace("seen(b0)", "seen(b9)"), "bad.stamp")
    with pytest.raises(StampcError) as info:
        load_together([dom, bad])
    assert [d.code for d in info.value.diagnostics if d.is_error] == ["E307"]


UNKNOWN_FIXED = """domain d
type arm
type feed
constant left, right: arm
constant f1, f2: feed
? predicate reaches(a: arm, f: feed)
static predicate near(a: arm, f: feed)
predicate done(f: feed)
action pick(a: arm, f: feed)
    pre  reaches(a, f), near(a, f)
    eff  done(f)
"""


def test_an_unknown_predicate_is_a_fluent_at_its_optimistic_value(tmp_path: Path) -> None:
    """`? predicate`: no action changes it, yet it is neither static nor compiled away —
    refinement learns its facts — and every fact starts at the optimistic value."""
    import stampc
    from stampc.semantics.api import parse
    from stampc.syntax.fmt import format_program

    domain = write(tmp_path, UNKNOWN_FIXED, "d.stamp")
    problem = write(tmp_path, "problem p for d\ninit near(left, f1), near(right, f2)\n"
                    "goal done(f1), done(f2)\n", "p.stamp")
    loaded = load(domain)
    assert [d.code for d in loaded.diagnostics] == ["W408"]  # no evaluator bound here
    reaches = next(p for p in lower_domain(loaded).predicates if p.name == "reaches")
    assert reaches.unknowable and reaches.optimistic is True and not reaches.static
    gm = stampc.ground(stampc.compile(str(domain), str(problem)))
    facts = [(f.predicate, f.args) for f in gm.facts]
    held = {facts[i] for i in range(len(facts)) if gm.init >> i & 1}
    picks = {a.args: a for a in gm.actions if a.name == "pick"}
    assert set(picks) == {("left", "f1"), ("right", "f2")}  # `near` is static: compiled away
    assert {("reaches", args) for args in picks} <= held
    bit = facts.index(("reaches", ("left", "f1")))
    assert picks[("left", "f1")].precondition.pos >> bit & 1  # kept for refinement
    formatted = format_program(parse(UNKNOWN_FIXED), UNKNOWN_FIXED)
    assert "\n? predicate reaches(a: arm, f: feed)\n" in formatted
