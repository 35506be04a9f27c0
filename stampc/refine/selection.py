"""Path selection: the uncovered root-to-leaf path with the best p/ĉ (greedy knapsack,
Thm. 1 of Shah et al.), found by best-first branch and bound over per-node bounds.

The bounds are a fixed point over the whole policy graph. The engine keeps them between
steps (:func:`tracked_bounds`, incremental.py): after a step only the nodes it changed
and their ancestors are recomputed, which gives the same values as a sweep from scratch
(:func:`path_bounds`); cyclic graphs are swept from scratch every time.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass
from typing import Callable, Hashable, Iterable, Mapping

from stampc.refine.graph import Node, PolicyGraph
from stampc.refine.incremental import IncrementalValues

INF = math.inf
#: a node's bounds before the fixed point reaches it: nothing open below
UNSET = (0.0, 0.0, INF, INF)
#: a change below this does not count (the cyclic sweep's convergence test)
EPSILON = 1e-15

NodeCost = Callable[[Node], float]


def per_cost(value: float, cost: float) -> float:
    """``value`` per unit of estimated cost; a cost below one counts as one, so a nearly
    free step does not blow a tiny value up past every real path."""
    return value / max(cost, 1.0)


def path_is_covered(graph: PolicyGraph, path: tuple[int, ...]) -> bool:
    leaf = graph.nodes[path[-1]]
    return leaf.terminal and all(graph.nodes[u].refined for u in path[:-1])


@dataclass(frozen=True)
class Bounds:
    """Per node, bounds on its continuations to a selectable leaf: the most likely one's
    probability and the cheapest one's remaining ĉ (both counting from below the node).
    ``open``: continuations that are uncovered given a refined path down to the node;
    ``any``: every continuation (below an unrefined node, all of them are uncovered).
    ``values[uid]`` = (p_open, p_any, c_open, c_any, ĉ of the node, refined or a leaf)."""

    values: Mapping[int, tuple]

    def open(self, uid: int) -> tuple[float, float]:
        v = self.values[uid]
        return v[0], v[2]

    def any(self, uid: int) -> tuple[float, float]:
        v = self.values[uid]
        return v[1], v[3]


def _raw_bounds(node: Node, cost: float, values: Mapping[int, tuple]) -> tuple:
    """(p_open, p_any, c_open, c_any) of ``node`` from its children's values."""
    if node.is_leaf:
        selectable = not node.given_up and cost < INF
        return (1.0 if selectable and not node.terminal else 0.0,
                1.0 if selectable else 0.0, 0.0, 0.0)
    any_p = open_p = 0.0
    any_c = open_c = INF
    refined = node.refined
    for e in node.edges:
        q = e.probability
        if not q > 0.0:
            continue
        v = values[e.child]
        k = v[4]
        p, c = q * v[1], k + v[3]
        any_p, any_c = max(any_p, p), min(any_c, c)
        if refined:
            if v[5]:  # the child is refined or a leaf: a refined path goes on through it
                p, c = q * v[0], k + v[2]
            open_p, open_c = max(open_p, p), min(open_c, c)
    if refined:
        return open_p, any_p, open_c, any_c
    return any_p, any_p, any_c, any_c


def _settled(new: tuple, old: tuple) -> tuple:
    """``new`` unless it differs from ``old`` by less than EPSILON in every component."""
    for a, b in zip(new, old):
        if a != b and abs(a - b) > EPSILON:
            return new
    return old


def bounds_local(node_cost: NodeCost) -> Callable[[Node, Mapping[int, tuple]], tuple]:
    """A node's bounds from its children's (one sweep, children first: acyclic graphs)."""
    def local(node: Node, values: Mapping[int, tuple]) -> tuple:
        cost = node_cost(node)
        return (*_settled(_raw_bounds(node, cost, values), UNSET), cost,
                node.refined or node.is_leaf)
    return local


def path_bounds(graph: PolicyGraph, node_cost: NodeCost) -> Bounds:
    """The bounds from scratch: a fixed point over the policy graph (cycles converge: a
    loop multiplies probabilities < 1 and adds costs >= 0). A node's own ĉ counts in its
    parent's sums. Acyclic graphs take one sweep children first."""
    order, acyclic = graph.postorder()
    if acyclic:
        local = bounds_local(node_cost)
        values: dict[int, tuple] = {}
        for uid in order:
            values[uid] = local(graph.nodes[uid], values)
        return Bounds(values)
    return Bounds(_swept_bounds(graph, order, node_cost))


def _swept_bounds(graph: PolicyGraph, order: list[int], node_cost: NodeCost) -> dict:
    """Gauss-Seidel sweeps in ``order`` until nothing changes by more than EPSILON."""
    extra = {u: (node_cost(graph.nodes[u]), graph.nodes[u].refined or graph.nodes[u].is_leaf)
             for u in order}
    values = {u: (*UNSET, *extra[u]) for u in order}
    for _ in range(10_000):
        changed = False
        for uid in order:
            old = values[uid][:4]
            new = _settled(_raw_bounds(graph.nodes[uid], extra[uid][0], values), old)
            if new is not old:
                values[uid] = (*new, *extra[uid])
                changed = True
        if not changed:
            break
    return values


def tracked_bounds(graph: PolicyGraph, node_cost: NodeCost, key: Hashable,
                   changed: Iterable[int] = ()) -> Bounds:
    """:func:`path_bounds`, kept on ``graph`` between calls and updated incrementally.

    ``key`` names the costs: ``node_cost`` must give the same cost for the same node and
    key (the engine's ĉ depends on its horizon); a new key starts afresh. ``changed``:
    nodes whose cost under ``node_cost`` differs from the key's (e.g. nodes a parallel
    batch already took): computed aside, the kept bounds stay those of the key."""
    tracker = graph.caches.get("bounds")
    fresh = tracker is None or tracker[0] != key
    if changed:  # only the key's own costs may be kept
        values = None if fresh else tracker[1].variant(graph, changed, bounds_local(node_cost))
    else:
        if fresh:
            tracker = graph.caches["bounds"] = (key, IncrementalValues(bounds_local(node_cost)))
        values = tracker[1].values if tracker[1].refresh(graph) else None
    return Bounds(values) if values is not None else path_bounds(graph, node_cost)


def select_path(graph: PolicyGraph, node_cost: NodeCost, max_pops: int = 200_000,
                bounds: Bounds | None = None) -> tuple[float, float, tuple[int, ...]] | None:
    """The uncovered root-to-leaf path with the largest p / ĉ (greedy knapsack, Thm. 1).

    p is the path probability; ĉ the summed estimated refinement cost of the path's
    unrefined nodes (``node_cost``; refined nodes cost 0). Best-first branch and bound:
    a prefix with probability p and cost c, ending at a node whose continuations have
    probability at most u and cost at least r (``bounds``, by default
    :func:`path_bounds`), bounds every completion by p·u / max(c + r, 1). Subtrees with
    nothing uncovered (u = 0) are skipped, and the cost bound leads the search straight
    down long unrefined chains, so it never enumerates the exponentially many paths of a
    large policy (a 12- or 24-level Keva tower, where each feed outcome rejoins the
    chain). Cycles are cut (a path never revisits a node). A greedy dive down the best
    bounds gives the search its first incumbent (``_dive``), so where the pop budget runs
    out first the answer is the best path met, never "nothing left" while something is
    open. Returns (p, ĉ, path), or None when nothing is left.
    """
    b = bounds if bounds is not None else path_bounds(graph, node_cost)
    root = graph.nodes[graph.root]
    c0 = node_cost(root)
    refined = root.refined or root.is_leaf
    u0, r0 = b.open(graph.root) if refined else b.any(graph.root)
    if u0 <= 0.0:
        return None
    best = _dive(graph, node_cost, b, 1.0, c0, refined, (graph.root,))
    # just below the dive's ratio: a path as good, met by the search, still replaces it,
    # so the answer is the one the search alone gives whenever its budget suffices
    best_ratio = best[0] / best[1] * (1.0 - 1e-9) if best is not None else 0.0
    counter = 0
    heap = [(-per_cost(u0, c0 + r0), counter, 1.0, c0, refined, (graph.root,))]
    pops = 0
    while heap and pops < max_pops:
        neg_bound, _, prob, cost, refined_prefix, path = heapq.heappop(heap)
        pops += 1
        if -neg_bound <= best_ratio:
            break
        if graph.nodes[path[-1]].is_leaf:
            found = _uncovered(graph, prob, cost, path)
            if found is not None and prob / cost > best_ratio:
                best, best_ratio = found, prob / cost
            continue
        for neg, p2, c2, still, longer in _extensions(graph, node_cost, b, prob, cost,
                                                      refined_prefix, path):
            counter += 1
            heapq.heappush(heap, (neg, counter, p2, c2, still, longer))
    return best


#: a prefix extended by one child: (-bound, probability, ĉ so far, refined so far, path)
_Extension = tuple[float, float, float, bool, tuple[int, ...]]


def _uncovered(graph: PolicyGraph, prob: float, cost: float,
               path: tuple[int, ...]) -> tuple[float, float, tuple[int, ...]] | None:
    """(p, ĉ, path) for a root-to-leaf ``path`` that is an answer: uncovered, and with a
    finite ĉ > 0 (something left to refine or extend on it)."""
    if path_is_covered(graph, path) or not 0 < cost < INF:
        return None
    return prob, cost, path


def _extensions(graph: PolicyGraph, node_cost: NodeCost, b: Bounds, prob: float,
                cost: float, refined_prefix: bool, path: tuple[int, ...]) -> list[_Extension]:
    """The prefix ``path`` extended by each child with something open below it."""
    out = []
    for e in graph.nodes[path[-1]].edges:
        if e.child in path or e.probability <= 0.0:
            continue
        child = graph.nodes[e.child]
        still = refined_prefix and (child.refined or child.is_leaf)
        u, r = b.open(e.child) if still else b.any(e.child)
        if u <= 0.0:
            continue
        p2, c2 = prob * e.probability, cost + node_cost(child)
        out.append((-per_cost(p2 * u, c2 + r), p2, c2, still, path + (e.child,)))
    return out


def _dive(graph: PolicyGraph, node_cost: NodeCost, b: Bounds, prob: float, cost: float,
          refined_prefix: bool,
          path: tuple[int, ...]) -> tuple[float, float, tuple[int, ...]] | None:
    """A first uncovered path, followed greedily down the best bound from the prefix
    ``path``: the incumbent that prunes the best-first search, and its answer if the pop
    budget runs out first. Where the open mass is spread over exponentially many unlikely
    paths whose bounds are loose (Keva tower-24 seed 6: 0.072 of the mass left below a
    large unrefined subtree, no path above 1.4e-6), the search alone ran out of pops
    before any leaf and the engine took the PRG node for exhausted, backtracking for
    557 s without refining it."""
    while not graph.nodes[path[-1]].is_leaf:
        steps = _extensions(graph, node_cost, b, prob, cost, refined_prefix, path)
        if not steps:
            return None  # only through a node already on the path (a cycle)
        _, prob, cost, refined_prefix, path = min(steps, key=lambda s: s[0])
    return _uncovered(graph, prob, cost, path)
