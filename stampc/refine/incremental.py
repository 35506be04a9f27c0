"""Per-node values of a policy graph, kept up to date between the engine's steps.

Both of the engine's bookkeeping passes — the path-selection bounds (selection.py) and
the coverage / goal-probability masses (graph.py) — give every node a value that is a
function of the node and its children's values. On an acyclic graph one sweep, children
first, settles them all; after a step only the nodes the step changed and their
ancestors can change. :class:`IncrementalValues` keeps the values of one graph and, on
:meth:`~IncrementalValues.refresh`, recomputes exactly those — the nodes marked with
:meth:`PolicyGraph.touch` (changed in place), every node it has no value for (new), and
their ancestors — children first, with the same function, so the values are the ones a
sweep from scratch gives, bit for bit.

Cyclic graphs (retry loops) are not kept: their values are Gauss-Seidel fixed points that
depend on the sweep order, so the caller computes them from scratch (``refresh`` returns
False), as before.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Callable, Iterable

if TYPE_CHECKING:
    from stampc.refine.graph import Node, PolicyGraph

#: a node's value from the node and the values computed so far (its children's included)
Local = Callable[["Node", dict[int, Any]], Any]


class IncrementalValues:
    """The values of ``local`` over one policy graph (attached to it: ``graph.caches``)."""

    def __init__(self, local: Local):
        self.local = local
        self.values: dict[int, Any] = {}
        #: nodes changed in place since the last refresh (PolicyGraph.touch)
        self.pending: set[int] = set()
        self._children: dict[int, tuple[int, ...]] = {}
        #: frozen, so that a copy can share them
        self._parents: dict[int, frozenset[int]] = {}
        self._acyclic: bool | None = None  # None: not built yet
        #: nodes with more than one parent (where branches of the policy meet again)
        self._merged: set[int] = set()

    def refresh(self, graph: "PolicyGraph") -> bool:
        """Bring the values up to date with ``graph``; False if it has a cycle (then no
        values are kept)."""
        if self._acyclic is None:
            return self._build(graph)
        if not self._acyclic:
            return False
        nodes = graph.nodes
        if len(self._children) > 2 * len(nodes) + 1000:
            self._forget_all_but(nodes.keys())
        changed = (self.pending | (nodes.keys() - self._children.keys())) & nodes.keys()
        self.pending = set()
        if not changed:
            return True
        for uid in changed:
            self._relink(uid, nodes[uid])
        affected = self.ancestors(changed, graph)
        order = self._children_first(affected, graph)
        if order is None:  # the change closed a cycle (or left a dangling edge)
            return self._build(graph)
        for uid in order:
            self.values[uid] = self.local(nodes[uid], self.values)
        return True

    def variant(self, graph: "PolicyGraph", changed: Iterable[int], local: Local) -> dict | None:
        """The values ``local`` gives when it differs from the kept function only on the
        ``changed`` nodes' own values (e.g. their cost): those nodes and their ancestors
        are computed into a copy, the kept values stay. None on a cyclic graph."""
        if not self.refresh(graph):
            return None
        affected = self.ancestors({u for u in changed if u in graph.nodes}, graph)
        order = self._children_first(affected, graph)
        if order is None:
            return None
        values = dict(self.values)
        for uid in order:
            values[uid] = local(graph.nodes[uid], values)
        return values

    def merges(self, graph: "PolicyGraph") -> bool:
        """Whether some node of ``graph`` has several parents in it (as of the last
        refresh; a parent pruned from the graph no longer counts)."""
        nodes = graph.nodes
        return any(uid in nodes and sum(p in nodes for p in self._parents[uid]) > 1
                   for uid in self._merged)

    def ancestors(self, uids: set[int], graph: "PolicyGraph") -> set[int]:
        """``uids`` and every node above them (parents as of the last refresh)."""
        seen = set(uids)
        stack = list(uids)
        while stack:
            for parent in self._parents.get(stack.pop(), ()):
                if parent not in seen and parent in graph.nodes:
                    seen.add(parent)
                    stack.append(parent)
        return seen

    def _build(self, graph: "PolicyGraph") -> bool:
        order, acyclic = graph.postorder()
        self.pending = set()
        self._acyclic = acyclic
        self.values, self._children, self._parents = {}, {}, {}
        self._merged = set()
        if not acyclic:
            return False
        for uid in order:
            node = graph.nodes[uid]
            self._relink(uid, node)
            self.values[uid] = self.local(node, self.values)
        return True

    def _forget_all_but(self, live) -> None:
        """Drop what is kept for nodes no longer in the graph: pruned and detached nodes
        would otherwise pile up over a run (uids are never reused, so nothing is lost)."""
        self.values = {u: v for u, v in self.values.items() if u in live}
        self._children = {u: c for u, c in self._children.items() if u in live}
        self._parents = {u: p for u, p in self._parents.items() if u in live}
        self._merged &= self._parents.keys()

    def _relink(self, uid: int, node: "Node") -> None:
        """Record ``node``'s current children (and it as their parent)."""
        old = self._children.get(uid, ())
        new = self._children[uid] = tuple(e.child for e in node.edges)
        if new == old:
            return
        parents = self._parents
        for child in set(old) - set(new):
            parents[child] = parents.get(child, frozenset()) - {uid}
            if len(parents[child]) < 2:
                self._merged.discard(child)
        for child in set(new) - set(old):
            parents[child] = parents.get(child, frozenset()) | {uid}
            if len(parents[child]) > 1:
                self._merged.add(child)

    def _children_first(self, affected: set[int], graph: "PolicyGraph") -> list[int] | None:
        """``affected`` ordered children first (Kahn), or None when they contain a cycle
        or a child with neither a kept value nor a place in ``affected``."""
        nodes, values = graph.nodes, self.values
        waiting: dict[int, int] = {}
        ready: list[int] = []
        for uid in affected:
            kids = set(self._children[uid])
            if any(c not in nodes or (c not in affected and c not in values) for c in kids):
                return None
            waiting[uid] = len(kids & affected)
            if not waiting[uid]:
                ready.append(uid)
        order: list[int] = []
        while ready:
            uid = ready.pop()
            order.append(uid)
            for parent in self._parents.get(uid, ()):
                if parent in waiting:
                    waiting[parent] -= 1
                    if not waiting[parent]:
                        ready.append(parent)
        return order if len(order) == len(affected) else None
