"""Improved LAO* (Hansen & Zilberstein 2001).

Each pass walks the best partial solution graph depth-first from the initial node,
expands the unexpanded tips it meets (backing them up at once) and backs up every
interior node in postorder, so values flow from the tips towards the root within a single
pass. The search stops after a pass that expanded nothing, changed no greedy action and
whose largest Bellman residual is below ε.
"""

from __future__ import annotations

from stampc.solvers.core import Search

_TIME_CHECK_EVERY = 8


def lao(search: Search, init: int, epsilon: float, dive: bool = True,
        prune: float = 0.0) -> None:
    """Run ILAO* from ``init``; raises ``SolverTimeout`` past the deadline.

    With ``dive`` a freshly expanded tip whose backed-up value did not rise (its heuristic
    estimate held) is explored further in the same pass instead of waiting for the next
    one: fewer passes over the solution graph, without the blow-up of always diving.
    """
    search.seed(init)
    V, best, terminal, expanded = search.V, search.best, search.terminal, search.expanded
    dead_end = search.dead_end_cost
    while init not in terminal:
        search.iterations += 1
        expansions = 0
        residual = 0.0
        changed = False
        visited = {init}
        stack = [init]
        reach = {init: 1.0}  # first-visit path probability (pruning only)
        scanned = 0  # transitions backed up in postorder (the search's work counter)
        while stack:
            x = stack.pop()
            if x < 0:  # post-visit marker: Bellman backup (Search.greedy, inlined)
                x = -x - 1
                bq, bi, i = dead_end, -1, 0
                for _, c, probs, nexts in expanded[x]:
                    q = c
                    for p, n in zip(probs, nexts):
                        q += p * V[n]
                    if q < bq:
                        bq, bi = q, i
                    i += 1
                old = V[x]
                d = bq - old if bq > old else old - bq
                if d > residual:
                    residual = d
                if best[x] != bi:
                    changed = True
                    best[x] = bi
                V[x] = bq
                scanned += i
                continue
            if x not in expanded:
                if prune and reach[x] < prune:
                    continue  # a low-probability tip keeps its estimate (partial policy)
                search.expand(x)
                expansions += 1
                rose = x not in terminal and search.backup(x) > epsilon
                # check the limits only once x is backed up: a stopped search stays a
                # consistent warm start (every expanded node has its greedy action)
                if expansions % _TIME_CHECK_EVERY == 0:
                    search.backed_up += scanned
                    scanned = 0
                    search.check_limits()
                if x in terminal or rose or not dive:
                    continue  # a rising estimate lets the parents reconsider first
            stack.append(-x - 1)
            bi = best.get(x, -1)
            if bi >= 0:
                _, _, probs, nexts = expanded[x][bi]
                if prune:  # kept out of the plain loop: this is the solver's hottest walk
                    rx = reach[x]
                    for p, n in zip(probs, nexts):
                        reach.setdefault(n, rx * p)  # first visit, as ``visited`` below
                for n in nexts:
                    if n not in visited:
                        visited.add(n)
                        if n not in terminal:
                            stack.append(n)
        search.backed_up += scanned
        search.check_limits()
        if expansions == 0 and not changed and residual < epsilon:
            return
        if search.stop is not None and search.stop(init):
            return
