"""Abstract (re)planning for the engine: solve the SSP from a state with the built-in
solver and graft the unrolled policy into a policy graph.

Re-solving happens after every UpdateAbstraction, from a state that differs from the
previous one only in learned facts, on the *same* grounded model, so the previous
solution's values are reused (``warm``).
"""

from __future__ import annotations

import math
import random
import time
from dataclasses import dataclass, replace
from typing import Iterator

from stampc.ir.grounded import GroundModel
from stampc.refine.graph import DEAD_END, GOAL, HORIZON, Edge, Node, PolicyGraph
from stampc.refine.deadends import DeadEndProver
from stampc.solvers import Solution, SolverOptions, policy_tree, solve
from stampc.solvers.determinized import with_greedy_plan
from stampc.solvers.space import is_forbidden


#: the adaptive cap goes down to 1/2**MAX_CAP_SHIFT of the solve work limit
MAX_CAP_SHIFT = 4


@dataclass(frozen=True)
class _Cap:
    """A single solve's budget: work units (``Search.work``) and seconds."""
    work: int | None
    seconds: float | None

    def doubled(self) -> _Cap:
        return _Cap(None if self.work is None else 2 * self.work,
                    None if self.seconds is None else 2 * self.seconds)

    def __str__(self) -> str:
        parts = ([f"{self.work:,} work units"] if self.work is not None else []) + \
            ([f"{self.seconds:g} s"] if self.seconds is not None else [])
        return ", ".join(parts) or "no cap"


class AbstractPlanner:
    def __init__(self, model: GroundModel, options: SolverOptions, uids: Iterator[int],
                 fallback: SolverOptions | None = None):
        self.model = model
        # The engine unrolls stationary policies to its own (growing) horizon, so the
        # problem's horizon must not turn every re-solve into a time-indexed one.
        self.solve_model = replace(model, horizon=None) if model.horizon is not None else model
        #: solver settings tried in order: when one finds no way to the goal (e.g. h_add
        #: overestimating a long chain past the dead-end cost) the next one is tried
        self.chain = (options,) + ((fallback,) if fallback is not None else ())
        #: absolute time.perf_counter() deadline for solver calls (the engine's time limit)
        self.deadline: float | None = None
        #: cap on a single solve's work (``Search.work``; deterministic), and on its
        #: time in seconds (a guard for slow machines: where it stops a solve, the run
        #: depends on the machine's speed)
        self.solve_work_limit: int | None = None
        self.solve_time_limit: float | None = None
        self.uids = uids
        self.prover = DeadEndProver(model)
        self.solves = 0
        self.solve_time_s = 0.0
        self._last: dict[str, Solution] = {}
        self.forbidden: set[tuple[int, int]] = set()
        #: a capped solve is continued this many times (doubling the cap) before its
        #: partial policy is used
        self.max_retries = 2
        #: the continuation of a capped solve plans only outcomes reached with at least
        #: this probability (0: all); the rest wait as horizon leaves
        self.timeout_prune = 0.0
        self.timeouts = 0
        #: what the last ``solve_from`` did beyond one plain solve (for progress events)
        self.notes: list[str] = []
        self.last_converged = True
        #: when a list: (state, learned, warm, solution) of every solve (bench/refine.py)
        self.log: list | None = None
        #: warm tables with more states than this are dropped and the next solve starts
        #: cold: they only grow over a run (cluttered-25 seed 5: 1.1 M states, 2.8 GB RSS
        #: after 1,346 s); None: no bound
        self.warm_state_limit: int | None = None
        self.cold_starts = 0
        #: a capped solve first tries a plan on the all-outcomes determinization
        #: (solvers/determinized.py) before any retry
        self.timeout_plan = True
        #: length of the determinized plan the last solve returned (0: none)
        self.plan_steps = 0
        #: a capped solve that a determinized plan then answered quarters the next
        #: solve's work cap (down to 1/2**MAX_CAP_SHIFT of ``solve_work_limit``); a solve
        #: that converges within its cap doubles it back. A run whose model outgrew the
        #: cap then stops paying the whole cap for every update (docs/refine.md,
        #: "Solve caps adapt"). Work-based, so as reproducible as the cap itself.
        self.adaptive_cap = True
        self.cap_shift = 0

    def solve_from(self, state: int, learned: tuple[int, int] | None = None) -> Solution:
        """Solve from ``state``; ``learned`` = (facts learned true, learned false) since
        the previous solve, whose values then seed the new one (incremental re-solve).

        A solve that hits its cap is *not* taken as a verdict: it is continued (its tables
        are a consistent warm start) with twice the time, up to ``max_retries`` times
        within the run's deadline, planning only the outcomes reached with probability
        ``timeout_prune`` or more (the rest are planned when refinement gets there). Only
        a converged solve without a way to the goal falls back to the next solver
        settings (h_FF). Before any retry, a plan on the all-outcomes determinization is
        tried (``timeout_plan``): when one is found its path is the policy, and the
        outcomes off it are planned when refinement reaches them. The first attempt's
        cap adapts (``adaptive_cap``): quartered after a capped solve that a plan
        answered, doubled back by each converged one. ``notes`` says what happened."""
        self.notes = []
        self.plan_steps = 0
        primary = self.chain[0]
        full = _Cap(self.solve_work_limit, self.solve_time_limit)
        cap = self._first_cap(full)
        solution = self._solve_with(primary, state, learned, cap)
        if solution.converged and self.cap_shift:
            self.cap_shift -= 1
        elif not solution.converged and cap != full:
            self.notes.append(f"solver timeout at the adaptive cap ({cap}: earlier capped "
                              "solves were answered by determinized plans)")
        if not solution.converged and self.timeout_plan and self._remaining() > 0.05:
            # the plan gets the full cap: a plan found is cheap, and the shrunk cap is
            # only a bet that the contingent solve will not converge
            planned = with_greedy_plan(solution, min(full.seconds or math.inf, self._remaining()),
                                       full.work)
            if planned is not None:
                if self.adaptive_cap:
                    self.cap_shift = min(MAX_CAP_SHIFT, self.cap_shift + 2)
                self.solve_time_s += planned[0].solve_time_s - solution.solve_time_s
                solution, self.plan_steps = planned
                self.timeouts += 1
                self.notes.append(f"solver timeout: a {self.plan_steps}-step plan on the "
                                  "all-outcomes determinization; outcomes off it are "
                                  "planned when refinement gets there")
                self.last_converged = False
                return solution
        if self.timeout_prune > primary.prune_probability:
            primary = replace(primary, prune_probability=self.timeout_prune)
        if not solution.converged:
            # no plan either: the bet on a cheap answer lost; continue from the full cap
            self.cap_shift = 0
            cap = full
        for _ in range(self.max_retries):
            if solution.converged or self._remaining() <= 0.05:
                break
            cap = cap.doubled()
            self.timeouts += 1
            pruned = f", outcomes below {primary.prune_probability:g} left for later" \
                if primary.prune_probability else ""
            self.notes.append(f"solver timeout: retry with twice the budget ({cap}{pruned})")
            solution = self._solve_with(primary, state, learned, cap)
        for fallback in self.chain[1:]:
            if solution.goal_probability > 0.0 or self._remaining() <= 0.05:
                break
            why = "no way to the goal" if solution.converged else "solver timeout"
            self.notes.append(f"{why} with {primary.heuristic}: {fallback.heuristic} fallback")
            solution = self._solve_with(fallback, state, learned, cap)
        if not solution.converged:
            self.timeouts += 1
            self.notes.append("solver timeout: best partial policy kept")
        self.last_converged = solution.converged
        return solution

    def _first_cap(self, full: _Cap) -> _Cap:
        if full.work is None or not self.cap_shift:
            return full
        return _Cap(max(1, full.work >> self.cap_shift), full.seconds)

    def _remaining(self) -> float:
        return float("inf") if self.deadline is None else self.deadline - time.perf_counter()

    def _solve_with(self, options: SolverOptions, state: int,
                    learned: tuple[int, int] | None, cap: _Cap) -> Solution:
        opts = replace(options, forbidden=frozenset(self.forbidden)) if self.forbidden else options
        budget = [b for b in (cap.seconds, self.deadline and max(0.05, self._remaining())) if b]
        if budget:
            opts = replace(opts, time_limit=min(budget))
        if cap.work is not None:
            opts = replace(opts, work_limit=cap.work)
        key = f"{options.heuristic}:{options.weight}"
        warm = self._last.get(key)  # valid with more bans too (values stay lower bounds)
        if warm is not None and self._too_big(warm):
            self.notes.append(f"warm tables dropped at {len(warm.search.V):,} states "
                              "(memory bound): solved cold")
            del self._last[key]
            warm = None
            self.cold_starts += 1
        solution = solve(self.solve_model, opts, init=state, warm=warm,
                         learned=learned if warm is not None else None)
        self.solves += 1
        self.solve_time_s += solution.solve_time_s
        self._last[key] = solution
        if self.log is not None:
            self.log.append((state, learned, warm, solution))
        return solution

    def _too_big(self, warm: Solution) -> bool:
        limit = self.warm_state_limit
        return limit is not None and warm.search is not None and len(warm.search.V) > limit

    def graft(self, graph: PolicyGraph, state: int, depth: int, horizon: int,
              forced_action: int | None = None, learned: tuple[int, int] | None = None) -> int:
        """Solve from ``state`` and add the policy unrolled to ``horizon`` to ``graph``;
        returns the uid of the new subtree's root. ``forced_action`` (explore step) makes
        the root take that action and plans from each of its outcomes."""
        if forced_action is not None:
            return self._graft_forced(graph, state, depth, horizon, forced_action)
        solution = self.solve_from(state, learned)
        # a determinized plan is unrolled whole, past the horizon if need be: cut at the
        # horizon, its end would only be planned again
        remaining = max(0, horizon - depth, self.plan_steps)
        # a capped or pruned solve leaves tips unexpanded: they become horizon leaves,
        # planned when the engine gets there (one-step lookahead there would be blind)
        partial = not solution.converged or solution.options.prune_probability > 0
        tree = policy_tree(self.solve_model, solution, init=state, depth=remaining,
                           planned_only=partial)
        return self._add_tree(graph, tree, depth)

    def _graft_forced(self, graph: PolicyGraph, state: int, depth: int, horizon: int,
                      action: int) -> int:
        ground = self.model.actions[action]
        node = Node(next(self.uids), state, depth, action=action)
        graph.nodes[node.uid] = node
        for index, succ in enumerate(ground.outcomes(state)):
            child_state = succ.apply(state)
            if self.model.is_goal(child_state):
                child = self._leaf(graph, child_state, depth + 1, GOAL)
            elif depth + 1 >= horizon:
                child = self._leaf(graph, child_state, depth + 1, HORIZON)
            else:
                child = self.graft(graph, child_state, depth + 1, horizon)
            node.edges.append(Edge(float(succ.probability), index, succ, child))
        return node.uid

    def _leaf(self, graph: PolicyGraph, state: int, depth: int, kind: str) -> int:
        node = Node(next(self.uids), state, depth, leaf=kind,
                    proven=kind == DEAD_END and self.prover.proven(state))
        graph.nodes[node.uid] = node
        return node.uid

    def _add_tree(self, graph: PolicyGraph, tree, depth: int) -> int:
        """Copy a solver policy tree into graph nodes, keeping its shared subtrees shared
        (the engine splits a shared node lazily when its parents' concrete states differ)."""
        made: dict[int, int] = {}
        order: list = []
        stack = [tree]
        while stack:  # collect distinct tree nodes, parents before children
            t = stack.pop()
            if id(t) in made:
                continue
            made[id(t)] = next(self.uids)
            order.append(t)
            stack.extend(e.child for e in t.children)
        for t in order:
            kind = _leaf_kind(t)
            node = Node(made[id(t)], t.state, depth + t.depth, action=t.action, leaf=kind,
                        proven=kind == DEAD_END and self.prover.proven(t.state))
            if t.action is not None:
                outcomes = self.model.actions[t.action].outcomes(t.state)
                node.edges = [Edge(e.probability, e.outcome, outcomes[e.outcome], made[id(e.child)])
                              for e in t.children]
            graph.nodes[node.uid] = node
        return made[id(tree)]

    def random_action(self, state: int, rng: random.Random, exclude: int | None) -> int | None:
        """An applicable action other than ``exclude`` (the explore step of Alg. 1)."""
        candidates = [a.index for a in self.model.actions
                      if a.index != exclude and not is_forbidden(self.forbidden, state, a.index)
                      and a.precondition.holds(state)]
        return rng.choice(candidates) if candidates else None


def _leaf_kind(tree) -> str | None:
    if tree.action is not None:
        return None
    if tree.leaf in (GOAL, DEAD_END, HORIZON):
        return tree.leaf
    return DEAD_END
