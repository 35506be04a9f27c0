"""Ground effects and action instances (see docs/ir.md, "Grounding semantics").

Effects stay factored: ``when`` conditions that simplify to true are inlined and false
ones dropped, ``forall`` effects expand over typed objects, probabilistic blocks keep
their outcomes (empty outcomes are dropped: the leftover mass is the implicit no-op),
``?`` effects fold the predicate's optimistic value into add/delete and mark the fact in
``GEffect.unknown``, and cost effects are evaluated with the problem's function values.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from stampc.ir import lifted as L
from stampc.ir.ground_context import GroundingContext, located
from stampc.ir.grounded import EMPTY_EFFECT, GEffect, GProb, GroundCondition, \
    GroundGeneratorUse
from stampc.ir.masks import single, union_all
from stampc.ir.simplify import Env, Simplifier


_ZERO = EMPTY_EFFECT.cost  # the default cost object, shared by most effects


def is_empty(e: GEffect) -> bool:
    return not (e.add_facts or e.delete_facts or e.unknown_facts or e.cost or e.whens
                or e.blocks)


def merge(parts: list[GEffect]) -> GEffect:
    """Conjunction of effects (adds/deletes united, costs summed, sub-effects kept)."""
    # Runs once per ground forall/and, over up to |objects| parts: kept to flat loops.
    # inlined is_empty, cheapest tests first (a Fraction's truth value is a Python call)
    parts = [p for p in parts if p.blocks or p.whens or p.add_facts or p.delete_facts
             or p.unknown_facts or (p.cost is not _ZERO and p.cost)]
    if not parts:
        return EMPTY_EFFECT
    if len(parts) == 1:
        return parts[0]
    add = delete = unknown = 0
    sparse: list[GEffect] = []  # parts with a Sparse fact set: united by index below
    costs: list[Fraction] = []
    whens: list = []
    blocks: list = []
    for p in parts:
        a, d, u = p.add_facts, p.delete_facts, p.unknown_facts
        if a or d or u:
            if a.__class__ is int and d.__class__ is int and u.__class__ is int:
                add |= a
                delete |= d
                unknown |= u
            else:
                sparse.append(p)
        if p.cost is not _ZERO and p.cost:  # Fraction arithmetic is slow; most cost nothing
            costs.append(p.cost)
        if p.whens:
            whens += p.whens
        if p.blocks:
            blocks += p.blocks
    if sparse:
        add = union_all([add, *(p.add_facts for p in sparse)])
        delete = union_all([delete, *(p.delete_facts for p in sparse)])
        unknown = union_all([unknown, *(p.unknown_facts for p in sparse)])
    cost = sum(costs, Fraction(0)) if costs else Fraction(0)
    return GEffect(add, delete, cost, unknown, tuple(whens), tuple(blocks))


class EffectGrounder:
    def __init__(self, simp: Simplifier):
        self.simp = simp
        self.ctx = simp.ctx
        self.memo: dict[tuple, GEffect] = {}

    def effect(self, e: L.Effect, env: Env) -> GEffect:
        if isinstance(e, L.Lit):
            return self._literal(e, env)
        if isinstance(e, L.CostEffect):
            return GEffect(cost=self.simp.number(e.amount, env))
        if isinstance(e, L.Unknown):
            return self._unknown(e, env)
        key = self.simp.scopes.memo_key(e, env)
        cached = self.memo.get(key)
        if cached is None:
            cached = self.memo[key] = self._compound(e, env)
        return cached

    def root(self, e: L.Effect, env: Env) -> GEffect:
        """An action's whole effect: unique per ground action, so never memoised."""
        if isinstance(e, L.EffAnd):
            return merge([self.effect(sub, env) for sub in e.effects])
        return self.effect(e, env)

    def _compound(self, e: L.Effect, env: Env) -> GEffect:
        if isinstance(e, L.EffAnd):
            return merge([self.effect(sub, env) for sub in e.effects])
        if isinstance(e, L.When):
            cond = self.simp.condition(e.condition, env)
            if cond.never:
                return EMPTY_EFFECT
            sub = self.effect(e.effect, env)
            if is_empty(sub) or cond.is_trivial:
                return sub
            return GEffect(whens=((cond, sub),))
        if isinstance(e, L.EffForall):
            return self._forall(e, env)
        if isinstance(e, L.Probabilistic):
            return self._probabilistic(e, env)
        raise TypeError(f"not an effect: {e!r}")

    def _forall(self, e: L.EffForall, env: Env) -> GEffect:
        body = e.effect
        bindings = self.simp.effect_bindings(e, env)
        if isinstance(body, (L.Lit, L.CostEffect, L.Unknown)):
            return merge([self.effect(body, inner) for inner in bindings])
        # inlined self.effect(body, inner): this loop is the grounder's hot spot
        key_of = self.simp.scopes.keyer(body)
        memo = self.memo
        parts = []
        for inner in bindings:
            key = key_of(inner)
            part = memo.get(key)
            if part is None:
                part = memo[key] = self._compound(body, inner)
            parts.append(part)
        return merge(parts)

    def _probabilistic(self, e: L.Probabilistic, env: Env) -> GEffect:
        outcomes: list[tuple[Fraction, GEffect]] = []
        labels: list[str | None] = []
        rest: list[str] = []  # labels of outcomes without effect (part of the no-op rest)
        for o in e.outcomes:
            if o.probability > 0:
                sub = self.effect(o.effect, env)
                if not is_empty(sub):
                    outcomes.append((Fraction(o.probability), sub))
                    labels.append(o.label)
                elif o.label:
                    rest.append(o.label)
        if not outcomes:
            return EMPTY_EFFECT
        if len(outcomes) == 1 and outcomes[0][0] == 1:
            return outcomes[0][1]
        return GEffect(blocks=(GProb(tuple(outcomes), tuple(labels), "|".join(rest) or None),))

    def _literal(self, e: L.Lit, env: Env) -> GEffect:
        key = (e.atom.predicate, self.simp.args(e.atom.args, env))
        if e.positive:
            i = self.simp.facts.require(key)
            return EMPTY_EFFECT if i is None else GEffect(add=single(i))
        i = self.simp.facts.lookup(key)
        # deleting a fact that is never true is a no-op
        return EMPTY_EFFECT if i is None else GEffect(delete=single(i))

    def _unknown(self, e: L.Unknown, env: Env) -> GEffect:
        key = (e.atom.predicate, self.simp.args(e.atom.args, env))
        i = self.simp.facts.require(key)
        if i is None:
            return EMPTY_EFFECT
        bit = single(i)
        if self.ctx.predicates[e.atom.predicate].optimistic:
            return GEffect(add=bit, unknown=bit)
        return GEffect(delete=bit, unknown=bit)


@dataclass(frozen=True)
class ActionInstance:
    """A ground action before its final index is known."""

    name: str
    args: tuple[str, ...]
    schema: int
    precondition: GroundCondition
    effect: GEffect
    base_cost: Fraction
    generated: tuple[GroundGeneratorUse, ...]


def instantiate(ctx: GroundingContext, simp: Simplifier, effects: EffectGrounder,
                schema: int, binding: tuple[str, ...]) -> ActionInstance | None:
    """Ground one reachable binding; ``None`` when its precondition is statically false."""
    action = ctx.actions[schema]
    env = dict(zip((p.name for p in action.params), binding))
    simp.span = located(action.span, ctx.model)
    pre = simp.condition(action.precondition, env)
    if pre.never:
        return None
    effect = effects.root(action.effect, env)
    base = simp.number(action.cost, env) if action.cost is not None else ctx.costs.default_cost
    generated = tuple(GroundGeneratorUse(use.generator, tuple(env[a] for a in use.inputs),
                                         tuple(env[o] for o in use.outputs))
                      for use in action.generated)
    return ActionInstance(action.name, binding, schema, pre, effect, base, generated)
