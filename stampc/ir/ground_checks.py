"""Warnings about a grounded model that is valid but probably not what the author meant.

- G201: grounding left no actions (nothing is applicable from the initial state);
- G202: every action costs 0 (expected costs are all 0; no plan is preferred);
- G203: an action may add and delete the same fact in one outcome (IPPC 2006 ``drive``
  does): the warning names the rule applied, once per action schema.

Conflicting effects are resolved by ``CONFLICT_RULES``: ``add-wins`` is PDDL's and
MDPSim's rule (deletes first, then adds); ``delete-wins`` is what mdp-lib's mini-gpt
does. The two give different values on such domains (docs/ir.md).
"""

from __future__ import annotations

from typing import Union

from stampc.diagnostics import Diagnostic, Span, warning
from stampc.ir import lifted as L
from stampc.ir.grounded import GEffect, GroundAction
from stampc.ir.masks import DENSE_BITS, FactSet, from_indices, indices, pack

ADD_WINS = "add-wins"
DELETE_WINS = "delete-wins"
CONFLICT_RULES = (ADD_WINS, DELETE_WINS)
_RULE_WORDS = {ADD_WINS: "the add wins (PDDL / MDPSim rule)",
               DELETE_WINS: "the delete wins (mdp-lib mini-gpt rule)"}


def check_rule(rule: str) -> str:
    if rule not in CONFLICT_RULES:
        raise ValueError(f"conflicting_effects must be one of {', '.join(CONFLICT_RULES)}, "
                         f"got {rule!r}")
    return rule


#: What :func:`effect_conflicts` computes with: int bitsets, or sets of fact indices when
#: the model has fact sets too sparse for ints (both support ``&``, ``|`` and ``^``).
Work = Union[int, frozenset[int]]


def effect_conflicts(effect: GEffect, n_facts: int | None = None) -> FactSet:
    """Facts that some joint outcome of ``effect`` may both add and delete.

    Outcomes of one probabilistic block exclude each other; everything else (the
    top-level literals, each ``when``, each block) may combine. ``when`` conditions are
    not compared, so the answer may include conflicts no state triggers ("may").
    With ``n_facts`` (the model's fact count) at most ``DENSE_BITS`` every fact set is
    an int and the check works on ints; otherwise on sets of fact indices.
    """
    if n_facts is not None and n_facts <= DENSE_BITS:
        return pack(_conflicts(effect, False))
    return from_indices(_conflicts(effect, True))


def _literals(effect: GEffect, as_sets: bool) -> tuple[Work, Work]:
    """The effect's own adds and deletes, in the working type."""
    if as_sets:
        return frozenset(indices(effect.add_facts)), frozenset(indices(effect.delete_facts))
    return effect.add_facts, effect.delete_facts


def _conflicts(effect: GEffect, as_sets: bool) -> Work:
    # hot: SysAdmin p14 walks 3.7 million (shared) sub-effects here, so the int case is
    # inlined
    add, delete = _literals(effect, True) if as_sets else (effect.add_facts,
                                                           effect.delete_facts)
    parts: list[tuple[Work, Work]] = [(add, delete)]
    conflicts = add & delete
    for _, sub in effect.whens:
        conflicts = conflicts | _conflicts(sub, as_sets)
        parts.append(_reach(sub, as_sets))
    for block in effect.blocks:
        adds = deletes = type(add)()  # empty, of the working type
        for _, sub in block.outcomes:
            conflicts = conflicts | _conflicts(sub, as_sets)
            a, d = _reach(sub, as_sets)
            adds, deletes = adds | a, deletes | d
        parts.append((adds, deletes))
    return conflicts | _across_parts(parts)


def _across_parts(parts: list[tuple[Work, Work]]) -> Work:
    """Facts one part adds and another part deletes, in linear time (an action may have
    thousands of ``when`` parts): a fact added (or deleted) by two or more parts
    conflicts with any deleter (adder); one added and deleted once conflicts unless the
    same part does both."""
    empty = type(parts[0][0])()
    adds_any = deletes_any = adds_twice = deletes_twice = same_part = empty
    for adds, deletes in parts:
        adds_twice = adds_twice | (adds & adds_any)
        deletes_twice = deletes_twice | (deletes & deletes_any)
        adds_any = adds_any | adds
        deletes_any = deletes_any | deletes
        same_part = same_part | (adds & deletes)
    both = adds_any & deletes_any
    return (adds_twice & deletes_any) | (deletes_twice & adds_any) | (both ^ (both & same_part))


def _reach(effect: GEffect, as_sets: bool) -> tuple[Work, Work]:
    """Every fact ``effect`` may add, and every fact it may delete."""
    adds, deletes = _literals(effect, True) if as_sets else (effect.add_facts,
                                                             effect.delete_facts)
    for _, sub in effect.whens:
        a, d = _reach(sub, as_sets)
        adds, deletes = adds | a, deletes | d
    for block in effect.blocks:
        for _, sub in block.outcomes:
            a, d = _reach(sub, as_sets)
            adds, deletes = adds | a, deletes | d
    return adds, deletes


def _costs_something(effect: GEffect) -> bool:
    return bool(effect.cost) or any(_costs_something(sub) for _, sub in effect.whens) or any(
        _costs_something(sub) for block in effect.blocks for _, sub in block.outcomes)


def grounding_warnings(model: L.Model, actions: tuple[GroundAction, ...],
                       conflicts: dict[int, tuple[GroundAction, FactSet]], facts: tuple,
                       rule: str) -> list[Diagnostic]:
    """G201/G202 for the whole model, G203 per action schema in ``conflicts`` (schema →
    first ground action with a conflict and its conflict mask)."""
    where = model.problem.span or model.domain.span or Span.point("<model>")
    out: list[Diagnostic] = []
    if not actions:
        out.append(warning("G201", "grounding left no actions: no action is applicable in "
                           "any state reachable from the initial state", where,
                           hint="check the preconditions against the initial facts and "
                                "the object types"))
    elif all(a.base_cost == 0 and not _costs_something(a.effect) for a in actions):
        out.append(warning("G202", "every action costs 0: every policy has expected cost 0, "
                           "so solvers prefer no plan over another", model.domain.span or where,
                           hint="give actions costs ((decrease (reward) k) in PPDDL, `cost` "
                                "in stamp) or solve with --unit-cost"))
    for schema, (action, mask) in sorted(conflicts.items()):
        lifted = model.domain.actions[schema] if 0 <= schema < len(model.domain.actions) else None
        fact = facts[indices(mask)[0]]
        other = DELETE_WINS if rule == ADD_WINS else ADD_WINS
        out.append(warning(
            "G203", f"action '{action.name}' may add and delete the same fact in one outcome "
            f"(e.g. {fact} in {action.label}); {_RULE_WORDS[rule]}",
            (lifted.span if lifted is not None else None) or where,
            hint=f"--conflicting-effects {other} (API: conflicting_effects='{other}') "
                 "applies the other rule"))
    return out
