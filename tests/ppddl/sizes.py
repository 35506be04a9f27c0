"""A worst-case size estimate of grounding a lifted model (used to bound test time)."""

from __future__ import annotations

from stampc.ir.lifted import (
    And, EffAnd, EffForall, Effect, Exists, Forall, Formula, Imply, Model, Not, Or,
    Param, Probabilistic, When,
)


def _counts(model: Model) -> dict[str, int]:
    d, p = model.domain, model.problem
    parents = {t.name: t.parent for t in d.types}
    counts: dict[str, int] = {}
    for o in d.constants + p.objects:
        t: str | None = o.type
        seen = set()
        while t is not None and t not in seen:
            seen.add(t)
            counts[t] = counts.get(t, 0) + 1
            t = parents.get(t)
        if "object" not in seen:
            counts["object"] = counts.get("object", 0) + 1
    return counts


def _product(params: tuple[Param, ...], counts: dict[str, int]) -> int:
    n = 1
    for q in params:
        n *= max(1, counts.get(q.type, 0))
    return n


def _formula_size(f: Formula, counts) -> int:
    if isinstance(f, (Forall, Exists)):
        return _product(f.params, counts) * _formula_size(f.body, counts)
    if isinstance(f, Not):
        return _formula_size(f.arg, counts)
    if isinstance(f, (And, Or)):
        return sum(_formula_size(a, counts) for a in f.args) or 1
    if isinstance(f, Imply):
        return _formula_size(f.left, counts) + _formula_size(f.right, counts)
    return 1


def _effect_size(e: Effect, counts) -> int:
    if isinstance(e, EffAnd):
        return sum(_effect_size(x, counts) for x in e.effects) or 1
    if isinstance(e, When):
        return _formula_size(e.condition, counts) + _effect_size(e.effect, counts)
    if isinstance(e, EffForall):
        return _product(e.params, counts) * _effect_size(e.effect, counts)
    if isinstance(e, Probabilistic):
        return sum(_effect_size(o.effect, counts) for o in e.outcomes) or 1
    return 1


def grounding_estimate(model: Model) -> int:
    """Sum over actions of (#ground instances x size of one instantiated body)."""
    counts = _counts(model)
    total = 0
    for a in model.domain.actions:
        body = _formula_size(a.precondition, counts) + _effect_size(a.effect, counts)
        total += _product(a.params, counts) * body
    return total
