"""A plan on the all-outcomes determinization, written into a solve's tables (FF-Replan's
idea inside the refinement loop).

When LAO* cannot converge within its cap, the refinement engine still needs *a* way to
the goal to refine: a greedy best-first search that may pick any outcome of an action
finds one in a few dozen expansions where LAO* spends thousands proving which policy is
best (cluttered-60: 19 expansions, 0.45 s, against > 5,000 and no convergence in 150 s;
the delete relaxation there ignores that the hand must be emptied between picks, so
h_add is half the true cost and LAO* must look at every ordering of the blockers).

The plan is written into the timed-out search's tables: each node on it gets the plan's
transition as its greedy choice, and every outcome off the plan stays an unexpanded tip,
which the engine plans when refinement gets there. The tables stay a consistent warm
start for the next solve: the search only expands nodes, as LAO* would.
"""

from __future__ import annotations

import heapq
import math
import time
from dataclasses import replace

from stampc.solvers.core import Search
from stampc.solvers.solution import Solution

_TIME_CHECK_EVERY = 8


def greedy_plan(search: Search, init: int, deadline: float,
                work_limit: int | None = None) -> list[tuple[int, int]] | None:
    """[(node, transition index)] from ``init`` to a goal node, by greedy best-first search
    on the nodes' current values (heuristic or backed up); ties go to the likelier path,
    then the cheaper one. ``None``: no plan found before ``deadline``, within
    ``work_limit`` more units of the search's work, or none exists."""
    stop_at = None if work_limit is None else search.work + work_limit
    V, terminal, expanded = search.V, search.terminal, search.expanded
    is_goal = search.space.cache.is_goal
    state_of = search.space.state
    search.seed(init)
    parent: dict[int, tuple[int, int] | None] = {init: None}
    queue = [(V[init], 0.0, 0.0, 0, init)]  # value, -log(path probability), cost, order
    pushed = expansions = 0
    while queue:
        _, surprise, g, _, x = heapq.heappop(queue)
        if x in terminal:
            if is_goal(state_of(x)):
                return _path_to(parent, x)
            continue  # a recognised dead end
        if x not in expanded:
            search.expand(x)
            if x not in terminal:  # as LAO* does: every expanded node has its greedy
                search.backup(x)   # choice, so the tables stay a valid warm start
            expansions += 1
            if expansions % _TIME_CHECK_EVERY == 0 and (
                    time.perf_counter() > deadline
                    or stop_at is not None and search.work > stop_at):
                return None
        for i, (_, cost, probs, nexts) in enumerate(expanded[x]):
            for p, n in zip(probs, nexts):
                if n in parent or p <= 0.0:
                    continue
                parent[n] = (x, i)
                pushed += 1
                heapq.heappush(queue, (V[n], surprise - math.log(p), g + cost, pushed, n))
    return None


def _path_to(parent: dict[int, tuple[int, int] | None], goal: int) -> list[tuple[int, int]]:
    path = []
    link = parent[goal]
    while link is not None:
        path.append(link)
        link = parent[link[0]]
    path.reverse()
    return path


def with_greedy_plan(solution: Solution, time_limit: float,
                     work_limit: int | None = None) -> tuple[Solution, int] | None:
    """``solution`` (a timed-out search) with a determinized plan from its initial state
    as the greedy choice along the plan, and the plan's length; ``None`` when no plan was
    found within ``time_limit`` seconds or ``work_limit`` units of work. The result is a
    partial policy (``converged=False``): outcomes off the plan are unplanned tips."""
    search = solution.search
    if search is None:
        return None
    x0 = search.space.node(solution.init, 0)
    start = time.perf_counter()
    plan = greedy_plan(search, x0, start + time_limit, work_limit)
    if plan is None:
        return None
    for node, index in plan:
        search.best[node] = index
    goal_probability = search.goal_probability(x0, deadline=time.perf_counter() + 1.0)
    return replace(solution, goal_probability=goal_probability, converged=False,
                   solve_time_s=solution.solve_time_s + time.perf_counter() - start), len(plan)
