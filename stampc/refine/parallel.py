"""Parallel refinement: the engine dispatches the concretizations of several independent
nodes to workers (``stampc refine --workers N``) and stays the single owner of the PRG,
the policy graphs and every random choice.

Each batch takes the ``N`` best uncovered paths of the current policy whose first
unrefined action can be refined now (its concrete start state is known): the path the
serial engine would take (largest p/ĉ), then the best path avoiding the nodes already
taken, and so on. Their concretizations — generators, ``?`` evaluators, and on success the
executors giving the children's states — run in the workers at the same time. The engine
then integrates the replies one step at a time, **in rank order** (never arrival order),
exactly as the serial engine integrates its own concretization. A reply whose node
changed meanwhile — the policy was re-planned (a new PRG node), the node was merged away,
re-sampled, or its attempt count moved — is *stale*: discarded and counted
(``ParallelStats.discarded``); its node is selected again later if still uncovered.

Determinism: the mode of each concretization (UpdateAbstraction or full backtracking)
comes from ``Random(f"{seed}:mode:{node}:{attempt}")`` and every generator call's RNG from
(seed, node, attempt, generator), so a reply depends only on its task; batches and their
order depend only on the policy; hence the run depends only on the seed and ``N`` (not on
timing, load or which worker answers), up to a time limit cutting it short.
"""

from __future__ import annotations

import math
import random
import time
from collections import deque
from dataclasses import dataclass, replace
from typing import Any, Protocol

from stampc.diagnostics import StampcError
from stampc.ir.grounded import GroundModel
from stampc.refine.engine import Engine
from stampc.refine.graph import Concrete, Node, PolicyGraph, path_values
from stampc.refine.options import RefineOptions, RefineResult
from stampc.refine.workers import WorkReply, WorkTask, handle_task
from stampc.worlds.bindings import ResolvedBindings


class WorkerPool(Protocol):
    size: int

    def ready(self, signature: tuple[int, int]) -> bool: ...
    def submit(self, tasks: list[WorkTask]) -> None: ...
    def collect(self) -> list[WorkReply]: ...
    def close(self) -> None: ...


@dataclass
class ParallelStats:
    """Counters of a parallel run (summary.json ``parallel``)."""

    workers: int
    backend: str
    batches: int = 0
    dispatched: int = 0
    integrated: int = 0
    #: replies made stale by an earlier integration of their batch (the policy changed)
    discarded: int = 0
    #: replies still queued when the run stopped
    unused: int = 0
    #: engine time waiting for a batch's replies, and the workers' summed busy time
    wait_s: float = 0.0
    worker_busy_s: float = 0.0
    #: the batches' critical path: per batch its longest task's time (or of the tasks run
    #: one after another while the workers were starting), a floor for the engine's time
    critical_s: float = 0.0

    def as_dict(self) -> dict[str, Any]:
        return {k: round(v, 4) if isinstance(v, float) else v for k, v in vars(self).items()}


@dataclass(frozen=True)
class _Pending:
    prg_node: int
    graph: PolicyGraph
    path: tuple[int, ...]
    action: int
    attempt: int
    concrete: Concrete
    values: dict
    reply: WorkReply


class ParallelEngine(Engine):
    def __init__(self, model: GroundModel, world: Any, bindings: ResolvedBindings,
                 options: RefineOptions, pool: WorkerPool, backend: str = "local"):
        super().__init__(model, world, bindings, options)
        self.pool = pool
        #: the engine concretizes one node of each batch itself, the pool's workers the rest
        self.workers = pool.size + 1
        self.stats = ParallelStats(self.workers, backend)
        self._queue: deque[_Pending] = deque()

    def _loop(self):
        try:
            yield from super()._loop()
        finally:
            self.stats.unused += len(self._queue)
            self._queue.clear()

    def result(self) -> RefineResult:
        return replace(super().result(), parallel=self.stats.as_dict())

    def step(self) -> tuple[str, str]:
        while self._queue:
            item = self._queue.popleft()
            if self._still_current(item):
                return self._apply(item)
            self.stats.discarded += 1
        graph = self._current_graph()
        selected = self._select(graph)
        first = _refinable_prefix(graph, selected)
        if first is None:  # a horizon leaf to extend, or nothing: the serial step
            return self._act(graph, selected)
        self._dispatch(graph, [first] + self._more_paths(graph, first))
        return self.step()

    def _more_paths(self, graph: PolicyGraph, first: tuple[int, ...]) -> list[tuple[int, ...]]:
        """The next best paths whose first unrefined action is not one already taken."""
        taken = {first[-1]}

        def cost(node: Node) -> float:
            return math.inf if node.uid in taken else self._node_cost(node)

        out: list[tuple[int, ...]] = []
        while len(out) < self.workers - 1:
            path = _refinable_prefix(graph, self._select(graph, cost, changed=taken))
            if path is None or path[-1] in taken:
                break
            taken.add(path[-1])
            out.append(path)
        return out

    def _dispatch(self, graph: PolicyGraph, paths: list[tuple[int, ...]]) -> None:
        tasks, pending = [], []
        deadline = self.concretizer.deadline
        for path in paths:
            node = graph[path[-1]]
            values = path_values(graph, path[:-1], self.initial_values)
            mode = random.Random(f"{self.options.seed}:mode:{node.uid}:{node.attempts}")
            remaining = None if deadline is None else max(0.0, deadline - time.perf_counter())
            tasks.append(WorkTask(
                node.action, node.state, node.concrete.snapshot, dict(node.concrete.cache),
                values, node.uid, node.attempts,
                self._concretize_quickly(node, mode.random()),
                tuple((e.successor, e.outcome) for e in node.edges), remaining))
            pending.append((path, node, values))
        replies = self._run(tasks)
        self.stats.batches += 1
        self.stats.dispatched += len(tasks)
        for (path, node, values), reply in zip(pending, replies):
            if reply.diagnostics:
                raise StampcError(list(reply.diagnostics))
            self.stats.worker_busy_s += reply.busy_s
            self._queue.append(_Pending(self.current, graph, path, node.action, node.attempts,
                                        node.concrete, values, reply))

    def _run(self, tasks: list[WorkTask]) -> list[WorkReply]:
        """The replies to a batch, in task order: the engine answers the first task, the
        workers the others — once they are up. They start with the first batch that has
        work for them (a run without one never pays for them), and until they are ready
        the engine answers the whole batch itself: a reply depends on its task only."""
        rest = tasks[1:]
        beside = bool(rest) and self.pool.ready(self._signature)  # run beside the engine's
        if beside:
            self.pool.submit(rest)
        replies = [handle_task(self.model, self.concretizer, tasks[0])]
        after = bool(rest) and not beside and self.pool.ready(self._signature)  # up meanwhile
        if after:
            self.pool.submit(rest)
        if beside or after:
            start = time.perf_counter()
            replies += self.pool.collect()
            self.stats.wait_s += time.perf_counter() - start
        else:
            replies += [handle_task(self.model, self.concretizer, t) for t in rest]
        times = [r.busy_s for r in replies]  # the critical path: what ran one after another
        self.stats.critical_s += (max(times) if beside else times[0] + max(times[1:]) if after
                                  else sum(times))
        return replies

    @property
    def _signature(self) -> tuple[int, int]:
        """(actions, facts) of the grounded model, which every worker must share."""
        return len(self.model.actions), len(self.model.facts)

    def _still_current(self, item: _Pending) -> bool:
        """Whether the reply still applies: same policy, same unrefined node, same attempt."""
        if self.current != item.prg_node or self.prg.nodes[self.current]["graph"] is not item.graph:
            return False
        graph = item.graph
        if any(u not in graph.nodes for u in item.path):
            return False
        node = graph[item.path[-1]]
        linked = all(any(e.child == b for e in graph[a].edges)
                     for a, b in zip(item.path, item.path[1:]))
        return (linked and not node.refined and node.action == item.action
                and node.attempts == item.attempt and node.concrete is item.concrete)

    def _apply(self, item: _Pending) -> tuple[str, str]:
        self.stats.integrated += 1
        item.concrete.cache.update(item.reply.cache)
        # the work of replies too late to apply is not counted: it refined nothing
        self._account(item.path[-1], item.reply.work)
        return self._integrate(item.graph, item.path, item.reply.result, item.values,
                               item.reply.snapshots)


def _refinable_prefix(graph: PolicyGraph, selected) -> tuple[int, ...] | None:
    """The selected path up to its first unrefined action (None: it ends at a leaf first)."""
    if selected is None:
        return None
    path = selected[2]
    for i, uid in enumerate(path):
        node = graph[uid]
        if node.is_leaf:
            return None
        if not node.refined:
            return path[: i + 1]
    return None
