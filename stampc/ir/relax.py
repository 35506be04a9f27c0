"""Compile a lifted model into Datalog rules over its delete relaxation.

Relaxation (an over-approximation, so reachability never prunes a reachable action):
negative fluent conditions and universal quantifiers count as satisfiable, a
disjunction as any branch, every probabilistic outcome as possible, and a conditional
effect fires when its condition is relaxed-reachable. Static predicates are exact
(positive atoms join against static facts, negated ones filter). Every variable also
gets a type atom ``@type:T(v)``, so each rule variable is bound by some body atom.

Relations: predicates, ``@type:<T>`` (objects of T or a subtype), ``@act:<i>`` (reachable
bindings of all parameters of action schema i) and ``@pre:<i>`` (bindings of the
non-generated parameters of a schema with generated ones; reachability then creates the
Skolem symbols and the ``@act`` binding).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable

from stampc.ir import lifted as L
from stampc.ir.ground_context import GroundingContext

#: A rule term: (is_variable, name). Variables are rule-local, constants object names.
RTerm = tuple[bool, str]
#: Disjunctive bodies larger than this are relaxed to "true" (sound, only less precise).
MAX_BODIES = 64


@dataclass(frozen=True, slots=True)
class Pattern:
    rel: str
    terms: tuple[RTerm, ...]


@dataclass(frozen=True, slots=True)
class Filter:
    """``eq``/``neq`` between two terms, or ``nstatic``: a static atom must be absent."""

    kind: str
    terms: tuple[RTerm, ...]
    rel: str = ""


Item = Pattern | Filter
Body = tuple[Item, ...]


@dataclass(frozen=True, slots=True)
class Rule:
    head_rel: str
    head_terms: tuple[RTerm, ...]
    body: tuple[Pattern, ...]
    filters: tuple[Filter, ...]


def type_rel(type_name: str) -> str:
    return f"@type:{type_name}"


def act_rel(schema: int) -> str:
    return f"@act:{schema}"


def pre_rel(schema: int) -> str:
    return f"@pre:{schema}"


def _product(left: list[Body], right: list[Body]) -> list[Body]:
    out = [a + b for a in left for b in right]
    return out if len(out) <= MAX_BODIES else [()]


class _Compiler:
    """Relaxed DNF of formulas; one instance per action so fresh names stay unique."""

    def __init__(self, ctx: GroundingContext, skip_vars: frozenset[str],
                 shared: dict | None = None):
        self.ctx = ctx
        self.skip = skip_vars  # generated parameters: not joinable, items dropped
        self.counter = 0
        #: equal rule parts of all schemas, stored once (see :func:`_rule`)
        self.shared = {} if shared is None else shared

    def fresh(self, params: tuple[L.Param, ...], rename: dict[str, str]) -> tuple[dict, Body]:
        rename = dict(rename)
        items: list[Item] = []
        for p in params:
            self.counter += 1
            name = f"{p.name}#{self.counter}"
            rename[p.name] = name
            items.append(Pattern(type_rel(p.type), ((True, name),)))
        return rename, tuple(items)

    def term(self, t: L.Term, rename: dict[str, str]) -> RTerm | None:
        if isinstance(t, L.Const):
            return (False, t.name)
        name = rename.get(t.name, t.name)
        return None if name in self.skip else (True, name)

    def terms(self, args: Iterable[L.Term], rename: dict[str, str]) -> tuple[RTerm, ...] | None:
        out = []
        for a in args:
            rt = self.term(a, rename)
            if rt is None:
                return None
            out.append(rt)
        return tuple(out)

    def dnf(self, f: L.Formula, positive: bool, rename: dict[str, str]) -> list[Body]:
        if isinstance(f, L.Atom):
            return self._atom(f, positive, rename)
        if isinstance(f, L.Equals):
            terms = self.terms((f.left, f.right), rename)
            return [()] if terms is None else [(Filter("eq" if positive else "neq", terms),)]
        if isinstance(f, L.Not):
            return self.dnf(f.arg, not positive, rename)
        if isinstance(f, L.Truth):
            return [()] if f.value == positive else []
        if isinstance(f, (L.And, L.Or)):
            conj = isinstance(f, L.And) == positive
            parts = [self.dnf(a, positive, rename) for a in f.args]
            return self._combine(parts, conj)
        if isinstance(f, L.Imply):
            left = self.dnf(f.left, not positive, rename)
            right = self.dnf(f.right, positive, rename)
            return self._combine([left, right], conj=not positive)
        if isinstance(f, (L.Forall, L.Exists)):
            if isinstance(f, L.Exists) != positive:
                return [()]  # universal: relaxed to true
            rename, items = self.fresh(f.params, rename)
            return _product([items], self.dnf(f.body, positive, rename))
        raise TypeError(f"not a formula: {f!r}")

    def _atom(self, f: L.Atom, positive: bool, rename: dict[str, str]) -> list[Body]:
        terms = self.terms(f.args, rename)
        if terms is None:
            return [()]
        if self.ctx.is_static(f.predicate):
            return [(Pattern(f.predicate, terms),)] if positive else \
                [(Filter("nstatic", terms, f.predicate),)]
        if not positive or f.predicate in self.ctx.optimistic_true:
            return [()]
        return [(Pattern(f.predicate, terms),)]

    @staticmethod
    def _combine(parts: list[list[Body]], conj: bool) -> list[Body]:
        if conj:
            out: list[Body] = [()]
            for part in parts:
                out = _product(out, part)
            return out
        union = [b for part in parts for b in part]
        return union if len(union) <= MAX_BODIES else [()]


def _rule(comp: _Compiler, head_rel: str, head_terms: tuple[RTerm, ...], body: Body,
          extra: tuple[Pattern, ...] = ()) -> Rule:
    # Rule parts are interned: copies of one schema (generated domains have thousands)
    # give equal patterns, bodies and filters, which are then stored once.
    shared = comp.shared
    patterns = tuple(shared.setdefault(i, i) for i in body if isinstance(i, Pattern))
    patterns += tuple(shared.setdefault(p, p) for p in extra)
    filters = tuple(i for i in body if isinstance(i, Filter))
    return Rule(head_rel, shared.setdefault(head_terms, head_terms),
                shared.setdefault(patterns, patterns), shared.setdefault(filters, filters))


def action_rules(ctx: GroundingContext, schema: int, shared: dict | None = None) -> list[Rule]:
    """Rules deriving the (non-generated) parameter bindings of one action schema
    (``shared``: a table of rule parts to share between schemas)."""
    action = ctx.actions[schema]
    generated = frozenset(o for use in action.generated for o in use.outputs)
    comp = _Compiler(ctx, generated, shared)
    selected = tuple(p for p in action.params if p.name not in generated)
    types = tuple(Pattern(type_rel(p.type), ((True, p.name),)) for p in selected)
    head_rel = pre_rel(schema) if generated else act_rel(schema)
    head = tuple((True, p.name) for p in selected)
    return [_rule(comp, head_rel, head, body, types)
            for body in comp.dnf(action.precondition, True, {})]


def effect_rules(ctx: GroundingContext, schema: int, shared: dict | None = None) -> list[Rule]:
    """Rules deriving the atoms an action schema's effects can make true."""
    action = ctx.actions[schema]
    comp = _Compiler(ctx, frozenset(), shared)
    base = (Pattern(act_rel(schema), tuple((True, p.name) for p in action.params)),)
    rules: list[Rule] = []
    _walk_effect(comp, action.effect, [base], {}, rules)
    return rules


def _walk_effect(comp: _Compiler, e: L.Effect, path: list[Body], rename: dict[str, str],
                 out: list[Rule]) -> None:
    if isinstance(e, (L.Lit, L.Unknown)):
        if isinstance(e, L.Lit) and not e.positive:
            return  # deletes never make anything reachable
        terms = comp.terms(e.atom.args, rename)
        if terms is not None:
            out.extend(_rule(comp, e.atom.predicate, terms, body) for body in path)
    elif isinstance(e, L.EffAnd):
        for sub in e.effects:
            _walk_effect(comp, sub, path, rename, out)
    elif isinstance(e, L.When):
        cond = comp.dnf(e.condition, True, rename)
        path2 = [a + b for a in path for b in cond]
        if len(path2) > MAX_BODIES:
            path2 = path
        _walk_effect(comp, e.effect, path2, rename, out)
    elif isinstance(e, L.EffForall):
        rename2, items = comp.fresh(e.params, rename)
        _walk_effect(comp, e.effect, [b + items for b in path], rename2, out)
    elif isinstance(e, L.Probabilistic):
        for outcome in e.outcomes:
            if outcome.probability > 0:
                _walk_effect(comp, outcome.effect, path, rename, out)


def axiom_rules(ctx: GroundingContext, axiom: L.Axiom, shared: dict | None = None) -> list[Rule]:
    """Rules deriving the derived atoms a kept axiom can make true (its body relaxed
    like a precondition: negated fluent and derived atoms count as satisfiable)."""
    comp = _Compiler(ctx, frozenset(), shared)
    types = tuple(Pattern(type_rel(p.type), ((True, p.name),)) for p in axiom.params)
    head = tuple((True, p.name) for p in axiom.params)
    return [_rule(comp, axiom.predicate, head, body, types)
            for body in comp.dnf(axiom.body, True, {})]
