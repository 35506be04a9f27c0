"""Value tables and Bellman backups shared by LAO*, LRTDP and VI.

``Search`` owns the sparse tables: ``V`` (node -> value; every node ever generated has
one), ``best`` (node -> index into its transitions, ``-1`` = give up), ``terminal`` and
``expanded`` (node -> its transitions). A node is expanded once: its transitions are
generated and every successor gets an initial value (terminal value, heuristic, or
warm-start value). The algorithms read ``expanded[x]`` directly in their inner loops.
"""

from __future__ import annotations

import time
from typing import Callable

from stampc.solvers.space import Space
from stampc.solvers.successors import Transition


#: ``Search.work`` is in units of about one h_add evaluation on the 25-can cluttered table
#: (~130 µs of CPU): one unit per generated node (its heuristic evaluation), plus what
#: costlier evaluations cost beyond one unit where the heuristic reports it (``h.effort``:
#: its relaxed-action counter updates, heuristics.py); per expansion, ``expansion_work``
#: units; and one per 50 transitions scanned by Bellman backups (~2 µs each). Fitted to
#: the CPU time of 50 re-solves of cluttered-25 seed 5 (0.6-5 s each): ~10,000 units per
#: CPU second there, ~5,400 on 60 cans (measured on capped solves of seed 9; with one
#: unit per evaluation and per expansion ~2,200: the 30-s guard, not the cap, stopped
#: those solves).
EXPANSION_WORK = 1
BACKUPS_PER_WORK = 50
#: an expansion's cost grows with the state's width (its successors are built with
#: ``n_facts``-bit integer operations): one unit up to the 25-can table's 5,463 facts
#: (~150 µs; the units were fitted there), 6.6 on 60 cans (36,483 facts, ~1.25 ms)
FACTS_PER_EXPANSION_WORK = 5500


def expansion_work(n_facts: int) -> float:
    """The work units of one expansion in a model with ``n_facts`` facts."""
    return max(float(EXPANSION_WORK), n_facts / FACTS_PER_EXPANSION_WORK)


class SolverTimeout(Exception):
    """Internal: the time or work limit was reached (the caller returns
    ``converged=False``)."""


class Search:
    def __init__(self, space: Space, time_limit: float | None = None,
                 work_limit: int | None = None):
        self.space = space
        self.dead_end_cost = space.dead_end_cost
        self.V: dict[int, float] = {}
        self.best: dict[int, int] = {}
        self.terminal: set[int] = set()
        self.expanded: dict[int, tuple[Transition, ...]] = {}
        #: Finite horizon: the stationary search whose values guide this one.
        self.guide: Search | None = None
        #: Optional early stop, asked by LAO* after each complete pass (values are then
        #: consistent lower bounds): ``bounds.py`` stops once the certified gap is met,
        #: which LAO*'s own test (no expansion, no changed action) can miss for a long
        #: time when equal-valued actions keep trading places.
        self.stop: Callable[[int], bool] | None = None
        #: LAO* passes / LRTDP trials / VI sweeps run so far (statistics only).
        self.iterations = 0
        self.deadline = None if time_limit is None else time.perf_counter() + time_limit
        #: cap on :attr:`work` (None: none): unlike the deadline, where it stops the
        #: search does not depend on the machine or its load
        self.work_limit = work_limit
        #: work counters (deterministic): nodes expanded, nodes generated (each one
        #: heuristic evaluation), transitions scanned by Bellman backups
        self.expansions = 0
        self.generated = 0
        self.backed_up = 0
        self._effort = getattr(space.h, "effort", None)
        self._effort_start = self._effort() if self._effort is not None else 0.0
        self.expansion_work = expansion_work(len(space.cache.model.facts))

    @property
    def work(self) -> int:
        """The search's work so far, in units of about one h_add evaluation on the 25-can
        cluttered table (module constants). The heuristic's excess effort is read from
        the heuristic, so with a finite horizon it includes the guide search's (they
        share it): work done for this solve all the same."""
        costlier = self._effort() - self._effort_start if self._effort is not None else 0.0
        return int(self.expansion_work * self.expansions + self.generated + costlier
                   + self.backed_up // BACKUPS_PER_WORK)

    def check_limits(self) -> None:
        """Raise ``SolverTimeout`` past the deadline or the work limit."""
        if self.deadline is not None and time.perf_counter() > self.deadline:
            raise SolverTimeout()
        if self.work_limit is not None and self.work > self.work_limit:
            raise SolverTimeout()

    def seed(self, node: int) -> None:
        """Give ``node`` its initial value if it has none yet."""
        if node not in self.V:
            v, term = self.space.initial_value(node)
            self.V[node] = v
            if term:
                self.terminal.add(node)

    def expand(self, node: int) -> None:
        V = self.V
        initial_value = self.space.initial_value
        terminal = self.terminal
        trans = self.space.transitions(node)
        fresh = len(V)
        for _, _, _, nexts in trans:
            for n in nexts:
                if n not in V:
                    v, term = initial_value(n)
                    V[n] = v
                    if term:
                        terminal.add(n)
        self.expansions += 1
        self.generated += len(V) - fresh
        self.expanded[node] = trans
        if not trans:  # no applicable action: a dead end
            V[node] = self.dead_end_cost
            self.best[node] = -1
            terminal.add(node)

    def backup(self, node: int) -> float:
        """Bellman backup of an expanded node; returns |change|."""
        V = self.V
        bq, bi = self.greedy(node)
        old = V[node]
        V[node] = bq
        self.best[node] = bi
        return bq - old if bq > old else old - bq

    def greedy(self, node: int) -> tuple[float, int]:
        """(min capped Q, transition index or -1) without storing anything."""
        V = self.V
        bq = self.dead_end_cost
        bi = -1
        trans = self.expanded[node]
        self.backed_up += len(trans)
        for i, (_, c, probs, nexts) in enumerate(trans):
            q = c
            for p, n in zip(probs, nexts):
                q += p * V[n]
            if q < bq:
                bq, bi = q, i
        return bq, bi

    def successors(self, node: int) -> tuple[int, ...]:
        """Next nodes under the greedy choice (none when giving up / terminal)."""
        bi = self.best.get(node, -1)
        if bi < 0 or node in self.terminal:
            return ()
        return self.expanded[node][bi][3]

    # ----------------------------------------------------------- analysis
    def policy_graph(self, init: int) -> list[int]:
        """Nodes reachable from ``init`` under the greedy policy, DFS preorder."""
        order = [init]
        seen = {init}
        stack = [init]
        while stack:
            x = stack.pop()
            for n in self.successors(x):
                if n not in seen:
                    seen.add(n)
                    order.append(n)
                    stack.append(n)
        return order

    def goal_probability(self, init: int, tolerance: float = 1e-12,
                         max_sweeps: int = 100_000, deadline: float | None = None) -> float:
        """Probability of reaching a goal node from ``init`` under the greedy policy (the
        sweeps start from 0, so a sweep cut short by ``deadline`` gives a lower bound)."""
        nodes = self.policy_graph(init)
        is_goal = self.space.cache.is_goal
        P = {x: 1.0 if x in self.terminal and is_goal(self.space.state(x)) else 0.0
             for x in nodes}
        inner = [x for x in reversed(nodes) if self.best.get(x, -1) >= 0 and x not in self.terminal]
        rows = []
        for x in inner:
            _, _, probs, nexts = self.expanded[x][self.best[x]]
            rows.append((x, probs, nexts))
        for sweep in range(max_sweeps):
            change = 0.0
            for x, probs, nexts in rows:
                v = 0.0
                for p, n in zip(probs, nexts):
                    v += p * P[n]
                d = v - P[x]
                if d > change:
                    change = d
                P[x] = v
            if change < tolerance:
                break
            if deadline is not None and sweep % 8 == 7 and time.perf_counter() > deadline:
                break  # a search stopped by its time limit must not hang here
        return min(1.0, P[init])
