"""Float enumeration of state-dependent (conditional) effects for the solvers' hot path.

``GroundAction.outcomes(state)`` enumerates joint outcomes exactly, with ``Fraction``
arithmetic; on domains whose actions carry ``when`` effects (boxworld, schedule) that is
called for every (state, action) pair and dominates solve time. Solvers only need the
distribution over next states, so they use this float version of the same semantics
(conditions read in the old state, deletes before adds, a probabilistic block's missing
mass is a no-op); the exact enumeration stays the reference for policy trees.
"""

from __future__ import annotations

from stampc.ir.grounded import GEffect, GroundCondition
from stampc.ir.masks import as_int

#: (add, delete, cost, whens, blocks); whens are ((pos, neg, condition or None), sub-effect)
#: with the condition kept when it has a remainder (or sparse fact sets) to evaluate;
#: blocks are (no-op mass, ((p, sub-effect), ...)).
FloatEffect = tuple


def compile_effect(effect: GEffect, unit_cost: bool) -> FloatEffect:
    whens = tuple((condition_check(cond), compile_effect(sub, unit_cost))
                  for cond, sub in effect.whens if not cond.never)
    blocks = tuple((float(1 - sum(p for p, _ in block.outcomes)),
                    tuple((float(p), compile_effect(sub, unit_cost)) for p, sub in block.outcomes))
                   for block in effect.blocks)
    return (effect.add, effect.delete, 0.0 if unit_cost else float(effect.cost), whens, blocks)


#: Products longer than this are merged by (adds, deletes, cost).
_MERGE_ABOVE = 16


def _product(left: list, right: list) -> list:
    out = [(p * q, a1 | a2, d1 | d2, c1 + c2)
           for p, a1, d1, c1 in left for q, a2, d2, c2 in right if p * q > 0]
    return _merge(out) if len(out) > _MERGE_ABOVE else out


def _merge(items: list) -> list:
    """Branches with the same adds, deletes and cost lead to the same next state: one
    branch with their summed probability. Keeps independent blocks from multiplying
    out (sysadmin p04: 2 blocks x 8 computers = 4^8 = 65,536 branches per action, but
    only 2^8 distinct effects)."""
    acc: dict[tuple[int, int, float], float] = {}
    for p, a, d, c in items:
        key = (a, d, c)
        acc[key] = acc.get(key, 0.0) + p
    return [(p, a, d, c) for (a, d, c), p in acc.items()]


def branches(effect: FloatEffect, state: int) -> list[tuple[float, int, int, float]]:
    """Joint outcomes (probability, adds, deletes, cost) of ``effect`` in ``state``."""
    add, delete, cost, whens, blocks = effect
    result = [(1.0, add, delete, cost)]
    for cond, sub in whens:
        if _holds(cond, state):
            result = _product(result, branches(sub, state))
    for rest, outcomes in blocks:
        options = [(p * q, a, d, c) for p, sub in outcomes for q, a, d, c in branches(sub, state)]
        if rest > 0:
            options.append((rest, 0, 0, 0.0))
        result = _product(result, options)
    return result


def sample(effect: FloatEffect, state: int, rng) -> tuple[int, int, float]:
    """One joint outcome (adds, deletes, cost) of ``effect`` in ``state``, drawn block by
    block with ``rng.random()``: linear in the effect's size where :func:`branches`
    would enumerate up to 2^blocks outcomes (SysAdmin p06: 2^16 per state)."""
    add, delete, cost, whens, blocks = effect
    for cond, sub in whens:
        if _holds(cond, state):
            a, d, c = sample(sub, state, rng)
            add, delete, cost = add | a, delete | d, cost + c
    for _, outcomes in blocks:
        r, acc = rng.random(), 0.0
        for p, sub in outcomes:
            acc += p
            if r < acc:
                a, d, c = sample(sub, state, rng)
                add, delete, cost = add | a, delete | d, cost + c
                break
    return add, delete, cost


def condition_check(cond: GroundCondition, dense: bool = False
                    ) -> tuple[int, int, GroundCondition | None]:
    """(pos, neg, condition to call or None): ``state`` satisfies ``cond`` iff
    ``state & pos == pos``, ``not state & neg`` and the condition, if any, holds.
    ``dense``: sparse fact sets become ints too (the caller judged their size fine)."""
    pos, neg = cond.pos_facts, cond.neg_facts
    if cond.never:
        return 0, 0, cond  # its ``holds`` says no
    if pos.__class__ is int and neg.__class__ is int:
        return pos, neg, cond if cond.rest else None
    if not dense:
        return 0, 0, cond  # sparse: an int per condition would be as large as the model
    # the remainder alone: ``holds`` would rebuild the sparse sets' ints on every call
    return as_int(pos), as_int(neg), GroundCondition(0, 0, cond.rest) if cond.rest else None


def _holds(check: tuple[int, int, GroundCondition | None], state: int) -> bool:
    pos, neg, cond = check
    if (state & pos) != pos or (state & neg):
        return False
    return cond is None or cond.holds(state)
