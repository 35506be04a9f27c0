"""Rendering of (already mangled) lifted formulas, effects and numbers as PPDDL text.

Expressions become a tiny document tree (:class:`Group`, :class:`Pair`,
:class:`Commented`, plain strings) that :func:`layout` prints on one line when it fits
and broken over indented lines otherwise. Comments always sit on their own line
before the element they describe, so a closing parenthesis never ends up in a comment.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Union

from stampc.ir.lifted import (
    And, Atom, BinOp, CostEffect, EffAnd, EffForall, Effect, Equals, Exists, Forall,
    Formula, FuncTerm, Imply, Lit, Not, Num, NumExpr, Or, Param, Probabilistic, Term,
    Truth, Unknown, Var, When,
)

WIDTH = 88
_MAX_DECIMALS = 6


@dataclass(frozen=True)
class Group:
    """``(head item item ...)``"""

    head: str
    items: tuple["Doc", ...] = ()


@dataclass(frozen=True)
class Pair:
    """``prefix item`` without parentheses (a probabilistic outcome)."""

    prefix: str
    item: "Doc"


@dataclass(frozen=True)
class Commented:
    comment: str
    item: "Doc"


Doc = Union[str, Group, Pair, Commented]


# ------------------------------------------------------------------ numbers
def number(value: Fraction) -> str:
    """Exact PPDDL literal: integer, short decimal (``0.8``) or fraction (``1/3``)."""
    value = Fraction(value)
    if value.denominator == 1:
        return str(value.numerator)
    den = value.denominator
    twos = fives = 0
    while den % 2 == 0:
        den, twos = den // 2, twos + 1
    while den % 5 == 0:
        den, fives = den // 5, fives + 1
    digits = max(twos, fives)
    if den == 1 and digits <= _MAX_DECIMALS:
        sign = "-" if value < 0 else ""
        scaled = abs(value) * 10 ** digits
        whole, frac = divmod(int(scaled), 10 ** digits)
        return f"{sign}{whole}.{frac:0{digits}d}"
    return f"{value.numerator}/{value.denominator}"


# ----------------------------------------------------------------- printing
def flat(doc: Doc) -> str | None:
    """One-line text, or ``None`` when ``doc`` holds a comment."""
    if isinstance(doc, str):
        return doc
    if isinstance(doc, Commented):
        return None
    if isinstance(doc, Pair):
        inner = flat(doc.item)
        return None if inner is None else f"{doc.prefix} {inner}"
    parts = [doc.head]
    for item in doc.items:
        text = flat(item)
        if text is None:
            return None
        parts.append(text)
    return "(" + " ".join(parts) + ")"


def layout(doc: Doc, indent: int = 0, width: int = WIDTH) -> list[str]:
    """Lines (without the leading indentation of the first one) for ``doc``."""
    text = flat(doc)
    if text is not None and indent + len(text) <= width:
        return [text]
    pad = " " * (indent + 2)
    if isinstance(doc, str):
        return [doc]
    if isinstance(doc, Commented):
        # the comment takes the element's place; the element moves to the next line
        item = layout(doc.item, indent, width)
        return [f"; {doc.comment}", " " * indent + item[0]] + item[1:]
    if isinstance(doc, Pair):
        lines = layout(doc.item, indent + 2, width)
        return [doc.prefix] + [pad + lines[0]] + lines[1:]
    lines = ["(" + doc.head]
    for item in doc.items:
        sub = layout(item, indent + 2, width)
        lines.append(pad + sub[0])
        lines.extend(sub[1:])
    lines[-1] += ")"
    return lines


def text(doc: Doc, indent: int = 0) -> str:
    return "\n".join(layout(doc, indent)) if doc is not None else ""


# ---------------------------------------------------------------- formulas
def term(t: Term) -> str:
    return f"?{t.name}" if isinstance(t, Var) else t.name


def atom(a: Atom) -> Doc:
    return Group(a.predicate, tuple(term(t) for t in a.args))


def params(ps: tuple[Param, ...], typed: bool = True) -> str:
    if not typed:
        return " ".join(f"?{p.name}" for p in ps)
    return " ".join(f"?{p.name} - {p.type}" for p in ps)


def formula(f: Formula, typed: bool = True) -> Doc:
    if isinstance(f, Atom):
        return atom(f)
    if isinstance(f, Equals):
        return Group("=", (term(f.left), term(f.right)))
    if isinstance(f, Not):
        return Group("not", (formula(f.arg, typed),))
    if isinstance(f, And):
        return Group("and", tuple(formula(a, typed) for a in f.args))
    if isinstance(f, Or):
        return Group("or", tuple(formula(a, typed) for a in f.args))
    if isinstance(f, Imply):
        return Group("imply", (formula(f.left, typed), formula(f.right, typed)))
    if isinstance(f, (Forall, Exists)):
        head = "forall" if isinstance(f, Forall) else "exists"
        return Group(head, (f"({params(f.params, typed)})", formula(f.body, typed)))
    assert isinstance(f, Truth), f
    return "(and)" if f.value else "(or)"


def num_expr(e: NumExpr) -> Doc:
    if isinstance(e, Num):
        return number(e.value)
    if isinstance(e, FuncTerm):
        return Group(e.function, tuple(term(t) for t in e.args))
    return Group(e.op, (num_expr(e.left), num_expr(e.right)))


def cost(amount: NumExpr) -> Doc:
    """A cost of ``amount`` as an IPPC reward change."""
    if isinstance(amount, Num) and amount.value < 0:
        return Group("increase", ("(reward)", number(-amount.value)))
    if (isinstance(amount, BinOp) and amount.op == "-" and isinstance(amount.left, Num)
            and amount.left.value == 0):
        return Group("increase", ("(reward)", num_expr(amount.right)))
    return Group("decrease", ("(reward)", num_expr(amount)))


def effect(e: Effect, optimistic: dict[str, bool], typed: bool = True) -> Doc:
    """``optimistic`` gives, per predicate, the value a ``?`` effect is emitted as."""
    if isinstance(e, Lit):
        return atom(e.atom) if e.positive else Group("not", (atom(e.atom),))
    if isinstance(e, Unknown):
        value = optimistic.get(e.atom.predicate, False)
        lit = atom(e.atom) if value else Group("not", (atom(e.atom),))
        return Commented(f"? {flat(atom(e.atom))}: unknown after the action; emitted as its "
                         f"optimistic value ({str(value).lower()})", lit)
    if isinstance(e, EffAnd):
        return Group("and", tuple(effect(x, optimistic, typed) for x in e.effects))
    if isinstance(e, When):
        return Group("when", (formula(e.condition, typed), effect(e.effect, optimistic, typed)))
    if isinstance(e, EffForall):
        return Group("forall", (f"({params(e.params, typed)})",
                                effect(e.effect, optimistic, typed)))
    if isinstance(e, Probabilistic):
        return Group("probabilistic", tuple(Pair(number(o.probability),
                                                 effect(o.effect, optimistic, typed))
                                            for o in e.outcomes))
    assert isinstance(e, CostEffect), e
    return cost(e.amount)
