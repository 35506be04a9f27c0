"""The engine's policy graph: an unrolled abstract policy annotated with refinements.

It starts as the solver's policy tree. Nodes reached with the same abstract state *and*
the same concrete world state (per the world's optional ``fingerprint``) are merged, so
repeating sub-policies are refined once and retry loops become cycles instead of
exponentially deep trees. A node is *refined* when ``sigma`` (the concretization of its
action) is set; its children then know their concrete world state.

Each PRG node owns one graph; :meth:`PolicyGraph.copy` is cheap (records are copied
shallowly) so UpdateAbstraction never disturbs the policy of the PRG node it came from.
"""

from __future__ import annotations

import copy
import heapq
from dataclasses import dataclass, field
from typing import Any, Callable, Iterator, Mapping

from stampc.ir.grounded import Successor

GOAL, DEAD_END, HORIZON = "goal", "dead_end", "horizon"


@dataclass(frozen=True)
class Concrete:
    """A concrete world snapshot plus a scratch cache that lives as long as the snapshot."""

    snapshot: Any
    #: the world's fingerprint of the snapshot (None if the world cannot merge states)
    key: Any = None
    cache: dict = field(default_factory=dict, compare=False, hash=False)


@dataclass(frozen=True)
class Edge:
    probability: float
    outcome: int
    successor: Successor
    child: int  # uid


@dataclass
class Node:
    uid: int
    state: int
    depth: int
    action: int | None = None
    leaf: str | None = None
    edges: list[Edge] = field(default_factory=list)
    sigma: Mapping[str, Any] | None = None
    concrete: Concrete | None = None
    learned: tuple[tuple[int, bool], ...] = ()
    attempts: int = 0
    #: dead-end leaves only: the goal is provably unreachable from here (deadends.py);
    #: an unproven one is a give-up and does not count as covered
    proven: bool = False
    #: dead-end leaves only: replanning from here found no way out either; not selected
    #: again (its mass stays unrefined)
    given_up: bool = False
    #: times this node's generator values were re-drawn by backtracking from below
    resamples: int = 0

    @property
    def refined(self) -> bool:
        return self.sigma is not None

    @property
    def is_leaf(self) -> bool:
        return self.action is None

    @property
    def terminal(self) -> bool:
        """A leaf whose mass counts as covered: the goal or a proven dead end."""
        return self.leaf == GOAL or (self.leaf == DEAD_END and self.proven)


@dataclass
class PolicyGraph:
    root: int
    nodes: dict[int, Node]

    def copy(self) -> "PolicyGraph":
        return PolicyGraph(self.root, {u: _copy_node(n) for u, n in self.nodes.items()})

    def __getitem__(self, uid: int) -> Node:
        return self.nodes[uid]

    def reachable(self, start: int | None = None) -> list[int]:
        """uids reachable from ``start`` (default: the root) in depth-first preorder."""
        seen: set[int] = set()
        order: list[int] = []
        stack = [self.root if start is None else start]
        while stack:
            uid = stack.pop()
            if uid in seen:
                continue
            seen.add(uid)
            order.append(uid)
            stack.extend(e.child for e in reversed(self.nodes[uid].edges))
        return order

    def prune(self) -> None:
        """Drop nodes no longer reachable from the root."""
        keep = set(self.reachable())
        self.nodes = {u: n for u, n in self.nodes.items() if u in keep}

    def parents(self) -> dict[int, list[int]]:
        result: dict[int, list[int]] = {u: [] for u in self.nodes}
        for uid in self.reachable():
            for e in self.nodes[uid].edges:
                result[e.child].append(uid)
        return result


def _copy_node(node: Node) -> Node:
    clone = copy.copy(node)
    clone.edges = list(node.edges)
    return clone


# ------------------------------------------------------------------ coverage
def _mass(graph: PolicyGraph, leaf_value: Callable[[Node], float],
          refined_only: bool = True) -> float:
    """Probability, from the root, of reaching a leaf scored by ``leaf_value`` (while
    staying on refined nodes, with ``refined_only``). Iterated to a fixed point so cycles
    (retry loops) count with their true, geometric probability."""
    order = graph.reachable()
    value = {u: 0.0 for u in order}
    for _ in range(10_000):
        delta = 0.0
        for uid in reversed(order):
            node = graph.nodes[uid]
            if node.is_leaf:
                new = leaf_value(node)
            elif refined_only and not node.refined:
                new = 0.0
            else:
                new = sum(e.probability * value[e.child] for e in node.edges)
            delta = max(delta, abs(new - value[uid]))
            value[uid] = new
        if delta < 1e-12:
            break
    return min(1.0, value[graph.root])


def coverage(graph: PolicyGraph) -> float:
    """Probability mass of executions that stay on refined branches to a terminal leaf
    (the goal or a proven dead end): goal mass + proven dead-end mass."""
    return _mass(graph, lambda n: 1.0 if n.terminal else 0.0)


def dead_end_mass(graph: PolicyGraph) -> float:
    """Probability of reaching a *proven* dead end on refined branches."""
    return _mass(graph, lambda n: 1.0 if n.leaf == DEAD_END and n.proven else 0.0)


def goal_probability(graph: PolicyGraph) -> float:
    """Probability of reaching the goal on refined branches only."""
    return _mass(graph, lambda n: 1.0 if n.leaf == GOAL else 0.0)


def abstract_goal_probability(graph: PolicyGraph) -> float:
    """Goal probability of the abstract policy, ignoring refinement."""
    return _mass(graph, lambda n: 1.0 if n.leaf == GOAL else 0.0, refined_only=False)


# ------------------------------------------------------------ path selection
def path_is_covered(graph: PolicyGraph, path: tuple[int, ...]) -> bool:
    leaf = graph.nodes[path[-1]]
    return leaf.terminal and all(graph.nodes[u].refined for u in path[:-1])


def open_bounds(graph: PolicyGraph) -> dict[int, float]:
    """For every node, an upper bound on the probability (from that node) of its most
    likely *uncovered* continuation: 0 where everything below is covered (or given up,
    never selectable), 1 at an unrefined node or an open leaf, else the best edge
    probability × child bound. A max-product fixed point, so cycles converge (every loop
    multiplies by a probability < 1) — and covered subtrees are never searched."""
    order = graph.reachable()
    bound = {u: 0.0 for u in order}
    for _ in range(10_000):
        changed = False
        for uid in reversed(order):
            node = graph.nodes[uid]
            if node.is_leaf:
                new = 0.0 if node.terminal or node.given_up else 1.0
            elif not node.refined:
                new = 1.0
            else:
                new = max((e.probability * bound[e.child] for e in node.edges), default=0.0)
            if new > bound[uid] + 1e-15:
                bound[uid], changed = new, True
        if not changed:
            break
    return bound


def select_path(graph: PolicyGraph, node_cost: Callable[[Node], float],
                max_pops: int = 200_000) -> tuple[float, float, tuple[int, ...]] | None:
    """The uncovered root-to-leaf path with the largest p / ĉ (greedy knapsack, Thm. 1).

    p is the path probability; ĉ the summed estimated refinement cost of the path's
    unrefined nodes (``node_cost``; refined nodes cost 0). Best-first branch and bound:
    a prefix with probability p, cost c, ending at a node whose best uncovered
    continuation has probability at most u (:func:`open_bounds`) bounds every completion
    by p·u / max(c, 1), since an uncovered path costs at least one unit; subtrees with
    u = 0 (all covered) are skipped, so the search never enumerates the exponentially
    many refined paths of a large policy (a 12-level Keva tower). Cycles are cut (a path
    never revisits a node). Returns (p, ĉ, path), or None when everything is covered.
    """
    bounds = open_bounds(graph)
    if bounds.get(graph.root, 0.0) <= 0.0:
        return None
    counter = 0
    heap: list[tuple[float, int, float, float, tuple[int, ...]]] = []
    c0 = node_cost(graph.nodes[graph.root])
    heapq.heappush(heap, (-bounds[graph.root] / max(c0, 1.0), counter, 1.0, c0, (graph.root,)))
    best: tuple[float, float, tuple[int, ...]] | None = None
    best_ratio = 0.0
    pops = 0
    while heap and pops < max_pops:
        neg_bound, _, prob, cost, path = heapq.heappop(heap)
        pops += 1
        if -neg_bound <= best_ratio:
            break
        node = graph.nodes[path[-1]]
        if node.is_leaf:
            if not path_is_covered(graph, path) and cost > 0:
                ratio = prob / cost
                if ratio > best_ratio:
                    best, best_ratio = (prob, cost, path), ratio
            continue
        # below an unrefined node every continuation is uncovered: the bounds (which
        # assume a refined prefix) apply only while the prefix is refined
        prefix_refined = node.refined and cost == 0.0
        for e in node.edges:
            u = bounds.get(e.child, 0.0) if prefix_refined else 1.0
            if e.child in path or e.probability <= 0.0 or u <= 0.0:
                continue
            child = graph.nodes[e.child]
            p2, c2 = prob * e.probability, cost + node_cost(child)
            counter += 1
            heapq.heappush(heap, (-p2 * u / max(c2, 1.0), counter, p2, c2, path + (e.child,)))
    return best


def iter_leaf_paths(graph: PolicyGraph, limit: int = 100_000) -> Iterator[tuple[float, tuple[int, ...]]]:
    """Acyclic root-to-leaf paths with probabilities (for tests and small graphs)."""
    stack: list[tuple[float, tuple[int, ...]]] = [(1.0, (graph.root,))]
    produced = 0
    while stack and produced < limit:
        prob, path = stack.pop()
        node = graph.nodes[path[-1]]
        if node.is_leaf:
            produced += 1
            yield prob, path
            continue
        for e in reversed(node.edges):
            if e.child not in path:
                stack.append((prob * e.probability, path + (e.child,)))


def path_values(graph: PolicyGraph, path: tuple[int, ...],
                initial: Mapping[str, Any]) -> dict[str, Any]:
    """Concrete values of the symbols bound along ``path`` (the nearest binding wins)."""
    values = dict(initial)
    for uid in path:
        sigma = graph.nodes[uid].sigma
        if sigma:
            values.update(sigma)
    return values


def detach_subtree(graph: PolicyGraph, uid: int, uids: Iterator[int]) -> None:
    """Give node ``uid`` an unrefined private copy of the policy below it.

    Backtracking over a refined ancestor invalidates every refinement below it (its
    children's concrete states came from its old values). Nodes below it may also be
    shared with other branches (merged concrete states), so they are copied, not reset:
    the other branches keep their refinements. The copies keep abstract states, actions
    and learned facts; sigma, concrete states and attempt counts start afresh."""
    node = graph.nodes[uid]
    clones: dict[int, int] = {}
    order: list[int] = []
    stack = [e.child for e in node.edges]
    while stack:
        u = stack.pop()
        if u in clones:
            continue
        clones[u] = next(uids)
        order.append(u)
        stack.extend(e.child for e in graph.nodes[u].edges)
    for u in order:
        old = graph.nodes[u]
        graph.nodes[clones[u]] = Node(clones[u], old.state, old.depth, action=old.action,
                                      leaf=old.leaf, learned=old.learned, proven=old.proven,
                                      edges=[_retarget(e, clones) for e in old.edges])
    node.edges = [_retarget(e, clones) for e in node.edges]
    graph.prune()


def _retarget(edge: Edge, clones: Mapping[int, int]) -> Edge:
    return Edge(edge.probability, edge.outcome, edge.successor, clones.get(edge.child, edge.child))
