"""Structural renaming of lifted formulas and effects.

Used by the emitter's name mangling and by the round-trip canonicalizer. A
:class:`Renaming` holds one function per namespace; each returns the new name.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from stampc.ir.lifted import (
    And, Atom, BinOp, Const, CostEffect, EffAnd, EffForall, Effect, Equals, Exists, Forall,
    Formula, FuncTerm, Imply, Lit, Not, Num, NumExpr, Or, Outcome, Param, Probabilistic,
    Term, Truth, Unknown, Var, When,
)

Rename = Callable[[str], str]


def _same(name: str) -> str:
    return name


@dataclass(frozen=True)
class Renaming:
    predicate: Rename = _same
    function: Rename = _same
    obj: Rename = _same
    var: Rename = _same
    type: Rename = _same

    def term(self, t: Term) -> Term:
        return Var(self.var(t.name)) if isinstance(t, Var) else Const(self.obj(t.name))

    def atom(self, a: Atom) -> Atom:
        return Atom(self.predicate(a.predicate), tuple(self.term(t) for t in a.args))

    def params(self, params: tuple[Param, ...]) -> tuple[Param, ...]:
        return tuple(Param(self.var(p.name), self.type(p.type)) for p in params)

    def formula(self, f: Formula) -> Formula:
        if isinstance(f, Atom):
            return self.atom(f)
        if isinstance(f, Equals):
            return Equals(self.term(f.left), self.term(f.right))
        if isinstance(f, Not):
            return Not(self.formula(f.arg))
        if isinstance(f, And):
            return And(tuple(self.formula(a) for a in f.args))
        if isinstance(f, Or):
            return Or(tuple(self.formula(a) for a in f.args))
        if isinstance(f, Imply):
            return Imply(self.formula(f.left), self.formula(f.right))
        if isinstance(f, Forall):
            return Forall(self.params(f.params), self.formula(f.body))
        if isinstance(f, Exists):
            return Exists(self.params(f.params), self.formula(f.body))
        assert isinstance(f, Truth), f
        return f

    def num(self, e: NumExpr) -> NumExpr:
        if isinstance(e, FuncTerm):
            return FuncTerm(self.function(e.function), tuple(self.term(t) for t in e.args))
        if isinstance(e, BinOp):
            return BinOp(e.op, self.num(e.left), self.num(e.right))
        assert isinstance(e, Num), e
        return e

    def effect(self, e: Effect) -> Effect:
        if isinstance(e, Lit):
            return Lit(self.atom(e.atom), e.positive)
        if isinstance(e, Unknown):
            return Unknown(self.atom(e.atom))
        if isinstance(e, EffAnd):
            return EffAnd(tuple(self.effect(x) for x in e.effects))
        if isinstance(e, When):
            return When(self.formula(e.condition), self.effect(e.effect))
        if isinstance(e, EffForall):
            return EffForall(self.params(e.params), self.effect(e.effect))
        if isinstance(e, Probabilistic):
            return Probabilistic(tuple(Outcome(o.probability, self.effect(o.effect), o.label)
                                       for o in e.outcomes))
        assert isinstance(e, CostEffect), e
        return CostEffect(self.num(e.amount))


# ------------------------------------------------------------ variable names
def formula_vars(f: Formula) -> list[str]:
    """Names of variables bound by quantifiers in ``f`` (in order, with repeats)."""
    if isinstance(f, (Forall, Exists)):
        return [p.name for p in f.params] + formula_vars(f.body)
    if isinstance(f, Not):
        return formula_vars(f.arg)
    if isinstance(f, (And, Or)):
        return [v for a in f.args for v in formula_vars(a)]
    if isinstance(f, Imply):
        return formula_vars(f.left) + formula_vars(f.right)
    return []


def effect_vars(e: Effect) -> list[str]:
    """Names of variables bound by quantifiers in ``e`` (including its conditions)."""
    if isinstance(e, EffAnd):
        return [v for x in e.effects for v in effect_vars(x)]
    if isinstance(e, When):
        return formula_vars(e.condition) + effect_vars(e.effect)
    if isinstance(e, EffForall):
        return [p.name for p in e.params] + effect_vars(e.effect)
    if isinstance(e, Probabilistic):
        return [v for o in e.outcomes for v in effect_vars(o.effect)]
    return []
