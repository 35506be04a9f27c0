"""Backtracking in the ATM-MDP engine: over refined ancestors (Alg. 1's re-sampling of
earlier generator values, with the bans it lifts) and over the PRG (iterative
broadening). A mixin of :class:`stampc.refine.engine.Engine`, kept apart so that each
file reads in one sitting; it uses the engine's PRG, planner, options and uid counter."""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable, Iterator

from stampc.refine.graph import Node, PolicyGraph, detach_subtree

if TYPE_CHECKING:
    import networkx as nx

    from stampc.ir.grounded import GroundModel
    from stampc.refine.options import RefineOptions
    from stampc.refine.planner import AbstractPlanner


class Backtracking:
    prg: "nx.DiGraph"
    planner: "AbstractPlanner"
    options: "RefineOptions"
    current: int
    breadth: int
    resamples: int
    model: "GroundModel"
    uids: "Iterator[int]"
    _bans: dict[tuple[int, int], int]
    #: the engine's best-policy bookkeeping (``Engine._track``)
    _track: "Callable[[int, PolicyGraph], None]"

    def _resample_target(self, graph: PolicyGraph, path: tuple[int, ...]) -> Node | None:
        """The refined ancestor (with generated values) re-sampled least often so far,
        the nearest among equals: which earlier choice blocks the failing action is not
        known, so the re-draws are spread over the ancestors instead of exhausting the
        nearest one first (tried: nearest-first did worse on Keva tower-12 seed 2, coverage
        0.24 vs 0.99 in 240-300 s)."""
        candidates = [graph[u] for u in reversed(path[:-1])
                      if graph[u].refined and graph[u].sigma
                      and graph[u].resamples < self.options.max_resamples]
        return min(candidates, key=lambda n: n.resamples) if candidates else None

    def _resample(self, graph: PolicyGraph, ancestor: Node, failed: Node) -> tuple[str, str]:
        """Backtrack: draw fresh generator values for ``ancestor``. Every refinement below
        it is invalidated (its subtree becomes an unrefined copy); a new PRG node records
        the step."""
        self._lift_bans(graph.reachable(ancestor.uid))
        new_graph = graph.copy()
        target = new_graph[ancestor.uid]
        target.sigma = None
        target.attempts += 1  # the next concretization draws from fresh generator streams
        target.resamples += 1
        detach_subtree(new_graph, target.uid, self.uids)
        self.resamples += 1
        v = self.prg.number_of_nodes()
        self.prg.add_node(v, graph=new_graph, parent=self.current, failed=False)
        self.prg.add_edge(self.current, v, node=ancestor.uid, kind="resample",
                          failed_node=failed.uid, failed_preconditions=[],
                          concretization=sorted(map(str, (ancestor.sigma or {}).keys())))
        self.current = v
        self._track(v, new_graph)
        label = self.model.actions[ancestor.action].label
        return "resample", (f"{label}: new generator values (no refinement of "
                            f"{self.model.actions[failed.action].label} below it)")

    def _lift_bans(self, invalidated) -> None:
        """Bans recorded at nodes whose concrete state a re-sample invalidates came from
        the old generator values: the action may work from the new ones."""
        gone = set(invalidated)
        for key, uid in list(self._bans.items()):
            if uid in gone:
                self.planner.forbidden.discard(key)
                del self._bans[key]

    def _backtrack(self, uid: int | None) -> tuple[str, str]:
        """Iterative broadening: return to the deepest PRG ancestor with spare breadth
        (never to one found exhausted)."""
        u = self.current
        while u is not None:
            graph = self.prg.nodes[u]["graph"]
            if uid is not None and uid in graph.nodes:
                graph[uid].attempts += 1  # next visit draws fresh samples
            if self.prg.out_degree(u) < self.breadth and not self.prg.nodes[u].get("exhausted"):
                self.current = u
                return "backtrack", f"to PRG node {u}"
            u = self.prg.nodes[u]["parent"]
        self.breadth += self.options.breadth_step
        self.current = 0
        return "backtrack", f"breadth {self.breadth}"

