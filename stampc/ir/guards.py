"""Static guards: expand quantifiers by joining over static facts.

``(exists (?c) (and (conn ?c ?d) ...))`` only has non-false instances for the ``?c``
with ``conn(?c, ?d)`` true, and ``(forall (?c) (imply (conn ?c ?d) ...))`` only
non-true ones for those. A *guard* of a quantifier body is a static atom over quantified
variables whose falsity makes the body the neutral element of the expansion (false for a
disjunction, true for a conjunction, the empty effect for ``forall`` effects), so only
the bindings that make some guard true need to be expanded: they come from an index
lookup instead of the cross product of the quantified variables' types.
"""

from __future__ import annotations

from itertools import product
from typing import Iterator

from stampc.ir import lifted as L
from stampc.ir.datalog import FactBase
from stampc.ir.ground_context import GroundingContext


def formula_guards(ctx: GroundingContext, f: L.Formula, positive: bool, neutral_true: bool,
                   qvars: frozenset[str]) -> list[L.Atom]:
    """Static atoms whose falsity makes ``f`` (read with ``positive``) ``neutral_true``."""
    if isinstance(f, L.Atom):
        mentions = any(isinstance(t, L.Var) and t.name in qvars for t in f.args)
        return [f] if mentions and ctx.is_static(f.predicate) and positive != neutral_true else []
    if isinstance(f, L.Not):
        return formula_guards(ctx, f.arg, not positive, neutral_true, qvars)
    if isinstance(f, (L.And, L.Or)):
        if (isinstance(f, L.And) == positive) == neutral_true:
            return []
        return [g for a in f.args for g in formula_guards(ctx, a, positive, neutral_true, qvars)]
    if isinstance(f, L.Imply) and positive == neutral_true:
        # positive: (not l) or r -> disjunction, valid when the neutral value is true
        return (formula_guards(ctx, f.left, not positive, neutral_true, qvars)
                + formula_guards(ctx, f.right, positive, neutral_true, qvars))
    return []


def effect_guards(ctx: GroundingContext, e: L.Effect, qvars: frozenset[str]) -> list[L.Atom]:
    """Static atoms whose falsity makes effect ``e`` empty."""
    if isinstance(e, L.When):
        return formula_guards(ctx, e.condition, True, False, qvars)
    if isinstance(e, L.EffAnd) and len(e.effects) == 1:
        return effect_guards(ctx, e.effects[0], qvars)
    if isinstance(e, L.Probabilistic) and len(e.outcomes) == 1:
        return effect_guards(ctx, e.outcomes[0].effect, qvars)
    return []


class GuardedExpander:
    """Enumerates quantifier bindings, through a guard's static facts when possible."""

    def __init__(self, ctx: GroundingContext, static: set[tuple[str, tuple[str, ...]]]):
        self.ctx = ctx
        self.facts = FactBase()
        for pred, args in static:
            self.facts.add(pred, args)
        self.order = {name: i for i, (name, _) in enumerate(ctx.all_objects)}

    def bindings(self, params: tuple[L.Param, ...], env: dict[str, str],
                 guards: list[L.Atom]) -> Iterator[dict[str, str]]:
        names = [p.name for p in params]
        guard = self._best(guards, env, frozenset(names))
        if guard is None:
            if len(names) == 1:  # the common case, on the grounder's hot path
                name = names[0]
                for value in self.ctx.objects_of(params[0].type):
                    inner = dict(env)
                    inner[name] = value
                    yield inner
                return
            domains = [self.ctx.objects_of(p.type) for p in params]
            for values in product(*domains):
                inner = dict(env)
                inner.update(zip(names, values))
                yield inner
            return
        for values in self._from_guard(params, env, guard):
            inner = dict(env)
            inner.update(zip(names, values))
            yield inner

    def _best(self, guards: list[L.Atom], env: dict[str, str],
              qvars: frozenset[str]) -> L.Atom | None:
        best, best_bound = None, -1
        for g in guards:
            bound = sum(1 for t in g.args if not (isinstance(t, L.Var) and t.name in qvars))
            if bound > best_bound:
                best, best_bound = g, bound
        return best

    def _from_guard(self, params: tuple[L.Param, ...], env: dict[str, str],
                    guard: L.Atom) -> list[tuple[str, ...]]:
        qnames = {p.name for p in params}
        positions, key = [], []
        for i, t in enumerate(guard.args):
            if not (isinstance(t, L.Var) and t.name in qnames):
                positions.append(i)
                key.append(env[t.name] if isinstance(t, L.Var) else t.name)
        in_guard = {t.name for t in guard.args if isinstance(t, L.Var) and t.name in qnames}
        free = [p for p in params if p.name not in in_guard]
        found: set[tuple[str, ...]] = set()
        for tup in self.facts.lookup(guard.predicate, tuple(positions), tuple(key)):
            bind: dict[str, str] = {}
            if not self._bind(guard, tup, qnames, bind):
                continue
            if not all(self.ctx.is_of_type(bind[p.name], p.type)
                       for p in params if p.name in bind):
                continue
            for rest in product(*(self.ctx.objects_of(p.type) for p in free)):
                bind.update(zip((p.name for p in free), rest))
                found.add(tuple(bind[p.name] for p in params))
        # object order, like the unguarded expansion, so results never depend on hashing
        return sorted(found, key=lambda vs: tuple(self.order[v] for v in vs))

    @staticmethod
    def _bind(guard: L.Atom, tup: tuple[str, ...], qnames: set[str],
              bind: dict[str, str]) -> bool:
        for t, value in zip(guard.args, tup):
            if isinstance(t, L.Var) and t.name in qnames:
                if bind.setdefault(t.name, value) != value:
                    return False
        return True
