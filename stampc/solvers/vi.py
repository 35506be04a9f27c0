"""Value iteration over the reachable state space (small problems; correctness oracle).

All nodes reachable from the initial node under *any* action sequence are generated
first. Stationary problems then run Gauss-Seidel sweeps (in reverse discovery order, so
values flow from the goal side) until the largest residual is below ε. Time-indexed
problems are acyclic: one backward-induction sweep by decreasing time step is exact.
"""

from __future__ import annotations

from stampc.solvers.core import Search

#: Sweeps stop after this many even when the residual is still above ε.
MAX_SWEEPS = 1_000_000


def reachable(search: Search, init: int) -> list[int]:
    """Every non-terminal node reachable from ``init``, expanded, in BFS order."""
    search.seed(init)
    order: list[int] = []
    frontier = [init]
    seen = {init}
    while frontier:
        nxt: list[int] = []
        for x in frontier:
            if x in search.terminal:
                continue
            search.expand(x)
            if x in search.terminal:
                continue
            order.append(x)
            for _, _, _, nexts in search.expanded[x]:
                for n in nexts:
                    if n not in seen:
                        seen.add(n)
                        nxt.append(n)
        frontier = nxt
        search.check_limits()
    return order


def value_iteration(search: Search, init: int, epsilon: float) -> None:
    nodes = reachable(search, init)
    if search.space.horizon is not None:
        time_of = search.space.time
        for x in sorted(nodes, key=time_of, reverse=True):
            search.backup(x)
        return
    nodes.reverse()
    sweep_until_converged(search, nodes, epsilon)


def sweep_until_converged(search: Search, nodes: list[int], epsilon: float) -> None:
    """Gauss-Seidel sweeps over ``nodes`` (in order) until the largest Bellman residual
    of a sweep is below ``epsilon`` (or MAX_SWEEPS); checks the time and work limits every
    16 sweeps, from the first."""
    backup = search.backup
    for sweep in range(MAX_SWEEPS):
        search.iterations += 1
        residual = 0.0
        for x in nodes:
            d = backup(x)
            if d > residual:
                residual = d
        if residual < epsilon:
            return
        if sweep % 16 == 0:
            search.check_limits()
