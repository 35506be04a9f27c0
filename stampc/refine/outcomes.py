"""Outcome names for executors: which labelled outcomes (``probabilistic p as NAME:``)
make up each joint outcome of a ground action in a state.

Mirrors ``stampc.ir.grounded.outcome_distribution`` (same enumeration, same merging of
identical outcomes), carrying the labels along; the names never affect planning.
"""

from __future__ import annotations

from fractions import Fraction

from stampc.ir.grounded import GEffect, GroundAction

_Branch = tuple[Fraction, int, int, Fraction, int, tuple[str, ...]]


def outcome_labels(action: GroundAction, state: int) -> tuple[tuple[str, ...], ...]:
    """Labels of each joint outcome, aligned with ``action.outcomes(state)`` (matched on
    the effects' own masks: closing under axioms keeps the order, not the masks)."""
    merged: dict[tuple[int, int, Fraction, int], list[str]] = {}
    for _, a, d, c, u, names in _branches(action.effect, state):
        labels = merged.setdefault((a, d & ~a, c, u), [])
        labels.extend(n for n in names if n not in labels)
    by_key = {key: tuple(names) for key, names in merged.items()}
    return tuple(by_key.get((o.add, o.delete, o.cost - action.base_cost, o.unknown), ())
                 for o in action.basic_outcomes(state))


def _branches(eff: GEffect, state: int) -> list[_Branch]:
    branches: list[_Branch] = [(Fraction(1), eff.add, eff.delete, eff.cost, eff.unknown, ())]
    for cond, sub in eff.whens:
        if cond.holds(state):
            branches = _product(branches, _branches(sub, state))
    for block in eff.blocks:
        options: list[_Branch] = []
        rest = Fraction(1)
        labels = block.labels or (None,) * len(block.outcomes)
        for (p, sub), label in zip(block.outcomes, labels):
            rest -= p
            for q, a, d, c, u, names in _branches(sub, state):
                options.append((p * q, a, d, c, u, ((label,) if label else ()) + names))
        if rest > 0:
            options.append((rest, 0, 0, Fraction(0), 0,
                            (block.rest_label,) if block.rest_label else ()))
        branches = _product(branches, options)
    return branches


def _product(left: list[_Branch], right: list[_Branch]) -> list[_Branch]:
    return [(p * q, a1 | a2, d1 | d2, c1 + c2, u1 | u2, n1 + n2)
            for p, a1, d1, c1, u1, n1 in left for q, a2, d2, c2, u2, n2 in right if p * q > 0]
