"""Zero-cost traps (FRET, Kolobov, Mausam, Weld & Geffner 2011), for certified bounds.

With zero-cost cycles the Bellman operator has many fixed points: LAO* can settle on a
loop that never reaches the goal, valued at whatever its heuristic said (a *trap*: a
closed strongly connected part of the greedy graph, no goal, zero-cost greedy actions).
Two steps make such models certifiable:

- :func:`eliminate_traps` raises every trap member to the value of the trap collapsed
  into one state: moving inside it is free and reaches every member with probability 1,
  so all members are worth the best way *out*, ``min_a (c + Σ_out p·V) / (1 − p_in)``
  over the members' actions (or D). From lower bounds this is again a lower bound (of the
  optimum where looping forever counts as failure), and the search then resumes;
- :func:`repair_policy`: values alone cannot break the tie between the free loop and the
  exit, so before the policy is evaluated, a node that cannot reach the goal under the
  greedy policy takes another action whose Q-value equals its value (within a tolerance)
  and that moves towards nodes that can — grown backwards from the goal, as in a proper
  policy extraction. Whatever remains gives up (``bounds._goal_reaching``).
"""

from __future__ import annotations

from stampc.solvers.core import Search
from stampc.solvers.tvi import components

#: Q-values within this (relative) tolerance of a node's value count as greedy.
TIE = 1e-9


def find_traps(search: Search, init: int) -> list[list[int]]:
    """Traps reachable from ``init``: closed SCCs, without a goal, of the graph of *tied*
    actions (Q within TIE of the node's value). Taking every tied action rather than the
    greedy one matters: an exit whose value is that of the trap (it leads back in) is
    part of it. Tips reached through tied actions are expanded on the way."""
    edges = _tied_graph(search, init)
    traps = []
    for comp in components(search, list(edges), edges=edges):
        members = set(comp)
        if all(x in search.expanded and x not in search.terminal and edges[x]
               and edges[x] <= members for x in comp):
            traps.append(comp)
    return traps


def _tied_graph(search: Search, init: int) -> dict[int, set[int]]:
    V, D, expanded, terminal = search.V, search.dead_end_cost, search.expanded, search.terminal
    edges: dict[int, set[int]] = {}
    stack = [init]
    while stack:
        x = stack.pop()
        if x in edges:
            continue
        if x not in expanded and x not in terminal:
            search.expand(x)
            if x not in terminal:
                search.backup(x)
        tied: set[int] = set()
        if x not in terminal and V[x] < D:
            limit = V[x] * (1 + TIE) + TIE
            for _, c, probs, nexts in expanded[x]:
                if c + sum(p * V[n] for p, n in zip(probs, nexts)) <= limit:
                    tied.update(nexts)
        edges[x] = tied
        stack.extend(n for n in tied if n not in edges)
    return edges


def eliminate_traps(search: Search, init: int) -> int:
    """Raise the values of the traps reachable from ``init``; returns how many changed."""
    V, D = search.V, search.dead_end_cost
    changed = 0
    for trap in find_traps(search, init):
        members = set(trap)
        out, way_out = D, None
        for x in trap:
            for i, (_, c, probs, nexts) in enumerate(search.expanded[x]):
                p_in = sum(p for p, n in zip(probs, nexts) if n in members)
                if p_in < 1.0 - 1e-12:
                    q = (c + sum(p * V[n] for p, n in zip(probs, nexts) if n not in members))
                    if q / (1.0 - p_in) < out:
                        out, way_out = q / (1.0 - p_in), (x, i)
        if way_out is not None:
            # the next LAO* pass walks out through it and expands what lies beyond (the
            # exits' successors may be unexpanded tips with mere heuristic values)
            x, i = way_out
            search.best[x] = i
            changed += any(n not in search.expanded and n not in search.terminal
                           for n in search.expanded[x][i][3])
        for x in trap:
            if out > V[x] * (1 + TIE) + TIE:
                V[x] = out
                changed += 1
    return changed


def repair_policy(search: Search, init: int, bad: list[int], is_goal_node) -> int:
    """Re-point the ``bad`` nodes (from which the greedy policy never reaches a goal) to
    tied actions that do: grown backwards from the goal over the tied graph. Returns how
    many greedy choices changed (``search.best`` is updated)."""
    V, expanded = search.V, search.expanded
    edges = _tied_graph(search, init)
    good = {x for x in edges if is_goal_node(x)}
    choose: dict[int, int] = {}
    grown = True
    while grown:
        grown = False
        for x in edges:
            if x in good or x not in expanded or not edges[x]:
                continue
            limit = V[x] * (1 + TIE) + TIE
            for i, (_, c, probs, nexts) in enumerate(expanded[x]):
                if (any(n in good for n in nexts)
                        and c + sum(p * V[n] for p, n in zip(probs, nexts)) <= limit):
                    choose[x] = i
                    good.add(x)
                    grown = True
                    break
    changed = 0
    for x in bad:
        i = choose.get(x)
        if i is not None and search.best.get(x) != i:
            search.best[x] = i
            changed += 1
    return changed
