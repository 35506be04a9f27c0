"""The engine's policy graph: an unrolled abstract policy annotated with refinements.

It starts as the solver's policy tree. Nodes reached with the same abstract state *and*
the same concrete world state (per the world's optional ``fingerprint``) are merged, so
repeating sub-policies are refined once and retry loops become cycles instead of
exponentially deep trees. A node is *refined* when ``sigma`` (the concretization of its
action) is set; its children then know their concrete world state.

Each PRG node owns one graph; :meth:`PolicyGraph.copy` shares the node objects
(copy-on-write: :meth:`PolicyGraph.own` before a change), so UpdateAbstraction never
disturbs the policy of the PRG node it came from, and a run's PRG holds each node once
rather than once per PRG node (aircraft seed 5 grew past 24 GB with private copies).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Iterator, Mapping

from stampc.ir.grounded import Successor
from stampc.refine.incremental import IncrementalValues

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
    #: set by :meth:`PolicyGraph.copy`: this object is shared with another graph and must
    #: not change (:meth:`PolicyGraph.own` gives the graph a private copy to change)
    shared: bool = field(default=False, init=False, compare=False, repr=False)

    def __setattr__(self, name: str, value: Any) -> None:
        if self.__dict__.get("shared"):  # loud: a silent write would change other graphs
            raise AttributeError(f"policy node {self.uid} is shared between graphs: "
                                 "change it through PolicyGraph.own")
        object.__setattr__(self, name, value)

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
    #: per-node values kept between steps, by name: (key, IncrementalValues)
    caches: dict[str, Any] = field(default_factory=dict, repr=False, compare=False)

    def copy(self, *, keep_values: bool = True) -> "PolicyGraph":
        """A copy whose nodes can change independently, through :meth:`own` in either
        graph. The kept values move to the copy (a replan or re-sample of it then updates
        them instead of starting afresh); this graph rebuilds its own if it is used again.
        With ``keep_values=False`` they stay here and the copy starts without (a snapshot
        the engine will not change). Moving, not copying, them keeps one set per run
        rather than one per PRG node (aircraft seed 5: 24 GB after 440 s of CPU)."""
        for node in self.nodes.values():
            if not node.shared:
                node.__dict__["edges"] = tuple(node.edges)  # no in-place edits either
                node.__dict__["shared"] = True
        moved, self.caches = (self.caches, {}) if keep_values else ({}, self.caches)
        return PolicyGraph(self.root, dict(self.nodes), moved)

    def own(self, uid: int) -> Node:
        """Node ``uid``, made this graph's own to change (a private copy if shared)."""
        node = self.nodes[uid]
        if node.shared:
            node = self.nodes[uid] = _copy_node(node)
        return node

    def touch(self, uid: int) -> None:
        """Record that node ``uid`` changed in place (its refinement, leaf kind, action or
        edges), for the values kept in :attr:`caches`; new nodes need no call."""
        for cache in self.caches.values():
            cache[-1].pending.add(uid)

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

    def postorder(self, start: int | None = None) -> tuple[list[int], bool]:
        """uids reachable from ``start`` (default: the root), each after its children
        except where an edge closes a cycle, and whether none does. One sweep in this
        order settles a DAG exactly (outcomes that rejoin, as Keva's feeds do, made a
        reversed-preorder fixed point sweep again, and then once more to confirm)."""
        root = self.root if start is None else start
        seen, on_stack, order, acyclic = {root}, {root}, [], True
        stack = [(root, iter(self.nodes[root].edges))]
        while stack:
            uid, edges = stack[-1]
            for e in edges:
                if e.child not in seen:
                    seen.add(e.child)
                    on_stack.add(e.child)
                    stack.append((e.child, iter(self.nodes[e.child].edges)))
                    break
                acyclic = acyclic and e.child not in on_stack
            else:
                stack.pop()
                on_stack.discard(uid)
                order.append(uid)
        return order, acyclic

    def reaches_leaf(self, start: int) -> bool:
        """Whether some leaf is reachable from ``start`` (breadth first, stopping at the
        first: cheap wherever the answer is yes, the usual case)."""
        seen = {start}
        frontier = [start]
        while frontier:
            nxt = []
            for uid in frontier:
                node = self.nodes[uid]
                if node.is_leaf:
                    return True
                for e in node.edges:
                    if e.child not in seen:
                        seen.add(e.child)
                        nxt.append(e.child)
            frontier = nxt
        return False

    def prune(self) -> None:
        """Drop nodes no longer reachable from the root."""
        nodes = self.nodes
        keep, stack = {self.root}, [self.root]
        while stack:
            for e in nodes[stack.pop()].edges:
                if e.child not in keep:
                    keep.add(e.child)
                    stack.append(e.child)
        if len(keep) < len(nodes):  # else every node is kept: the same dict
            self.nodes = {u: n for u, n in nodes.items() if u in keep}

    def parents(self) -> dict[int, list[int]]:
        result: dict[int, list[int]] = {u: [] for u in self.nodes}
        for uid in self.reachable():
            for e in self.nodes[uid].edges:
                result[e.child].append(uid)
        return result


def adopt(graph: PolicyGraph, target: Node, source: Node) -> Node:
    """Overwrite ``target``'s policy with ``source``'s (keeping uid and concrete state);
    returns the graph's own ``target``."""
    target = graph.own(target.uid)
    graph.touch(target.uid)
    target.state, target.action, target.leaf = source.state, source.action, source.leaf
    target.edges, target.sigma, target.attempts = list(source.edges), None, 0
    target.proven, target.given_up = source.proven, False
    del graph.nodes[source.uid]
    return target


def _copy_node(node: Node) -> Node:
    """An unshared shallow copy with its own edge list (``copy.copy``, ~3x faster)."""
    clone = object.__new__(Node)
    clone.__dict__.update(node.__dict__, edges=list(node.edges), shared=False)
    return clone


# ------------------------------------------------------------------ coverage
def _masses(graph: PolicyGraph, leaf_value: Callable[[Node], tuple[float, ...]],
            refined_only: bool = True, start: int | None = None) -> tuple[float, ...]:
    """Probabilities, from ``start`` (default: the root), of reaching a leaf scored by
    each component of ``leaf_value`` (while staying on refined nodes, with
    ``refined_only``). Iterated to a fixed point so cycles (retry loops) count with their
    true, geometric probability."""
    start = graph.root if start is None else start
    order, acyclic = graph.postorder(start)
    width = len(leaf_value(graph.nodes[order[0]]))
    zero = (0.0,) * width
    value = {u: zero for u in order}
    for _ in range(10_000):
        delta = 0.0
        for uid in order:
            node = graph.nodes[uid]
            if node.is_leaf:
                new = leaf_value(node)
            elif refined_only and not node.refined:
                new = zero
            else:
                new = tuple(sum(e.probability * value[e.child][k] for e in node.edges)
                            for k in range(width))
            delta = max(delta, max(abs(a - b) for a, b in zip(new, value[uid])))
            value[uid] = new
        if acyclic or delta < 1e-12:
            break
    return tuple(min(1.0, v) for v in value[start])


def _mass(graph: PolicyGraph, leaf_value: Callable[[Node], float],
          refined_only: bool = True) -> float:
    return _masses(graph, lambda n: (leaf_value(n),), refined_only)[0]


def coverage(graph: PolicyGraph) -> float:
    """Probability mass of executions that stay on refined branches to a terminal leaf
    (the goal or a proven dead end): goal mass + proven dead-end mass."""
    return _mass(graph, lambda n: 1.0 if n.terminal else 0.0)


def coverage_and_goal(graph: PolicyGraph) -> tuple[float, float]:
    """``(coverage(graph), goal_probability(graph))`` in one fixed-point pass."""
    cov, goal = _masses(graph, lambda n: (1.0 if n.terminal else 0.0,
                                          1.0 if n.leaf == GOAL else 0.0))
    return cov, goal


def tracked_coverage_and_goal(graph: PolicyGraph) -> tuple[float, float]:
    """:func:`coverage_and_goal`, kept on ``graph`` between calls (incremental.py): after
    a step only the touched and new nodes and their ancestors are recomputed."""
    tracked = _tracked_masses(graph)
    if tracked is None:
        return coverage_and_goal(graph)
    cov, goal = tracked[graph.root]
    return min(1.0, cov), min(1.0, goal)


def covered_below(graph: PolicyGraph, uid: int) -> float:
    """The coverage of the policy below ``uid``, as if it were the root: the share of
    the executions reaching ``uid`` that stay on refined nodes to a terminal leaf. Read
    from the tracked masses when the graph is acyclic (no sweep)."""
    tracked = _tracked_masses(graph)
    if tracked is not None and uid in tracked:
        return min(1.0, tracked[uid][0])
    return _masses(graph, lambda n: (1.0 if n.terminal else 0.0,), start=uid)[0]


def _tracked_masses(graph: PolicyGraph) -> Mapping[int, tuple[float, float]] | None:
    """Every node's (coverage, goal) masses, kept on ``graph`` and brought up to date;
    None on a cyclic graph (not kept: incremental.py)."""
    tracker = graph.caches.get("masses")
    if tracker is None:
        tracker = graph.caches["masses"] = (None, IncrementalValues(_coverage_and_goal_local))
    return tracker[1].values if tracker[1].refresh(graph) else None


def _coverage_and_goal_local(node: Node, value: Mapping[int, tuple]) -> tuple[float, float]:
    """One node's (coverage, goal) masses from its children's (as :func:`_masses`)."""
    if node.is_leaf:
        return 1.0 if node.terminal else 0.0, 1.0 if node.leaf == GOAL else 0.0
    if not node.refined:
        return 0.0, 0.0
    return tuple(sum(e.probability * value[e.child][k] for e in node.edges)  # type: ignore[return-value]
                 for k in range(2))


def dead_end_mass(graph: PolicyGraph) -> float:
    """Probability of reaching a *proven* dead end on refined branches."""
    return _mass(graph, lambda n: 1.0 if n.leaf == DEAD_END and n.proven else 0.0)


def goal_probability(graph: PolicyGraph) -> float:
    """Probability of reaching the goal on refined branches only."""
    return _mass(graph, lambda n: 1.0 if n.leaf == GOAL else 0.0)


def abstract_goal_probability(graph: PolicyGraph) -> float:
    """Goal probability of the abstract policy, ignoring refinement."""
    return _mass(graph, lambda n: 1.0 if n.leaf == GOAL else 0.0, refined_only=False)


def count_covered_paths(graph: PolicyGraph) -> int:
    """Number of covered root-to-leaf paths (refined all the way to a goal or a proven
    dead end), by dynamic programming over the graph — linear in its size, where listing
    the paths is exponential (a 12-level Keva policy has 2^24). A path that would revisit
    a node (a retry loop) is cut there: edges back to a node on the depth-first stack are
    not followed (with cycles, a node's count is the one of its first visit, so it can
    differ from :func:`iter_leaf_paths`'s enumeration; on acyclic graphs it is exact)."""
    count: dict[int, int] = {}
    on_stack: set[int] = set()
    stack: list[tuple[int, int]] = [(graph.root, 0)]
    while stack:
        uid, i = stack.pop()
        node = graph.nodes[uid]
        if i == 0:
            if node.is_leaf:
                count[uid] = 1 if node.terminal else 0
                continue
            if not node.refined:
                count[uid] = 0
                continue
            on_stack.add(uid)
        if i < len(node.edges):
            stack.append((uid, i + 1))
            child = node.edges[i].child
            if child not in count and child not in on_stack:
                stack.append((child, 0))
            continue
        on_stack.discard(uid)
        count[uid] = sum(count.get(e.child, 0) for e in node.edges
                         if e.child not in on_stack)
    return count.get(graph.root, 0)


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
    node = graph.own(uid)
    graph.touch(uid)
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
