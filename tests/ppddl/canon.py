"""Canonical forms for comparing PPDDL round trips.

Lifted: a model is compared after (1) applying the emitter's name mangling to the
original, (2) alpha-renaming every action's and the goal's variables to v0, v1, ... in
order of first appearance, (3) dropping the requirement flags (the emitter recomputes
them from the constructs used, so they legitimately differ from what a file declared)
and (4) normalising the metric: costs are emitted as rewards, so
``minimize (total-cost)`` and ``maximize (reward)`` mean the same.

Grounded: facts and ground actions are compared by name (never by index): the
precondition, base cost and factored effect tree are translated to sets of ground
atoms, and, when the enumeration is small, the full outcome distribution in the
initial state is compared with ``outcome_distribution``.
"""

from __future__ import annotations

from dataclasses import replace
from fractions import Fraction

from stampc.backends.ppddl.mangle import mangle_model
from stampc.backends.ppddl.rename import Renaming, effect_vars, formula_vars
from stampc.ir.grounded import (
    GAnd, GEffect, GLit, GOr, GroundAction, GroundCondition, GroundModel,
    outcome_distribution,
)
from stampc.ir.lifted import Action, Model

REWARD_METRIC = "maximize (reward)"


def _alpha(names: list[str]):
    table: dict[str, str] = {}
    for n in names:
        table.setdefault(n, f"v{len(table)}")
    return lambda n: table.get(n, n)


def _canonical_action(a: Action) -> Action:
    names = [p.name for p in a.params] + formula_vars(a.precondition) + effect_vars(a.effect)
    r = Renaming(var=_alpha(names))
    return replace(a, params=r.params(a.params), precondition=r.formula(a.precondition),
                   effect=r.effect(a.effect), cost=None if a.cost is None else r.num(a.cost))


def canonical_lifted(model: Model, *, mangle: bool = True) -> Model:
    if mangle:
        model = mangle_model(model).model
    d, p = model.domain, model.problem
    domain = replace(d, requirements=(), actions=tuple(_canonical_action(a) for a in d.actions))
    metric = REWARD_METRIC if p.metric == "minimize (total-cost)" else p.metric
    goal = Renaming(var=_alpha(formula_vars(p.goal))).formula(p.goal)
    return Model(domain, replace(p, metric=metric, goal=goal))


# ----------------------------------------------------------------- grounded
def _facts(gm: GroundModel, mask: int) -> frozenset:
    return frozenset(f for i, f in enumerate(gm.facts) if (mask >> i) & 1)


def _gformula(gm: GroundModel, f):
    if isinstance(f, GLit):
        return ("lit", gm.facts[f.fact], f.positive)
    kind = "and" if isinstance(f, GAnd) else "or"
    assert isinstance(f, (GAnd, GOr))
    return (kind, tuple(_gformula(gm, x) for x in f.args))


def canonical_condition(gm: GroundModel, c: GroundCondition):
    return (_facts(gm, c.pos), _facts(gm, c.neg),
            tuple(_gformula(gm, f) for f in c.rest), c.never)


def canonical_effect(gm: GroundModel, e: GEffect):
    return (
        _facts(gm, e.add), _facts(gm, e.delete), e.cost, _facts(gm, e.unknown),
        tuple((canonical_condition(gm, c), canonical_effect(gm, sub)) for c, sub in e.whens),
        tuple(tuple((p, canonical_effect(gm, sub)) for p, sub in block.outcomes)
              for block in e.blocks),
    )


def _enumeration_size(e: GEffect) -> int:
    size = 1
    for _, sub in e.whens:
        size *= _enumeration_size(sub)
    for block in e.blocks:
        size *= sum(_enumeration_size(sub) for _, sub in block.outcomes) + 1
        if size > 4096:
            return size
    return size


def canonical_distribution(gm: GroundModel, a: GroundAction, state: int):
    """The joint outcome distribution in ``state`` as a multiset keyed by facts."""
    out: dict = {}
    for s in outcome_distribution(a, state):
        key = (_facts(gm, s.add), _facts(gm, s.delete), s.cost, _facts(gm, s.unknown))
        out[key] = out.get(key, Fraction(0)) + s.probability
    return out


def canonical_ground(gm: GroundModel, *, max_outcomes: int = 4096):
    actions = {}
    for a in gm.actions:
        entry = (canonical_condition(gm, a.precondition), a.base_cost,
                 canonical_effect(gm, a.effect))
        if _enumeration_size(a.effect) <= max_outcomes:
            entry += (canonical_distribution(gm, a, gm.init),)
        actions[(a.name, a.args)] = entry
    return {
        "facts": frozenset(gm.facts),
        "static": frozenset(gm.static_facts),
        "init": _facts(gm, gm.init),
        "goal": canonical_condition(gm, gm.goal),
        "objects": frozenset(gm.objects),
        "has_costs": gm.has_costs,
        "actions": actions,
    }
