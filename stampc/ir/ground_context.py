"""Read-only tables derived from a lifted model, shared by every grounding stage.

Builds the type hierarchy (``object`` is the implicit root), the object tables, the
predicate classification (static / fluent / unknowable) and the static function values.
The model must already have passed :func:`stampc.ir.validate.validate_model`.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Iterator, NoReturn

from stampc.diagnostics import Span, StampcError, error
from stampc.ir import lifted as L

ROOT_TYPE = "object"

#: A ground atom inside the grounder: (predicate, argument names). Plain tuples hash and
#: compare much faster than GroundAtom dataclasses; they sort exactly like GroundAtom.
AtomKey = tuple[str, tuple[str, ...]]


def model_span(model: L.Model) -> Span:
    """Best available location for model-wide diagnostics."""
    return model.problem.span or model.domain.span or Span.point(f"<problem {model.problem.name}>")


def located(span: Span | None, model: L.Model) -> Span:
    return span if span is not None else model_span(model)


def fail(code: str, message: str, span: Span, hint: str | None = None) -> NoReturn:
    raise StampcError([error(code, message, span, hint)])


def iter_effect_atoms(effect: L.Effect) -> Iterator[tuple[L.Atom, bool]]:
    """Every atom an effect touches, with ``True`` when it is a ``?`` (Unknown) effect."""
    if isinstance(effect, L.Lit):
        yield effect.atom, False
    elif isinstance(effect, L.Unknown):
        yield effect.atom, True
    elif isinstance(effect, L.EffAnd):
        for sub in effect.effects:
            yield from iter_effect_atoms(sub)
    elif isinstance(effect, (L.When, L.EffForall)):
        yield from iter_effect_atoms(effect.effect)
    elif isinstance(effect, L.Probabilistic):
        for outcome in effect.outcomes:
            yield from iter_effect_atoms(outcome.effect)


def has_cost_effect(effect: L.Effect) -> bool:
    if isinstance(effect, L.CostEffect):
        return True
    if isinstance(effect, L.EffAnd):
        return any(has_cost_effect(e) for e in effect.effects)
    if isinstance(effect, (L.When, L.EffForall)):
        return has_cost_effect(effect.effect)
    if isinstance(effect, L.Probabilistic):
        return any(has_cost_effect(o.effect) for o in effect.outcomes)
    return False


@dataclass(frozen=True)
class CostPolicy:
    """How base costs default: see docs/ir.md (cost defaults)."""

    default_cost: Fraction
    has_costs: bool


def cost_policy(domain: L.Domain) -> CostPolicy:
    rewards = ":rewards" in domain.requirements or "rewards" in domain.requirements
    cost_effects = any(has_cost_effect(a.effect) for a in domain.actions)
    # the stamp front end writes the unit default explicitly: only other costs count
    unit = L.Num(Fraction(1))
    explicit = any(a.cost is not None and a.cost != unit for a in domain.actions)
    default = Fraction(0) if (rewards or cost_effects) else Fraction(1)
    return CostPolicy(default, rewards or cost_effects or explicit)


class GroundingContext:
    """Lookup tables over one lifted model (plus the Skolem symbols found later)."""

    def __init__(self, model: L.Model):
        self.model = model
        domain, problem = model.domain, model.problem
        self.parent: dict[str, str | None] = {ROOT_TYPE: None}
        for t in domain.types:
            if t.name != ROOT_TYPE:
                self.parent[t.name] = t.parent or ROOT_TYPE
        self._ancestors: dict[str, tuple[str, ...]] = {}
        # constants first, then problem objects, in declaration order (deterministic)
        self.object_type: dict[str, str] = {}
        for obj in (*domain.constants, *problem.objects):
            self.object_type.setdefault(obj.name, obj.type)
        self.base_objects: tuple[tuple[str, str], ...] = tuple(self.object_type.items())
        self._by_type: dict[str, tuple[str, ...]] = {}
        self.predicates: dict[str, L.Predicate] = {p.name: p for p in domain.predicates}
        self.actions = domain.actions
        self.generators: dict[str, L.Generator] = {g.name: g for g in domain.generators}
        touched: set[str] = set()
        unknown_marked: set[str] = set()
        for action in domain.actions:
            for atom, is_unknown in iter_effect_atoms(action.effect):
                touched.add(atom.predicate)
                if is_unknown:
                    unknown_marked.add(atom.predicate)
        #: derived predicates kept as axioms (recursive over fluents): per-state facts
        self.derived: frozenset[str] = frozenset(ax.predicate for ax in domain.axioms)
        self.unknowable: frozenset[str] = frozenset(
            unknown_marked | {p.name for p in domain.predicates if p.unknowable})
        #: predicates no effect touches: evaluated at grounding time and compiled away
        #: (not a `? predicate`: no effect touches it, but refinement learns its facts)
        self.static: frozenset[str] = frozenset(
            set(self.predicates) - touched - self.derived - self.unknowable)
        #: unknowable predicates whose facts the abstraction assumes true
        self.optimistic_true: frozenset[str] = frozenset(
            p for p in self.unknowable if self.predicates[p].optimistic)
        self.function_values: dict[tuple[str, tuple[str, ...]], Fraction] = {}
        for atom, value in problem.init_values:
            args = tuple(t.name for t in atom.args)
            self.function_values[(atom.predicate, args)] = Fraction(value)
        self.costs = cost_policy(domain)

    # ------------------------------------------------------------- types
    def ancestors(self, type_name: str) -> tuple[str, ...]:
        """``type_name`` and all its ancestors up to ``object`` (validated acyclic)."""
        cached = self._ancestors.get(type_name)
        if cached is None:
            chain, t = [], type_name
            while t is not None and t not in chain:
                chain.append(t)
                t = self.parent.get(t, ROOT_TYPE if t != ROOT_TYPE else None)
            cached = self._ancestors[type_name] = tuple(chain)
        return cached

    def is_of_type(self, obj: str, type_name: str) -> bool:
        t = self.object_type.get(obj)
        return t is not None and type_name in self.ancestors(t)

    def objects_of(self, type_name: str) -> tuple[str, ...]:
        """Objects of ``type_name`` or a subtype, in object order (symbols last)."""
        cached = self._by_type.get(type_name)
        if cached is None:
            cached = tuple(o for o, t in self.object_type.items()
                           if type_name in self.ancestors(t))
            self._by_type[type_name] = cached
        return cached

    def add_symbols(self, symbols: list[tuple[str, str]]) -> None:
        """Register Skolem symbols (already sorted) after the reachability fixpoint."""
        for name, type_name in symbols:
            self.object_type[name] = type_name
        self._by_type.clear()

    @property
    def all_objects(self) -> tuple[tuple[str, str], ...]:
        return tuple(self.object_type.items())

    def is_static(self, predicate: str) -> bool:
        return predicate in self.static
