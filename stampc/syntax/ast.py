"""The stamp abstract syntax tree: frozen dataclasses, each with a source span.

Spans are excluded from equality (``compare=False``) so that two trees that differ only
in layout compare equal; this is what ``parse(fmt(x)) == x`` relies on. Names are
:class:`Ident` (text + span) so diagnostics can point at the exact identifier.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Union

from stampc.diagnostics import Span
from stampc.syntax.indexed import (IndexCond, IndexedAtom, IndexedName, IndexExpr, IndexNum,  # noqa: F401
                                   IndexOp, IndexRange, IndexVar, InitForall, NOWHERE, ObjectGrid,
                                   span_field)

_span = span_field


@dataclass(frozen=True, slots=True)
class Ident:
    name: str
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Param:
    name: Ident
    type: Ident
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Number:
    value: Fraction
    text: str = field(default="", compare=False)
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class String:
    value: str
    span: Span = _span()


# ------------------------------------------------------------------ formulas
@dataclass(frozen=True, slots=True)
class Atom:
    predicate: Ident
    args: tuple[Ident, ...]
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Eq:
    left: Ident
    right: Ident
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Not:
    arg: "Formula"
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class And:
    args: tuple["Formula", ...]
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Or:
    args: tuple["Formula", ...]
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Implies:
    left: "Formula"
    right: "Formula"
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Quantified:
    kind: str  # "forall" | "exists"
    params: tuple[Param, ...]
    body: "Formula"
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Truth:
    value: bool
    span: Span = _span()


Formula = Union[Atom, Eq, Not, And, Or, Implies, Quantified, Truth]


# ------------------------------------------------------------------- numeric
@dataclass(frozen=True, slots=True)
class FuncApp:
    function: Ident
    args: tuple[Ident, ...]
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class BinOp:
    op: str
    left: "NumExpr"
    right: "NumExpr"
    span: Span = _span()


NumExpr = Union[Number, FuncApp, BinOp]


# ------------------------------------------------------------------- effects
@dataclass(frozen=True, slots=True)
class Lit:
    atom: Atom
    positive: bool = True
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Unknown:
    atom: Atom
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class EffAnd:
    effects: tuple["Effect", ...]
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class When:
    condition: Formula
    effect: "Effect"
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class EffForall:
    params: tuple[Param, ...]
    effect: "Effect"
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Outcome:
    probability: Number
    effect: "Effect"
    label: Ident | None = None
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Probabilistic:
    outcomes: tuple[Outcome, ...]
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class CostEffect:
    amount: NumExpr
    span: Span = _span()


Effect = Union[Lit, Unknown, EffAnd, When, EffForall, Probabilistic, CostEffect]


# -------------------------------------------------------------- declarations
@dataclass(frozen=True, slots=True)
class DomainHeader:
    name: Ident
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class ProblemHeader:
    name: Ident
    domain: Ident
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class ModuleHeader:
    name: Ident
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Use:
    target: str
    is_path: bool
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class TypeDecl:
    names: tuple[Ident, ...]
    parent: Ident | None = None
    continuous: bool = False
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class ConstantDecl:
    names: tuple[Ident, ...]
    type: Ident
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class PredicateDecl:
    """A predicate; ``derived`` holds the definition of a derived one
    (``derived predicate p(x: t) := formula``), whose value is never set by effects."""

    name: Ident
    params: tuple[Param, ...]
    static: bool = False
    span: Span = _span()
    symmetric: bool = False
    derived: "Formula | None" = None
    #: ``? predicate``: no action changes it, yet the abstraction does not know its value
    #: (it assumes the optimistic one until refinement's evaluator decides a fact)
    unknown: bool = False


@dataclass(frozen=True, slots=True)
class FunctionDecl:
    name: Ident
    params: tuple[Param, ...]
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Option:
    """``budget 4`` is ``Option(budget, 4)``; values are Number, String or bool."""

    name: Ident
    value: object
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class GeneratorDecl:
    name: Ident
    inputs: tuple[Param, ...]
    outputs: tuple[Param, ...]
    certifies: tuple[Atom, ...]
    binding: String | None
    options: tuple[Option, ...] = ()
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class EvaluatorDecl:
    predicate: Ident
    binding: String | None
    options: tuple[Option, ...] = ()
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class Sample:
    """``sample g, q from grasp(o, p)``: an explicit generator use."""

    outputs: tuple[Ident, ...]
    generator: Ident
    inputs: tuple[Ident, ...]
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class ActionDecl:
    name: Ident
    params: tuple[Param, ...]
    pre: Formula | None = None
    eff: Effect | None = None
    cost: NumExpr | None = None
    executes: String | None = None
    samples: tuple[Sample, ...] = ()
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class ObjectRange:
    first: Ident
    last: Ident
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class ObjectDecl:
    items: tuple[Ident | ObjectRange | ObjectGrid, ...]
    type: Ident
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class InitValue:
    atom: Atom
    value: Number
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class InitDecl:
    facts: tuple[Atom | InitValue | InitForall, ...]
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class GoalDecl:
    formula: Formula
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class HorizonDecl:
    value: Number
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class SceneDecl:
    kind: str  # "file" | "builder"
    target: String
    args: tuple[Option, ...] = ()
    span: Span = _span()


Decl = Union[DomainHeader, ProblemHeader, ModuleHeader, Use, TypeDecl, ConstantDecl,
             PredicateDecl, FunctionDecl, GeneratorDecl, EvaluatorDecl, ActionDecl,
             ObjectDecl, InitDecl, GoalDecl, HorizonDecl, SceneDecl]


@dataclass(frozen=True, slots=True)
class Program:
    """One source file: its declarations in order."""

    decls: tuple[Decl, ...]
    file: str = field(default="<string>", compare=False)
