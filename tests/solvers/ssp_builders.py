"""Small grounded-model builders, a random SSP generator and an independent oracle.

The oracle (``reference_values``) works directly on ``GroundAction.outcomes`` with exact
outcome lists — no successor cache, no self-loop elimination — so it checks the solvers
and their data structures independently.
"""

from __future__ import annotations

import random
from fractions import Fraction
from typing import Iterable, Sequence

from stampc.ir.grounded import (GEffect, GProb, GroundAction, GroundAtom, GroundCondition,
                                GroundModel)


class ModelBuilder:
    """Propositional models over named 0-ary facts."""

    def __init__(self, facts: Sequence[str]):
        self.names = list(facts)
        self.index = {n: i for i, n in enumerate(self.names)}
        self.actions: list[GroundAction] = []

    def mask(self, names: Iterable[str]) -> int:
        m = 0
        for n in names:
            m |= 1 << self.index[n]
        return m

    def cond(self, pos: Iterable[str] = (), neg: Iterable[str] = ()) -> GroundCondition:
        return GroundCondition(pos=self.mask(pos), neg=self.mask(neg))

    def effect(self, add: Iterable[str] = (), delete: Iterable[str] = (), cost=0,
               whens=()) -> GEffect:
        return GEffect(add=self.mask(add), delete=self.mask(delete), cost=Fraction(cost),
                       whens=tuple(whens))

    def action(self, name: str, pre: Iterable[str] = (), neg: Iterable[str] = (),
               outcomes: Sequence[tuple] = (), cost=1, effect: GEffect | None = None,
               precondition: GroundCondition | None = None) -> int:
        """``outcomes``: (probability, adds, deletes[, extra cost]) of one probabilistic
        block; probabilities may sum below 1 (rest: nothing happens)."""
        if effect is None:
            block = GProb(tuple((Fraction(o[0]), self.effect(o[1], o[2], o[3] if len(o) > 3 else 0))
                                for o in outcomes))
            effect = GEffect(blocks=(block,))
        index = len(self.actions)
        self.actions.append(GroundAction(index=index, name=name, args=(),
                                         precondition=precondition or self.cond(pre, neg),
                                         effect=effect,
                                         base_cost=Fraction(cost)))
        return index

    def build(self, init: Iterable[str], goal: Iterable[str] = (), goal_neg: Iterable[str] = (),
              horizon: int | None = None,
              goal_condition: GroundCondition | None = None) -> GroundModel:
        return GroundModel(facts=tuple(GroundAtom(n, ()) for n in self.names),
                           actions=tuple(self.actions), init=self.mask(init),
                           goal=goal_condition or self.cond(goal, goal_neg), objects=(),
                           horizon=horizon,
                           has_costs=True)


def random_model(seed: int, n_facts: int = 5, n_actions: int = 7,
                 zero_cost_share: float = 0.0) -> GroundModel:
    """A random small SSP: conjunctive preconditions, 1-3 outcomes, integer costs; with
    ``zero_cost_share`` > 0 that share of the actions costs nothing (zero-cost cycles)."""
    rng = random.Random(seed)
    names = [f"f{i}" for i in range(n_facts)]
    b = ModelBuilder(names)
    for k in range(n_actions):
        pre = rng.sample(names, rng.randint(0, 2))
        neg = [n for n in rng.sample(names, rng.randint(0, 1)) if n not in pre]
        n_out = rng.randint(1, 3)
        weights = [rng.randint(1, 4) for _ in range(n_out + rng.randint(0, 1))]
        total = sum(weights)
        outcomes = []
        for w in weights[:n_out]:
            add = rng.sample(names, rng.randint(0, 2))
            delete = [n for n in rng.sample(names, rng.randint(0, 2)) if n not in add]
            outcomes.append((Fraction(w, total), add, delete, rng.randint(0, 2)))
        cost = rng.randint(1, 3)
        if zero_cost_share and rng.random() < zero_cost_share:
            cost, outcomes = 0, [(p, add, delete, 0) for p, add, delete, _ in outcomes]
        b.action(f"a{k}", pre, neg, outcomes, cost=cost)
    init = [n for n in names if rng.random() < 0.3]
    goal = rng.sample(names, rng.randint(1, 2))
    return b.build(init, goal)


def random_conditional_model(seed: int, n_facts: int = 5, n_actions: int = 6) -> GroundModel:
    """Random SSP whose actions have ``when`` effects and two independent blocks, so
    outcomes depend on the state."""
    rng = random.Random(seed)
    names = [f"f{i}" for i in range(n_facts)]
    b = ModelBuilder(names)

    def block() -> GProb:
        n = rng.randint(1, 2)
        weights = [rng.randint(1, 3) for _ in range(n + rng.randint(0, 1))]
        total = sum(weights)
        return GProb(tuple((Fraction(w, total),
                            b.effect(rng.sample(names, 1), rng.sample(names, rng.randint(0, 1)),
                                     rng.randint(0, 2)))
                           for w in weights[:n]))

    for k in range(n_actions):
        whens = [(b.cond(rng.sample(names, 1), []), b.effect(rng.sample(names, 1), [], 1)),
                 (b.cond([], rng.sample(names, 1)), b.effect([], rng.sample(names, 1)))]
        effect = GEffect(whens=tuple(whens), blocks=(block(), block()))
        b.action(f"c{k}", rng.sample(names, rng.randint(0, 1)), effect=effect,
                 cost=rng.randint(1, 2))
    return b.build([n for n in names if rng.random() < 0.3], rng.sample(names, 2))


def _successors(model: GroundModel, state: int, unit_cost: bool):
    for action in model.actions:
        if action.precondition.holds(state):
            yield action.index, [(float(o.probability), o.apply(state),
                                  1.0 if unit_cost else float(o.cost))
                                 for o in action.outcomes(state)]


def reachable_states(model: GroundModel, init: int | None = None) -> list[int]:
    start = model.init if init is None else init
    seen, stack = {start}, [start]
    while stack:
        s = stack.pop()
        if model.is_goal(s):
            continue
        for _, outs in _successors(model, s, False):
            for _, n, _ in outs:
                if n not in seen:
                    seen.add(n)
                    stack.append(n)
    return sorted(seen)


def reference_values(model: GroundModel, dead_end_cost: float, unit_cost: bool = False,
                     tol: float = 1e-12, max_iter: int = 200_000) -> dict[int, float]:
    """Jacobi value iteration with capped Q-values on exact outcome lists."""
    states = reachable_states(model)
    succ = {s: list(_successors(model, s, unit_cost)) for s in states}
    V = {s: 0.0 for s in states}
    for _ in range(max_iter):
        new = {}
        for s in states:
            if model.is_goal(s):
                new[s] = 0.0
                continue
            best = dead_end_cost
            for _, outs in succ[s]:
                best = min(best, sum(p * (c + V[n]) for p, n, c in outs))
            new[s] = best
        change = max(abs(new[s] - V[s]) for s in states)
        V = new
        if change < tol:
            break
    return V


def reference_from_above(model: GroundModel, dead_end_cost: float, tol: float = 1e-12,
                         max_iter: int = 200_000) -> dict[int, float]:
    """Jacobi value iteration started at D: the greatest fixed point below D, the optimum
    where looping forever without the goal counts as failure (FRET's semantics; the
    least fixed point, from 0, values a zero-cost loop at 0)."""
    states = reachable_states(model)
    succ = {s: list(_successors(model, s, False)) for s in states}
    V = {s: 0.0 if model.is_goal(s) else dead_end_cost for s in states}
    for _ in range(max_iter):
        new = {s: 0.0 if model.is_goal(s) else
               min([dead_end_cost] + [sum(p * (c + V[n]) for p, n, c in outs)
                                      for _, outs in succ[s]])
               for s in states}
        change = max(abs(new[s] - V[s]) for s in states)
        V = new
        if change < tol:
            break
    return V


def reference_finite(model: GroundModel, dead_end_cost: float, horizon: int,
                     unit_cost: bool = False) -> float:
    """Exact finite-horizon value of ``model.init`` by memoised recursion."""
    memo: dict[tuple[int, int], float] = {}

    def value(s: int, t: int) -> float:
        if model.is_goal(s):
            return 0.0
        if t >= horizon:
            return dead_end_cost
        key = (s, t)
        if key not in memo:
            best = dead_end_cost
            for _, outs in _successors(model, s, unit_cost):
                best = min(best, sum(p * (c + value(n, t + 1)) for p, n, c in outs))
            memo[key] = best
        return memo[key]

    return value(model.init, 0)


def ippc_model(root, instance: str) -> GroundModel:
    """The grounded IPPC ``instance`` under the benchmark folder ``root``; skips the test
    when that file is not there."""
    import pytest

    from stampc import api

    path = root / instance
    if not path.is_file():
        pytest.skip(f"{instance} not found")
    return api.ground(api.load_model([str(path)]))


def breadth_first_states(model: GroundModel, limit: int) -> list[int]:
    """Up to ``limit`` states reachable from the initial state, breadth-first."""
    from stampc.solvers.successors import SuccessorCache

    cache = SuccessorCache(model, True)
    seen, order = {model.init}, [model.init]
    for s in order:
        if len(order) >= limit:
            break
        for _, _, _, nexts in cache.transitions(s):
            for n in nexts:
                if n not in seen:
                    seen.add(n)
                    order.append(n)
    return order[:limit]


def shuffled_random_instance(seed: int) -> tuple[GroundModel, list[int]]:
    """``random_model(seed)`` and its reachable states in a seeded random order."""
    model = random_model(seed)
    states = reachable_states(model)
    random.Random(seed).shuffle(states)
    return model, states
