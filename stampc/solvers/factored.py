"""Product-form transitions over the few facts a model can change, vectorised with numpy.

Some models have a small state space but an exploding successor enumeration: SysAdmin's
``reboot`` has two independent probabilistic blocks per computer, so 2^n distinct next
states per action (n = 12: 4,096 per expansion). When every fact that actions change is
one of at most :data:`MAX_BITS` *varying* facts, the states are the 2^n assignments of
those facts (the others keep their initial values), and when every probabilistic block
touches a single fact, an action's next state is a product of independent per-fact
distributions: ``P(s' | s, a) = Π_j P(s'_j | s, a)``. Then each action is fully described
by the matrix ``q[s, j] = P(s'_j = 1 | s, a)``, computed here for all states at once from
the grounded effect tree (conditions read in the old state; a fact both added and deleted
ends up true, or false with ``delete_wins``, as in ``outcome_distribution``).

:func:`compile_factored` builds that description, or says why the model does not fit.
``dense.py`` runs value iteration on it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from stampc.ir.grounded import GAnd, GEffect, GFormula, GLit, GroundCondition, GroundModel
from stampc.ir.masks import indices

#: At most this many varying facts: the compilation holds a few float arrays of 2^n per
#: varying fact and action (2^18 states: 2 MB each).
MAX_BITS = 18


class NotFactored(Exception):
    """The model's structure does not fit the product form (message: why)."""


@dataclass(frozen=True)
class FactoredAction:
    """One ground action on the states where it applies (goal states excluded)."""
    index: int               # ground action index in the model
    rows: np.ndarray         # state indices where the action applies
    q: np.ndarray            # (len(rows), n): probability that bit j is 1 next
    cost: np.ndarray         # (len(rows),): expected immediate cost


@dataclass(frozen=True)
class FactoredModel:
    facts: tuple[int, ...]   # bit j of a state index = fact ``facts[j]`` of the model
    base: int                # the model state with every varying fact false
    goal: np.ndarray         # (2^n,) bool
    actions: tuple[FactoredAction, ...]
    init: int                # state index of the model's initial state

    @property
    def n_states(self) -> int:
        return 1 << len(self.facts)

    def state(self, k: int) -> int:
        """The model state (int bitset) of state index ``k``."""
        s = self.base
        for j, f in enumerate(self.facts):
            if (k >> j) & 1:
                s |= 1 << f
        return s

    def index(self, state: int) -> int:
        return states_index(state, self.facts)


# -------------------------------------------------------------- structure
def _effect_facts(effect: GEffect) -> int:
    touched = effect.add | effect.delete
    for _, sub in effect.whens:
        touched |= _effect_facts(sub)
    for block in effect.blocks:
        for _, sub in block.outcomes:
            touched |= _effect_facts(sub)
    return touched


def _check_blocks(effect: GEffect) -> None:
    """Each probabilistic block may touch one fact only (else outcomes correlate)."""
    for _, sub in effect.whens:
        _check_blocks(sub)
    for block in effect.blocks:
        touched = 0
        for _, sub in block.outcomes:
            touched |= _effect_facts(sub)
        if touched & (touched - 1):
            raise NotFactored("a probabilistic block changes several facts together")


# ------------------------------------------------------- vectorised reading
class _States:
    """Fact values over all 2^n state indices (columns computed once)."""

    def __init__(self, facts: tuple[int, ...], base: int):
        self.position = {f: j for j, f in enumerate(facts)}
        self.base = base
        self.k = np.arange(1 << len(facts), dtype=np.int64)

    def value(self, fact: int) -> np.ndarray | bool:
        j = self.position.get(fact)
        if j is None:
            return bool((self.base >> fact) & 1)
        return ((self.k >> j) & 1).astype(bool)

    def holds(self, cond: GroundCondition) -> np.ndarray:
        out = np.full(len(self.k), not cond.never)
        for f in indices(cond.pos_facts):
            out &= self.value(f)
        for f in indices(cond.neg_facts):
            out &= ~np.asarray(self.value(f))
        for formula in cond.rest:
            out &= self._formula(formula)
        return out

    def _formula(self, f: GFormula) -> np.ndarray:
        if isinstance(f, GLit):
            v = np.broadcast_to(self.value(f.fact), self.k.shape)
            return v if f.positive else ~v
        parts = [self._formula(a) for a in f.args]
        if isinstance(f, GAnd):
            return np.logical_and.reduce(parts) if parts else np.ones(len(self.k), bool)
        return np.logical_or.reduce(parts) if parts else np.zeros(len(self.k), bool)


#: Per fact, the probabilities of its (added, deleted) flags: index = added + 2·deleted.
_Flags = dict[int, list]
_NOTHING = (1.0, 0.0, 0.0, 0.0)


def _or(left: _Flags, right: _Flags) -> _Flags:
    """Flags of two independent parts of one effect (flags OR-ed)."""
    out = dict(left)
    for f, b in right.items():
        a = out.get(f, _NOTHING)
        out[f] = [a[0] * b[0],
                  a[1] * (b[0] + b[1]) + a[0] * b[1],
                  a[2] * (b[0] + b[2]) + a[0] * b[2],
                  a[3] + b[3] * (a[0] + a[1] + a[2]) + a[1] * (b[2]) + a[2] * (b[1])]
    return out


def _mix(parts: list[tuple[object, _Flags]]) -> _Flags:
    """Flags of a choice among ``parts`` (weight, flags); the weights sum to 1."""
    facts = {f for _, flags in parts for f in flags}
    return {f: [sum(w * flags.get(f, _NOTHING)[i] for w, flags in parts) for i in range(4)]
            for f in facts}


def _flags(effect: GEffect, states: _States) -> _Flags:
    flags: _Flags = {}
    add, delete = effect.add, effect.delete
    for f in indices(add | delete):
        a, d = bool((add >> f) & 1), bool((delete >> f) & 1)
        flags[f] = [0.0, 0.0, 0.0, 0.0]
        flags[f][a + 2 * d] = 1.0
    for cond, sub in effect.whens:
        fires = states.holds(cond).astype(float)
        flags = _or(flags, _mix([(fires, _flags(sub, states)), (1.0 - fires, {})]))
    for block in effect.blocks:
        rest = 1.0 - sum(float(p) for p, _ in block.outcomes)
        parts = [(float(p), _flags(sub, states)) for p, sub in block.outcomes]
        flags = _or(flags, _mix(parts + [(rest, {})]))
    return flags


def _expected_cost(effect: GEffect, states: _States):
    cost = float(effect.cost)
    for cond, sub in effect.whens:
        cost = cost + states.holds(cond) * _expected_cost(sub, states)
    for block in effect.blocks:
        for p, sub in block.outcomes:
            cost = cost + float(p) * _expected_cost(sub, states)
    return cost


def compile_factored(model: GroundModel, unit_cost: bool, max_bits: int = MAX_BITS,
                     init: int | None = None) -> FactoredModel:
    """The product-form description of ``model`` from ``init`` (default: the model's);
    ``NotFactored`` says why it does not fit."""
    if model.axioms:
        raise NotFactored("derived facts (axioms)")
    varying = 0
    for action in model.actions:
        _check_blocks(action.effect)
        varying |= _effect_facts(action.effect)
    facts = tuple(indices(varying))
    if len(facts) > max_bits:
        raise NotFactored(f"{len(facts)} varying facts (at most {max_bits})")
    init = model.init if init is None else init
    base = init & ~varying
    states = _States(facts, base)
    goal = states.holds(model.goal)
    shape = len(states.k)
    actions = []
    for action in model.actions:
        rows = np.flatnonzero(states.holds(action.precondition) & ~goal)
        if not len(rows):
            continue
        flags = _flags(action.effect, states)
        q = np.empty((len(rows), len(facts)))
        for j, f in enumerate(facts):
            old = ((rows >> j) & 1).astype(float)
            p = [np.broadcast_to(np.asarray(x, dtype=float), (shape,))[rows]
                 for x in flags.get(f, _NOTHING)]
            if action.delete_wins:  # an added-and-deleted fact ends up false (mini-gpt)
                q[:, j] = p[1] + p[0] * old
            else:
                q[:, j] = p[1] + p[3] + p[0] * old
        if unit_cost:
            cost = np.ones(len(rows))
        else:
            extra = np.broadcast_to(np.asarray(_expected_cost(action.effect, states), float),
                                    (shape,))
            cost = float(action.base_cost) + extra[rows]
        actions.append(FactoredAction(action.index, rows, np.clip(q, 0.0, 1.0), cost))
    return FactoredModel(facts=facts, base=base, goal=goal, actions=tuple(actions),
                         init=states_index(init, facts))


def states_index(state: int, facts: tuple[int, ...]) -> int:
    return sum(1 << j for j, f in enumerate(facts) if (state >> f) & 1)
