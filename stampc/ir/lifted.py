"""The lifted abstract SSP IR: what the front end and the PPDDL importer both produce.

Everything here is a frozen dataclass so models can be hashed, compared and shared.
Formulas and effects are small algebraic trees. Probabilities and costs are exact
:class:`fractions.Fraction` values. Spans (optional) point back at the source so later
stages (grounding, refinement) can still report located diagnostics.

Conventions
- A term is a :class:`Var` (action/quantifier parameter) or a :class:`Const` (object).
- ``Predicate.unknowable`` marks predicates that some effect annotates with ``?``: their
  value after that effect is decided by refinement; the abstraction assumes
  ``Predicate.optimistic`` (the value that makes preconditions easiest to satisfy).
- Continuous types (``Type.continuous``) are entity-abstracted: their objects are
  symbols whose concrete values come from generators or from the initial scene.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Union

from stampc.diagnostics import Span

IR_VERSION = "2.2"


# ------------------------------------------------------------------ terms
@dataclass(frozen=True, slots=True)
class Var:
    name: str


@dataclass(frozen=True, slots=True)
class Const:
    name: str


Term = Union[Var, Const]


@dataclass(frozen=True, slots=True)
class Param:
    name: str
    type: str


# --------------------------------------------------------------- formulas
@dataclass(frozen=True, slots=True)
class Atom:
    predicate: str
    args: tuple[Term, ...]


@dataclass(frozen=True, slots=True)
class Equals:
    left: Term
    right: Term


@dataclass(frozen=True, slots=True)
class Not:
    arg: "Formula"


@dataclass(frozen=True, slots=True)
class And:
    args: tuple["Formula", ...]


@dataclass(frozen=True, slots=True)
class Or:
    args: tuple["Formula", ...]


@dataclass(frozen=True, slots=True)
class Imply:
    left: "Formula"
    right: "Formula"


@dataclass(frozen=True, slots=True)
class Forall:
    params: tuple[Param, ...]
    body: "Formula"


@dataclass(frozen=True, slots=True)
class Exists:
    params: tuple[Param, ...]
    body: "Formula"


@dataclass(frozen=True, slots=True)
class Truth:
    value: bool


Formula = Union[Atom, Equals, Not, And, Or, Imply, Forall, Exists, Truth]
TRUE = Truth(True)


# ---------------------------------------------------------------- numeric
@dataclass(frozen=True, slots=True)
class Num:
    value: Fraction


@dataclass(frozen=True, slots=True)
class FuncTerm:
    """Application of a static numeric function, e.g. ``weight(o)``."""

    function: str
    args: tuple[Term, ...]


@dataclass(frozen=True, slots=True)
class BinOp:
    op: str  # one of + - * /
    left: "NumExpr"
    right: "NumExpr"


NumExpr = Union[Num, FuncTerm, BinOp]


# ----------------------------------------------------------------- effects
@dataclass(frozen=True, slots=True)
class Lit:
    """Add (``positive``) or delete an atom."""

    atom: Atom
    positive: bool = True


@dataclass(frozen=True, slots=True)
class Unknown:
    """``? atom``: after the action the atom's value is unknown to the abstraction."""

    atom: Atom


@dataclass(frozen=True, slots=True)
class EffAnd:
    effects: tuple["Effect", ...]


@dataclass(frozen=True, slots=True)
class When:
    condition: Formula
    effect: "Effect"


@dataclass(frozen=True, slots=True)
class EffForall:
    params: tuple[Param, ...]
    effect: "Effect"


@dataclass(frozen=True, slots=True)
class Outcome:
    probability: Fraction
    effect: "Effect"
    label: str | None = None


@dataclass(frozen=True, slots=True)
class Probabilistic:
    """Independent probabilistic block; probabilities may sum below 1 (rest: no-op)."""

    outcomes: tuple[Outcome, ...]


@dataclass(frozen=True, slots=True)
class CostEffect:
    """Adds ``amount`` to the action's cost when this effect fires.

    PPDDL ``(decrease (reward) k)`` imports as ``CostEffect(Num(k))``; ``increase``
    as a negative amount.
    """

    amount: NumExpr


Effect = Union[Lit, Unknown, EffAnd, When, EffForall, Probabilistic, CostEffect]
NO_EFFECT = EffAnd(())


# ----------------------------------------------------------- declarations
@dataclass(frozen=True, slots=True)
class Type:
    name: str
    parent: str | None = None
    continuous: bool = False
    span: Span | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class Object:
    name: str
    type: str
    #: True for symbols standing for continuous values (entity abstraction).
    symbolic: bool = False
    span: Span | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class Predicate:
    name: str
    params: tuple[Param, ...]
    static: bool = False
    unknowable: bool = False
    optimistic: bool = False
    span: Span | None = field(default=None, compare=False)
    #: p(a, b) holds iff p(b, a) (two parameters of one type): init facts and effects are
    #: mirrored by :func:`stampc.ir.derived.compile_derived`
    symmetric: bool = False
    #: defined by axioms (``Domain.axioms``), never set by effects
    derived: bool = False


@dataclass(frozen=True, slots=True)
class Function:
    """A static numeric function (e.g. for action costs); values given in the problem."""

    name: str
    params: tuple[Param, ...]
    span: Span | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class Binding:
    """A reference to Python code, ``"pkg.module:function"``; never imported by the compiler.

    A module path starting with ``.`` is relative to the world package chosen at refine
    time (``".manipulation:grasp"`` -> ``stampc.worlds.<world>.manipulation:grasp``).
    """

    target: str
    span: Span | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class Generator:
    name: str
    inputs: tuple[Param, ...]
    outputs: tuple[Param, ...]
    certifies: tuple[Atom, ...]
    binding: Binding
    #: e.g. {"budget": 8}; values are JSON scalars
    options: tuple[tuple[str, object], ...] = ()
    span: Span | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class Evaluator:
    """Decides a ``?`` predicate in a concrete world state."""

    predicate: str
    binding: Binding
    span: Span | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class GeneratorUse:
    """Within an action: generator ``generator`` applied to action parameters ``inputs``
    produces the action parameters ``outputs`` (one Skolem symbol each per ground action)."""

    generator: str
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class Action:
    name: str
    params: tuple[Param, ...]
    precondition: Formula
    effect: Effect
    #: Base cost added to any CostEffect amounts; ``None`` means "default" (1 for stamp
    #: domains and PPDDL domains without rewards, 0 for PPDDL domains with rewards).
    cost: NumExpr | None = None
    #: How continuous parameters are produced (in dependency order).
    generated: tuple[GeneratorUse, ...] = ()
    #: Optional binding applying the action's concrete effect in a world.
    executes: Binding | None = None
    span: Span | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class Axiom:
    """A derived predicate's rule: ``predicate(params)`` holds when ``body`` does (PDDL
    ``:derived``; several rules for one predicate mean "any of them")."""

    predicate: str
    params: tuple[Param, ...]
    body: Formula
    span: Span | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class Domain:
    name: str
    types: tuple[Type, ...]
    constants: tuple[Object, ...]
    predicates: tuple[Predicate, ...]
    functions: tuple[Function, ...]
    actions: tuple[Action, ...]
    generators: tuple[Generator, ...] = ()
    evaluators: tuple[Evaluator, ...] = ()
    #: PPDDL requirement flags seen on import (informational; the emitter recomputes).
    requirements: tuple[str, ...] = ()
    span: Span | None = field(default=None, compare=False)
    #: rules of derived predicates (compiled away before grounding: docs/ir.md)
    axioms: tuple[Axiom, ...] = ()


@dataclass(frozen=True, slots=True)
class SceneRef:
    """The concrete initial world: a scene file or a bound scene builder with arguments."""

    kind: str  # "file" | "builder"
    target: str
    args: tuple[tuple[str, object], ...] = ()
    span: Span | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class Problem:
    name: str
    domain: str
    objects: tuple[Object, ...]
    init: tuple[Atom, ...]
    #: Values of static numeric functions: ((function, args), value)
    init_values: tuple[tuple[Atom, Fraction], ...] = ()
    goal: Formula = TRUE
    horizon: int | None = None
    scene: SceneRef | None = None
    #: PPDDL (:goal-reward R) and (:metric ...), kept for faithful re-emission.
    goal_reward: Fraction | None = None
    metric: str | None = None
    span: Span | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class Model:
    """A lifted domain + problem pair: the compiler's main product.

    Plain data: stages operate on it (``stampc.ground(model)``, ``stampc.to_ppddl(model)``),
    so the IR imports nothing from the stages above it."""

    domain: Domain
    problem: Problem
    #: warnings of the front end that built it (e.g. the PPDDL importer's --lenient)
    diagnostics: tuple = field(default=(), compare=False)
