"""Exact grounding of formulas and numeric expressions under a variable binding.

Static atoms and equalities are decided here, quantifiers expand over the (typed)
objects including Skolem symbols, ``imply`` becomes ``or``, and fluent atoms become
:class:`GLit` over fact indices. A fluent atom outside the reachable fact set is false in
every reachable state, except for facts of unknowable predicates: no action may set them,
yet refinement decides them in the world (a ``collision`` with an object no action
moves), so they are registered as *missing* facts that the grounder adds (at their
optimistic value) before it re-runs; pruning them would drop the ``?`` checks of every
precondition that names them.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Iterator, Union

from stampc.ir import lifted as L
from stampc.ir.ground_context import AtomKey, GroundingContext, fail, located
from stampc.ir.grounded import GAnd, GFormula, GLit, GOr, GroundCondition
from stampc.ir.guards import GuardedExpander, effect_guards, formula_guards
from stampc.ir.masks import from_indices
from stampc.ir.scope import ScopeAnalysis

#: Result of simplification: a constant or a ground formula.
Simplified = Union[bool, GFormula]
Env = dict[str, str]
NEVER = GroundCondition(never=True)


def conjoin(parts: list[Simplified]) -> Simplified:
    out: list[GFormula] = []
    for p in parts:
        if p is False:
            return False
        if p is True:
            continue
        if isinstance(p, GAnd):
            out.extend(p.args)
        else:
            out.append(p)
    if not out:
        return True
    return out[0] if len(out) == 1 else GAnd(tuple(out))


def disjoin(parts: list[Simplified]) -> Simplified:
    out: list[GFormula] = []
    for p in parts:
        if p is True:
            return True
        if p is False:
            continue
        if isinstance(p, GOr):
            out.extend(p.args)
        else:
            out.append(p)
    if not out:
        return False
    return out[0] if len(out) == 1 else GOr(tuple(out))


def to_condition(f: Simplified) -> GroundCondition:
    """Split a simplified formula into conjunctive masks and a remainder."""
    if f is True:
        return GroundCondition()
    if f is False:
        return NEVER
    pos: list[int] = []
    neg: list[int] = []
    rest: list[GFormula] = []
    for part in (f.args if isinstance(f, GAnd) else (f,)):
        if isinstance(part, GLit):
            (pos if part.positive else neg).append(part.fact)
        else:
            rest.append(part)
    if pos and neg and not set(pos).isdisjoint(neg):
        return NEVER
    return GroundCondition(from_indices(pos), from_indices(neg), tuple(rest))


class FactTable:
    """Fact indices for the reachable fluent atoms, collecting missing unknowable ones."""

    def __init__(self, facts: list[AtomKey], ctx: GroundingContext):
        self.facts = facts
        self.index: dict[AtomKey, int] = {f: i for i, f in enumerate(facts)}
        self.ctx = ctx
        self.missing: set[AtomKey] = set()

    def lookup(self, key: AtomKey) -> int | None:
        i = self.index.get(key)
        if i is None and key[0] in self.ctx.unknowable:
            self.missing.add(key)  # decided by refinement, not by the actions: needs a fact
        return i

    def require(self, key: AtomKey) -> int | None:
        """Index of a fact that must exist (e.g. the target of an add or ``?``)."""
        i = self.index.get(key)
        if i is None:
            self.missing.add(key)
        return i


class Simplifier:
    def __init__(self, ctx: GroundingContext, static: set[AtomKey], facts: FactTable,
                 scopes: ScopeAnalysis):
        self.ctx = ctx
        self.static = static
        self.facts = facts
        self.scopes = scopes
        self.memo: dict[tuple, Simplified] = {}
        self.lit_cache: dict[int, tuple[GLit, GLit]] = {}
        self.expander = GuardedExpander(ctx, static)
        self._guards: dict[tuple[int, bool], list[L.Atom]] = {}
        #: location used in diagnostics raised while grounding the current declaration
        self.span = located(None, ctx.model)

    def forget_nodes(self) -> None:
        """Drop the caches keyed by lifted nodes (memo, guards, scopes): nodes of an
        action schema already ground are not met again, and keeping them for every
        schema made grounding memory grow several kB per action."""
        self.memo.clear()
        self._guards.clear()
        self.scopes.clear()

    def args(self, terms: tuple[L.Term, ...], env: Env) -> tuple[str, ...]:
        # hot path: a list comprehension and exact type checks are ~2x faster here
        return tuple([env[t.name] if type(t) is L.Var else t.name for t in terms])

    def glit(self, fact: int, positive: bool) -> GLit:
        pair = self.lit_cache.get(fact)
        if pair is None:
            pair = self.lit_cache[fact] = (GLit(fact, True), GLit(fact, False))
        return pair[0] if positive else pair[1]

    def atom(self, a: L.Atom, env: Env, positive: bool) -> Simplified:
        key = (a.predicate, self.args(a.args, env))
        if self.ctx.is_static(a.predicate):
            return (key in self.static) == positive
        i = self.facts.lookup(key)
        if i is None:
            return not positive  # never true in a reachable state
        return self.glit(i, positive)

    def formula(self, f: L.Formula, env: Env, positive: bool = True) -> Simplified:
        if isinstance(f, L.Atom):
            return self.atom(f, env, positive)
        if isinstance(f, L.Not):
            return self.formula(f.arg, env, not positive)
        if isinstance(f, L.And) or isinstance(f, L.Or):
            parts = [self.formula(a, env, positive) for a in f.args]
            return conjoin(parts) if isinstance(f, L.And) == positive else disjoin(parts)
        if isinstance(f, L.Equals):
            same = self.args((f.left, f.right), env)
            return (same[0] == same[1]) == positive
        if isinstance(f, L.Truth):
            return f.value == positive
        if isinstance(f, L.Imply):
            parts = [self.formula(f.left, env, not positive), self.formula(f.right, env, positive)]
            return disjoin(parts) if positive else conjoin(parts)
        if isinstance(f, (L.Forall, L.Exists)):
            key = (self.scopes.memo_key(f, env), positive)
            cached = self.memo.get(key)
            if cached is None:
                cached = self.memo[key] = self._quantified(f, env, positive)
            return cached
        raise TypeError(f"not a formula: {f!r}")

    def _quantified(self, f: L.Forall | L.Exists, env: Env, positive: bool) -> Simplified:
        conj = isinstance(f, L.Forall) == positive
        guards = self._guards.get((id(f), positive))
        if guards is None:
            qvars = frozenset(p.name for p in f.params)
            guards = self._guards[(id(f), positive)] = formula_guards(
                self.ctx, f.body, positive, conj, qvars)
        parts: list[Simplified] = []
        for inner in self.expander.bindings(f.params, env, guards):
            part = self.formula(f.body, inner, positive)
            if part is (not conj):  # short-circuit: False in a conjunction, True in a disjunction
                return part
            parts.append(part)
        return conjoin(parts) if conj else disjoin(parts)

    def effect_bindings(self, f: L.EffForall, env: Env) -> Iterator[Env]:
        """Extensions of ``env`` for a ``forall`` effect that can give a non-empty effect."""
        guards = self._guards.get((id(f), True))
        if guards is None:
            guards = self._guards[(id(f), True)] = effect_guards(
                self.ctx, f.effect, frozenset(p.name for p in f.params))
        return self.expander.bindings(f.params, env, guards)

    def condition(self, f: L.Formula, env: Env) -> GroundCondition:
        return to_condition(self.formula(f, env))

    # ------------------------------------------------------------- numbers
    def number(self, expr: L.NumExpr, env: Env) -> Fraction:
        if isinstance(expr, L.Num):
            value = expr.value
            return value if type(value) is Fraction else Fraction(value)
        if isinstance(expr, L.FuncTerm):
            args = self.args(expr.args, env)
            value = self.ctx.function_values.get((expr.function, args))
            if value is None:
                fail("G106", f"no value for {expr.function}({', '.join(args)}) in the problem",
                     self.span, "give the value in the problem's initial function values")
            return value
        left, right = self.number(expr.left, env), self.number(expr.right, env)
        if expr.op == "+":
            return left + right
        if expr.op == "-":
            return left - right
        if expr.op == "*":
            return left * right
        if right == 0:
            fail("G110", "division by zero in a cost expression", self.span)
        return left / right
