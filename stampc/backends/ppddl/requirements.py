"""The PPDDL requirement flags a lifted model actually needs (computed, never copied)."""

from __future__ import annotations

from stampc.ir.lifted import (
    And, Atom, CostEffect, EffAnd, EffForall, Effect, Equals, Exists, Forall, Formula,
    Imply, Model, Not, Or, Probabilistic, Truth, When,
)

#: Emission order of the flags.
ORDER = (
    ":strips", ":typing", ":equality", ":negative-preconditions",
    ":disjunctive-preconditions", ":existential-preconditions", ":universal-preconditions",
    ":conditional-effects", ":probabilistic-effects", ":rewards", ":fluents",
    ":derived-predicates",
)


def formula_flags(f: Formula) -> set[str]:
    if isinstance(f, Atom):
        return set()
    if isinstance(f, Truth):  # false is written as the empty disjunction (or)
        return set() if f.value else {":disjunctive-preconditions"}
    if isinstance(f, Equals):
        return {":equality"}
    if isinstance(f, Not):
        if isinstance(f.arg, Atom):
            return {":negative-preconditions"}
        if isinstance(f.arg, Equals):
            return {":equality"}  # (not (= a b)) is conventionally covered by :equality
        return {":disjunctive-preconditions"} | formula_flags(f.arg)
    if isinstance(f, And):
        return set().union(*(formula_flags(a) for a in f.args))
    if isinstance(f, Or):
        return {":disjunctive-preconditions"}.union(*(formula_flags(a) for a in f.args))
    if isinstance(f, Imply):
        return {":disjunctive-preconditions"} | formula_flags(f.left) | formula_flags(f.right)
    if isinstance(f, Forall):
        return {":universal-preconditions"} | formula_flags(f.body)
    assert isinstance(f, Exists), f
    return {":existential-preconditions"} | formula_flags(f.body)


def effect_flags(e: Effect) -> set[str]:
    if isinstance(e, EffAnd):
        return set().union(*(effect_flags(x) for x in e.effects))
    if isinstance(e, When):
        return {":conditional-effects"} | formula_flags(e.condition) | effect_flags(e.effect)
    if isinstance(e, EffForall):
        return {":conditional-effects"} | effect_flags(e.effect)
    if isinstance(e, Probabilistic):
        return {":probabilistic-effects"}.union(*(effect_flags(o.effect) for o in e.outcomes))
    if isinstance(e, CostEffect):
        return {":rewards"}
    return set()  # Lit, Unknown (emitted as a literal)


def required_flags(model: Model, *, explicit_costs: bool) -> tuple[str, ...]:
    """Flags for the constructs ``model`` uses; ``explicit_costs`` when the emitter adds
    base-cost ``(decrease (reward) k)`` conjuncts."""
    d, p = model.domain, model.problem
    flags: set[str] = set()
    if any(t.parent is not None for t in d.types):
        flags.add(":typing")
    for a in d.actions:
        flags |= formula_flags(a.precondition) | effect_flags(a.effect)
    flags |= formula_flags(p.goal)
    for ax in d.axioms:
        flags |= formula_flags(ax.body) | {":derived-predicates"}
    if explicit_costs or p.goal_reward is not None or p.metric is not None:
        flags.add(":rewards")
    if d.functions:
        flags.add(":fluents")
    if not flags:
        flags.add(":strips")
    return tuple(f for f in ORDER if f in flags)
