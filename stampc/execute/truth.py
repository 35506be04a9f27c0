"""The world's truth model: what really happens when an action runs.

Execution samples each action's outcome here, never from the probabilities stored in the
policy. By default the truth is the model itself; a scene (``meta.truth``) or
``stampc execute --truth KEY=VALUE`` sets other true probabilities for labelled
outcomes (``probabilistic p as NAME: ...``):

* ``NAME=P`` — every outcome labelled ``NAME``, in any action;
* ``ACTION.NAME=P`` — only in action schema ``ACTION`` (wins over ``NAME=P``).

Inside a probabilistic block the overridden outcomes get their new probabilities and the
block's other outcomes (and its implicit "nothing happens" rest) share what is left, in
the model's proportions; a block whose fixed outcomes exceed 1 is an error (T002), an
unknown label or action too (T001). The true distribution of a ground action in a state
comes from grounding this re-weighted model (same semantics as planning).

A sampled outcome the policy has no edge for (the model gave it probability 0, or the
refinement did not keep it) is *unplanned*: the run ends on an unrefined branch.
"""

from __future__ import annotations

import random
from dataclasses import dataclass, replace
from fractions import Fraction
from typing import Any, Iterable, Mapping

from stampc.diagnostics import Span, StampcError, error
from stampc.ir import lifted as L
from stampc.ir.grounded import GroundModel, bits

CODES = {"T001": "a truth key names no labelled outcome or action",
         "T002": "true probabilities out of range"}

OutcomeKey = tuple[frozenset[str], frozenset[str]]


# ------------------------------------------------------------------ overrides
def parse_overrides(items: Mapping[str, Any] | Iterable[str], where: Span) -> dict[str, Fraction]:
    """``{"[ACTION.]NAME": probability}`` from a mapping or ``KEY=VALUE`` strings."""
    pairs = items.items() if isinstance(items, Mapping) else (_split(s, where) for s in items)
    out: dict[str, Fraction] = {}
    for key, value in pairs:
        try:
            p = Fraction(str(value)) if not isinstance(value, bool) else None
        except (ValueError, ZeroDivisionError):
            p = None
        if p is None or not 0 <= p <= 1:
            raise StampcError([error("T002", f"truth {key!r}: {value!r} is not a probability "
                                     "in [0, 1]", where, hint="write e.g. crushed=0.9 or 9/10")])
        out[str(key)] = p
    return out


def _split(text: str, where: Span) -> tuple[str, str]:
    key, sep, value = text.partition("=")
    if not sep or not key.strip():
        raise StampcError([error("T001", f"truth {text!r} is not KEY=VALUE", where,
                                 hint="e.g. --truth crushed=0.9 or --truth pick.crushed=0.9")])
    return key.strip(), value.strip()


def true_lifted_model(model: L.Model, overrides: Mapping[str, Fraction], where: Span) -> L.Model:
    """``model`` with the overridden outcome probabilities (T001/T002 on bad keys)."""
    labels = {(a.name, o.label) for a in model.domain.actions for o in _outcomes(a.effect)
              if o.label}
    actions = {a.name for a in model.domain.actions}
    for key in overrides:
        action, _, name = key.rpartition(".")
        if (action and action not in actions) or not any(
                lab == name and (not action or act == action) for act, lab in labels):
            known = ", ".join(sorted({lab for _, lab in labels})) or "none (no `as NAME` labels)"
            raise StampcError([error("T001", f"truth key {key!r} names no labelled outcome"
                                     + (f" of action {action!r}" if action else ""), where,
                                     hint=f"outcome labels of this domain: {known}")])
    if not overrides:
        return model
    new_actions = tuple(replace(a, effect=_reweighted(a.effect, a.name, overrides, where))
                        for a in model.domain.actions)
    return replace(model, domain=replace(model.domain, actions=new_actions))


def _outcomes(effect: L.Effect) -> Iterable[L.Outcome]:
    if isinstance(effect, L.Probabilistic):
        for o in effect.outcomes:
            yield o
            yield from _outcomes(o.effect)
    elif isinstance(effect, L.EffAnd):
        for e in effect.effects:
            yield from _outcomes(e)
    elif isinstance(effect, (L.When, L.EffForall)):
        yield from _outcomes(effect.effect)


def _reweighted(effect: L.Effect, action: str, overrides: Mapping[str, Fraction],
                where: Span) -> L.Effect:
    def again(e: L.Effect) -> L.Effect:
        return _reweighted(e, action, overrides, where)

    if isinstance(effect, L.EffAnd):
        return L.EffAnd(tuple(again(e) for e in effect.effects))
    if isinstance(effect, (L.When, L.EffForall)):
        return replace(effect, effect=again(effect.effect))
    if not isinstance(effect, L.Probabilistic):
        return effect
    fixed = {i: _override(o.label, action, overrides) for i, o in enumerate(effect.outcomes)}
    fixed = {i: p for i, p in fixed.items() if p is not None}
    total_fixed = sum(fixed.values(), Fraction(0))
    if total_fixed > 1:
        raise StampcError([error("T002", f"true probabilities of one block of action "
                                 f"{action!r} sum to {float(total_fixed):g} > 1", where)])
    free = [i for i in range(len(effect.outcomes)) if i not in fixed]
    model_free = sum((effect.outcomes[i].probability for i in free), Fraction(0))
    model_rest = 1 - sum((o.probability for o in effect.outcomes), Fraction(0))
    share = (1 - total_fixed) / (model_free + model_rest) if model_free + model_rest else 0
    outcomes = tuple(L.Outcome(fixed[i] if i in fixed else o.probability * share,
                               again(o.effect), o.label)
                     for i, o in enumerate(effect.outcomes))
    return L.Probabilistic(outcomes)


def _override(label: str | None, action: str, overrides: Mapping[str, Fraction]):
    if label is None:
        return None
    return overrides.get(f"{action}.{label}", overrides.get(label))


# ------------------------------------------------------------------ the truth model
@dataclass(frozen=True)
class TrueOutcome:
    probability: float
    key: OutcomeKey
    #: index of the policy outcome with the same effects, None if the policy has none
    planned: int | None


class TruthModel:
    """Samples outcomes of the policy's ground actions from the true distribution."""

    def __init__(self, truth: GroundModel, overrides: Mapping[str, Fraction]):
        self.truth = truth
        self.overrides = dict(overrides)
        self._facts = {str(f): i for i, f in enumerate(truth.facts)}
        self._actions = {a.label: a for a in truth.actions}
        self._cache: dict[int, tuple[TrueOutcome, ...]] = {}

    def distribution(self, node: Mapping[str, Any]) -> tuple[TrueOutcome, ...]:
        """The true outcomes of ``node``'s action in its abstract state."""
        uid = node["id"]
        if uid not in self._cache:
            self._cache[uid] = self._distribution(node)
        return self._cache[uid]

    def _distribution(self, node: Mapping[str, Any]) -> tuple[TrueOutcome, ...]:
        action = self._actions.get(node["action"])
        if action is None:  # unreachable under the truth: cannot happen on a true path
            raise KeyError(f"action {node['action']} does not exist under the truth model")
        state = 0
        for fact in node["state"]:
            if fact in self._facts:
                state |= 1 << self._facts[fact]
        state = self.truth.axioms.close(state)  # derived facts as the truth model derives them
        planned = {planned_key(o): i for i, o in enumerate(node["outcomes"])}
        out = []
        for s in action.outcomes(state):
            adds = self._names(s.add)
            # a policy lists the deletes of facts true before (refine/export.py)
            key = (adds, self._names(s.delete & state & ~s.add))
            if key not in planned:  # one written before that listed every delete
                every = (adds, self._names(s.delete & ~s.add))
                key = every if every in planned else key
            out.append(TrueOutcome(float(s.probability), key, planned.get(key)))
        return tuple(out)

    def _names(self, mask: int) -> frozenset[str]:
        return frozenset(str(self.truth.facts[b]) for b in bits(mask))

    def sample(self, node: Mapping[str, Any], rng: random.Random) -> TrueOutcome:
        outcomes = self.distribution(node)
        r = rng.random() * sum(o.probability for o in outcomes)
        for o in outcomes:
            r -= o.probability
            if r < 0:
                return o
        return outcomes[-1]


def planned_key(outcome: Mapping[str, Any]) -> OutcomeKey:
    def names(lits):
        return frozenset(f"{lit['predicate']}({', '.join(lit['args'])})" for lit in lits)
    return names(outcome["adds"]), names(outcome["deletes"])


def build_truth(model: L.Model, overrides: Mapping[str, Fraction], where: Span) -> TruthModel:
    from stampc.api import ground

    return TruthModel(ground(true_lifted_model(model, overrides, where)), overrides)


def predicted_success(policy: Mapping[str, Any], truth: TruthModel,
                      tolerance: float = 1e-12, max_sweeps: int = 100_000) -> float:
    """Probability that a run of ``policy`` under ``truth`` ends at a goal leaf (every
    goal leaf counted as reached; unplanned outcomes and unrefined nodes count 0).

    Policy graphs may hold cycles (a retried action, a slip that changes nothing), so
    this is a fixed point, not a tree sum: sweeps from below until nothing moves."""
    nodes = {n["id"]: n for n in policy["nodes"]}
    value = {uid: 1.0 if n["leaf"] == "goal" else 0.0 for uid, n in nodes.items()}
    inner = [(uid, [(o.probability, n["outcomes"][o.planned]["child"])
                    for o in truth.distribution(n) if o.planned is not None])
             for uid, n in nodes.items() if n["leaf"] is None and n["refined"]]
    for _ in range(max_sweeps):
        change = 0.0
        for uid, branches in inner:
            new = sum(p * value[child] for p, child in branches)
            change = max(change, abs(new - value[uid]))
            value[uid] = new
        if change <= tolerance:
            break
    return value[policy["root"]]
