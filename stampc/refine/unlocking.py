"""Path selection by the mass a path unlocks: the uncovered path whose refinement adds
the most coverage per unit of estimated refinement cost ĉ.

The paper's rule (selection.py) takes the path with the best p/ĉ, p being the path's own
probability. On a policy *graph*, where the outcomes of an action meet again in merged
states, that undervalues a node whose continuations are already refined: refining it
covers all of them at once. Keva 3π seed 0 showed it: the root's feed-2 branch (0.2 of
the mass) was refined last, because its single most likely path is no likelier than a
deep one (0.2 · 0.8⁸) and its ĉ is the longest; one put-down near the root then added
0.195 at 27.2 s of a 28.1 s run. Here a path is worth the coverage it adds.

If every node on a path were refined, a node ``n`` on it would be covered with mass
``G(n) = S(n) − q·cov(c) + q·G(c)``: its children's covered mass ``S(n)`` with the path's
child ``c`` (edge probability ``q``) counted at its own ``G``. The path may also stop at
an unrefined node whose children are already covered (``G = S(n)``). An open leaf (a
horizon, an unproven dead end) counts as covered once extended, as in p/ĉ. The gain at
``n`` is ``G(n) − cov(n)`` for the cost ``ĉ`` of the path's unrefined nodes. Each node
keeps the continuation with the best gain / ĉ, chosen among its children's (children
first: one sweep), and the root's is the selected path. Off-path children that meet the
path again lower down are counted at their current mass, so the gain is a lower bound
where branches merge. The values are kept between steps like the p/ĉ bounds
(incremental.py). A cyclic graph, and a tree (no node with two parents: nothing is
unlocked that its paths' probabilities do not show), are left to p/ĉ selection, whose
search finds the best ratio exactly: each node here keeps one continuation, the best for
its own ratio, which is not always the best for its parent's; so where branches merge
the engine still asks p/ĉ's search and takes its path when its ratio is the better one
(:func:`better_ratio`). On the cluttered table,
whose policies are trees, the sweep alone took cluttered-20 seed 3 past 24 min where p/ĉ
solved it in 12.6.
"""

from __future__ import annotations

import math
from typing import Callable, Hashable, Iterable, Mapping

from stampc.refine.graph import Node, PolicyGraph
from stampc.refine.incremental import IncrementalValues
from stampc.refine.selection import per_cost

INF = math.inf
#: any gain counts: single paths through a tall tower's merged feed outcomes have
#: probabilities far below 1e-12 (0.2^24 on tower-24) and their mass must stay selectable;
#: a rounding gain is harmless, since a selectable path always has work on it (ĉ > 0)
EPSILON = 0.0
#: per node: (covered mass, mass once the best continuation is refined, its ĉ, the
#: child it goes on to, or None where it stops at the node)
Value = tuple[float, float, float, "int | None"]
#: a selected path: (its gain or probability, its ĉ, the node uids from the root)
Selected = tuple[float, float, tuple[int, ...]]
NodeCost = Callable[[Node], float]


def unlock_local(node_cost: NodeCost) -> Callable[[Node, Mapping[int, Value]], Value]:
    """A node's value from its children's (the function incremental.py keeps)."""
    def local(node: Node, values: Mapping[int, Value]) -> Value:
        cost = node_cost(node)
        if node.is_leaf:
            if node.terminal:
                return 1.0, 1.0, 0.0, None
            if node.given_up or cost == INF:
                return 0.0, 0.0, INF, None
            return 0.0, 1.0, cost, None  # open: covered once extended (optimistic)
        return _inner(node, cost, values)
    return local


def _inner(node: Node, cost: float, values: Mapping[int, Value]) -> Value:
    edges = [(e.probability, values[e.child], e.child) for e in node.edges
             if e.probability > 0.0]
    children = sum(q * v[0] for q, v, _ in edges)
    covered = children if node.refined else 0.0
    best: tuple[float, float, float, int | None] | None = None
    if not node.refined and cost < INF and children > EPSILON:
        best = (per_cost(children, cost), children, cost, None)  # this node alone
    for q, (c_cov, c_mass, c_cost, _), child in edges:
        if c_cost == INF:
            continue
        mass = children - q * c_cov + q * c_mass
        total = cost + c_cost
        gain = mass - covered
        if gain <= EPSILON or total == INF:
            continue
        score = per_cost(gain, total)
        if best is None or score > best[0]:
            best = (score, mass, total, child)
    if best is None:
        return covered, covered, INF, None
    return covered, best[1], best[2], best[3]


def select_unlocking(graph: PolicyGraph, node_cost: NodeCost, key: Hashable,
                     changed: Iterable[int] = ()
                     ) -> tuple[float, float, tuple[int, ...]] | None | bool:
    """(gain, ĉ, path) of the path that unlocks the most mass per ĉ, None when nothing
    is left to gain, or False where the caller selects by p/ĉ instead: on a cyclic
    graph, and on a graph where no branches meet again (a tree, where the gain is a
    path's probability, give or take the goal leaves beside it, and p/ĉ's exact
    search finds the best ratio, which the sweep here only approximates). ``key`` and
    ``changed`` as in ``tracked_bounds``: the values are kept for the key's costs;
    nodes whose cost differs (a parallel batch's taken ones) are computed aside."""
    found = best_unlocking(graph, node_cost, key, changed)
    if found is False or not _kept(graph, node_cost, key).merges(graph):
        return False
    return found


def better_ratio(unlocking: Selected, by_path: Selected | None) -> Selected:
    """The unlocking sweep's path, unless p/ĉ's exact search found a better ratio.

    A path's probability p is a lower bound on the coverage its refinement adds, so p/ĉ
    is a lower bound on the same yardstick as the sweep's gain/ĉ. The sweep keeps one
    continuation per node, chosen for that node's own ratio, so on a graph with few
    merges it can fall below the best p/ĉ: aircraft-2x seed 5, in its tail of 5 %
    drift branches, refined 1,800 nodes (255 s) by the sweep against 415 (82 s) by p/ĉ."""
    if by_path is None:
        return unlocking
    gain, cost, _ = unlocking
    p, p_cost, _ = by_path
    return by_path if per_cost(p, p_cost) > per_cost(gain, cost) else unlocking


def _kept(graph: PolicyGraph, node_cost: NodeCost, key: Hashable) -> IncrementalValues:
    """The values kept on ``graph`` for the costs named ``key`` (a new key starts afresh)."""
    tracker = graph.caches.get("unlocking")
    if tracker is None or tracker[0] != key:
        tracker = graph.caches["unlocking"] = (key, IncrementalValues(unlock_local(node_cost)))
    return tracker[1]


def best_unlocking(graph: PolicyGraph, node_cost: NodeCost, key: Hashable,
                   changed: Iterable[int] = ()
                   ) -> tuple[float, float, tuple[int, ...]] | None | bool:
    """:func:`select_unlocking` on any acyclic graph, trees included (False: cyclic).
    The path runs from the root to a leaf, or to an unrefined node whose continuations
    are all covered already."""
    kept = _kept(graph, node_cost, key)
    if changed:
        v = kept.variant(graph, changed, unlock_local(node_cost))
    else:
        v = kept.values if kept.refresh(graph) else None
    if v is None:
        return False
    covered, mass, cost, _ = v[graph.root]
    if cost == INF or mass - covered <= EPSILON:
        return None
    path = [graph.root]
    seen = {graph.root}
    while (child := v[path[-1]][3]) is not None:
        if child in seen:  # cannot happen on an acyclic graph; never loop
            break
        seen.add(child)
        path.append(child)
    return mass - covered, cost, tuple(path)
