"""LM-cut (Helmert & Domshlak 2009) on the delete relaxation of the all-outcomes
determinization — admissible, and never below h_max.

The relaxed actions are those of :class:`heuristics.RelaxedModel` (one per distinct
precondition and cost, adds of every outcome OR-ed — a further relaxation, so still
admissible), plus an artificial zero-cost goal action achieving the fact ``G``. Each
round computes h_max under the current costs, picks for every action its precondition
with the largest h_max (``pcf``), finds the *goal zone* (facts reaching ``G`` through
zero-cost justification edges) and the cut: the actions whose ``pcf`` is reachable from
the state without crossing the zone and that add a zone fact. The cut is a landmark (every
relaxed plan uses one of its actions); its cheapest cost is added to h and subtracted
from every cut action. Rounds stop when h_max(G) reaches 0.

A state whose relaxation cannot reach the goal is a dead end (``inf``). Costs are the
relaxed costs of ``RelaxedModel`` (unit or ``base + min outcome cost``, clamped at 0).
"""

from __future__ import annotations

import heapq
import math

from stampc.ir.grounded import GroundModel
from stampc.solvers.heuristics import Heuristic, RelaxedModel, relaxed_state

_ZERO = 1e-12  # costs below this count as zero (float leftovers of subtractions)


class LMCut:
    def __init__(self, model: GroundModel, unit_cost: bool):
        rm = RelaxedModel(model, unit_cost)
        self.rm = rm
        self.goal_fact = 2 * rm.n
        self.goal_action = len(rm.pres)
        self.pres = list(rm.pres) + [rm.goal_facts]
        self.adds = list(rm.adds) + [(self.goal_fact,)]
        self.costs = list(rm.costs) + [0.0]
        self.pre_masks = list(rm.pre_masks) + [rm.goal_mask]
        self.users = [list(u) for u in rm.users] + [[]]
        for g in rm.goal_facts:
            self.users[g].append(self.goal_action)
        self.achievers: list[list[int]] = [[] for _ in range(2 * rm.n + 1)]
        for a, adds in enumerate(self.adds):
            for g in adds:
                self.achievers[g].append(a)

    def __call__(self, state: int) -> float:
        rm = self.rm
        if rm.goal_never:
            return math.inf
        s = relaxed_state(state, rm.n, rm.full)
        if s & rm.goal_mask == rm.goal_mask:
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


def make_lmcut(model: GroundModel, unit_cost: bool, weight: float = 1.0) -> Heuristic:
    """A cached LM-cut heuristic (``inf`` marks a recognised dead end)."""
    lm = LMCut(model, unit_cost)
    cache: dict[int, float] = {}

    def h(state: int) -> float:
        v = cache.get(state)
        if v is None:
            v = cache[state] = weight * lm(state)
        return v

    return h
