"""LM-cut (Helmert & Domshlak 2009) on the delete relaxation of the all-outcomes
determinization — admissible, and never below h_max.

The relaxed actions (:func:`relaxed_actions`) are one per ground action with the adds of
every outcome OR-ed (a further relaxation, so still admissible), its ``when`` effects as
zero-cost pieces (except an action's only top-level ``when`` when nothing else is added:
it carries the cost, boxworld's LM-cut 3 -> 20 at p01's initial state), plus an artificial zero-cost goal action achieving the fact ``G``. Each
round computes h_max under the current costs, picks for every action its precondition
with the largest h_max (``pcf``), finds the *goal zone* (facts reaching ``G`` through
zero-cost justification edges) and the cut: the actions whose ``pcf`` is reachable from
the state without crossing the zone and that add a zone fact. The cut is a landmark (every
relaxed plan uses one of its actions); its cheapest cost is added to h and subtracted
from every cut action. Rounds stop when h_max(G) reaches 0.

A state whose relaxation cannot reach the goal is a dead end (``inf``). Costs are those
of h_max's relaxation (unit, or ``base + min outcome cost`` clamped at 0).
"""

from __future__ import annotations

import heapq
import math

from stampc.ir.grounded import GEffect, GroundModel
from stampc.solvers.heuristics import (Heuristic, _min_cost, condition_facts, iter_bits,
                                      make_heuristic, relaxed_axioms, relaxed_state)

_ZERO = 1e-12  # costs below this count as zero (float leftovers of subtractions)


def _pieces(effect: GEffect, pre: frozenset[int], n: int, out: dict) -> None:
    """The literals ``effect`` adds under ``pre`` (all outcomes OR-ed) and, separately,
    those of its ``when`` effects under ``pre`` plus their conditions."""
    achieved = effect.add | (effect.delete << n)
    if achieved:
        out[pre] = out.get(pre, 0) | achieved
    for block in effect.blocks:
        for _, sub in block.outcomes:
            _pieces(sub, pre, n, out)
    for cond, sub in effect.whens:
        if not cond.never:
            _pieces(sub, pre | condition_facts(cond, n), n, out)


def _top_whens(effect: GEffect) -> list:
    """The ``when`` effects an application may fire that are not nested in another
    ``when``: the effect's own and those inside its probabilistic blocks."""
    whens = list(effect.whens)
    for block in effect.blocks:
        for _, sub in block.outcomes:
            whens += _top_whens(sub)
    return whens


def _sole_when(effect: GEffect, pre: frozenset[int], n: int) -> frozenset[int] | None:
    """The piece precondition of an action's only top-level ``when`` when it adds nothing
    unconditionally (boxworld: every action is one ``when``), else None. Every
    application fires that piece at most once and no other charged piece, so it may
    carry the action's cost."""
    whens = [c for c, _ in _top_whens(effect) if not c.never]
    if len(whens) != 1:
        return None
    return pre | condition_facts(whens[0], n)


def relaxed_actions(model: GroundModel, unit_cost: bool) -> dict[tuple[frozenset[int], float], int]:
    """(precondition literals, cost) -> added literals, for LM-cut.

    Unlike h_max, LM-cut *sums* costs, so one ground action must not become several
    relaxed actions that each cost the full price: the outcomes under the action's own
    precondition are OR-ed into one relaxed action of cost c, and each ``when`` effect
    becomes a relaxed action of cost 0 (it fires only together with the action, whose
    cost the main piece already charges — 0 can only lower the estimate).
    """
    n = len(model.facts)
    merged: dict[tuple[frozenset[int], float], int] = {}
    for action in model.actions:
        if action.precondition.never:
            continue
        cost = 1.0 if unit_cost else max(0.0, float(action.base_cost + _min_cost(action.effect)))
        pre = condition_facts(action.precondition, n)
        pieces: dict[frozenset[int], int] = {}
        _pieces(action.effect, pre, n, pieces)
        charged = pre if pre in pieces else _sole_when(action.effect, pre, n)
        for piece_pre, add in pieces.items():
            key = (piece_pre, cost if piece_pre == charged else 0.0)
            merged[key] = merged.get(key, 0) | add
    for pre, add in relaxed_axioms(model, n).items():  # axioms: zero-cost relaxed actions
        merged[(pre, 0.0)] = merged.get((pre, 0.0), 0) | add
    return merged


class LMCut:
    def __init__(self, model: GroundModel, unit_cost: bool):
        n = len(model.facts)
        self.n, self.full = n, (1 << n) - 1
        merged = relaxed_actions(model, unit_cost)
        self.goal_never = model.goal.never
        goal_facts = tuple(sorted(condition_facts(model.goal, n)))
        self.goal_mask = sum(1 << g for g in goal_facts)
        self.goal_fact = 2 * n
        self.goal_action = len(merged)
        self.pres = [tuple(sorted(pre)) for pre, _ in merged] + [goal_facts]
        self.adds = [tuple(iter_bits(add)) for add in merged.values()] + [(self.goal_fact,)]
        self.costs = [cost for _, cost in merged] + [0.0]
        self.pre_masks = [sum(1 << f for f in p) for p in self.pres]
        self.users: list[list[int]] = [[] for _ in range(2 * n + 1)]
        self.achievers: list[list[int]] = [[] for _ in range(2 * n + 1)]
        for a, pre in enumerate(self.pres):
            for f in pre:
                self.users[f].append(a)
            for g in self.adds[a]:
                self.achievers[g].append(a)

    def __call__(self, state: int) -> float:
        if self.goal_never:
            return math.inf
        s = relaxed_state(state, self.n, self.full)
        if s & self.goal_mask == self.goal_mask:
            return 0.0
        cost = list(self.costs)
        total = 0.0
        while True:
            h, pcf = self._hmax(s, cost)
            hg = h.get(self.goal_fact)
            if hg is None:
                return math.inf
            if hg <= _ZERO:
                return total
            zone = self._goal_zone(pcf, cost)
            cut = self._cut(s, pcf, zone)
            m = min(cost[a] for a in cut)
            total += m
            for a in cut:
                cost[a] -= m

    def _hmax(self, s: int, cost: list[float]) -> tuple[dict[int, float], dict[int, int]]:
        """h_max of every reachable fact not true in ``s`` (those are 0), and each reached
        action's ``pcf`` (-1: no precondition)."""
        counts = [(m & ~s).bit_count() for m in self.pre_masks]
        pres, adds, users = self.pres, self.adds, self.users
        h: dict[int, float] = {}
        pcf: dict[int, int] = {}
        heap: list[tuple[float, int]] = []
        for a, c in enumerate(counts):
            if not c:
                pcf[a] = pres[a][0] if pres[a] else -1
                for g in adds[a]:
                    if not (s >> g) & 1:
                        heap.append((cost[a], g))
        heapq.heapify(heap)
        while heap:
            c, f = heapq.heappop(heap)
            if f in h:
                continue
            h[f] = c
            for a in users[f]:
                counts[a] -= 1
                if counts[a]:
                    continue
                pcf[a] = f  # settled in non-decreasing order: the last is the max
                v = c + cost[a]
                for g in adds[a]:
                    if g not in h and not (s >> g) & 1:
                        heapq.heappush(heap, (v, g))
        return h, pcf

    def _goal_zone(self, pcf: dict[int, int], cost: list[float]) -> set[int]:
        zone = {self.goal_fact}
        stack = [self.goal_fact]
        achievers = self.achievers
        while stack:
            g = stack.pop()
            for a in achievers[g]:
                p = pcf.get(a)
                if p is not None and p >= 0 and cost[a] <= _ZERO and p not in zone:
                    zone.add(p)
                    stack.append(p)
        return zone

    def _cut(self, s: int, pcf: dict[int, int], zone: set[int]) -> list[int]:
        by_pcf: dict[int, list[int]] = {}
        for a, p in pcf.items():
            by_pcf.setdefault(p, []).append(a)
        reached = {p for p in by_pcf if p < 0 or (s >> p) & 1}
        stack = list(reached)
        cut = []
        adds = self.adds
        while stack:
            f = stack.pop()
            for a in by_pcf.get(f, ()):
                crosses = False
                for g in adds[a]:
                    if g in zone:
                        crosses = True
                    elif g not in reached:
                        reached.add(g)
                        stack.append(g)
                if crosses:
                    cut.append(a)
        return cut


def _has_whens(effect: GEffect) -> bool:
    return bool(effect.whens) or any(_has_whens(sub) for block in effect.blocks
                                     for _, sub in block.outcomes)


def make_lmcut(model: GroundModel, unit_cost: bool, weight: float = 1.0) -> Heuristic:
    """A cached LM-cut heuristic (``inf`` marks a recognised dead end)."""
    lm = LMCut(model, unit_cost)
    # zero-cost ``when`` pieces can leave LM-cut below h_max: take the max of both there
    hmax = (make_heuristic("hmax", model, unit_cost)
            if any(_has_whens(a.effect) for a in model.actions) else None)
    cache: dict[int, float] = {}

    def h(state: int) -> float:
        v = cache.get(state)
        if v is None:
            v = lm(state)
            if hmax is not None:
                v = max(v, hmax(state))
            v = cache[state] = weight * v
        return v

    return h
