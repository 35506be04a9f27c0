"""Reporting in the ATM-MDP engine: the best policy so far, progress events and the
run's result. A mixin of :class:`stampc.refine.engine.Engine` (it reads the engine's PRG,
planner, options and best-policy bookkeeping)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Callable

from stampc.refine.graph import (PolicyGraph, abstract_goal_probability, count_covered_paths,
                                 coverage, dead_end_mass, goal_probability,
                                 tracked_coverage_and_goal)
from stampc.refine.options import ProgressEvent, RefineResult

if TYPE_CHECKING:
    import networkx as nx

    from stampc.refine.options import RefineOptions
    from stampc.refine.planner import AbstractPlanner
    from stampc.refine.recall import FactMemory

THRESHOLDS = (0.5, 0.8, 0.9, 1.0)


class Reporting:
    prg: "nx.DiGraph"
    planner: "AbstractPlanner"
    options: "RefineOptions"
    best: tuple[float, float]
    best_graph: PolicyGraph | None
    best_prg: int
    crossed: dict[str, float | None]
    events: list[ProgressEvent]
    stop_reason: str
    resamples: int
    memory: "FactMemory"
    _notes: list[str]

    #: the engine's clock (``Engine.elapsed``)
    elapsed: "Callable[[], float]"

    def result(self) -> RefineResult:
        graph = self.best_graph
        cov = coverage(graph) if graph else 0.0
        goal = goal_probability(graph) if graph else 0.0
        dead = dead_end_mass(graph) if graph else 0.0
        refined_paths = count_covered_paths(graph) if graph else 0
        return RefineResult(
            coverage=cov,
            goal_probability=goal,
            abstract_goal_probability=abstract_goal_probability(graph) if graph else 0.0,
            wall_time_s=self.elapsed(),
            time_to_coverage=dict(self.crossed),
            prg_nodes=self.prg.number_of_nodes(),
            refined_paths=refined_paths,
            refined_nodes=sum(1 for n in graph.nodes.values() if n.refined) if graph else 0,
            abstract_solves=self.planner.solves,
            seed=self.options.seed,
            stop_reason=self.stop_reason if self.stop_reason != "running" else "interrupted",
            events=tuple(self.events),
            goal_mass=goal, dead_end_mass=dead, unrefined_mass=max(0.0, 1.0 - goal - dead),
            solver_timeouts=self.planner.timeouts, resamples=self.resamples,
            recalled_facts=self.memory.recalled)


    def _track(self, prg_node: int, graph: PolicyGraph) -> None:
        score = tracked_coverage_and_goal(graph)
        if score > self.best:
            self.best, self.best_prg = score, prg_node
            self.best_graph = graph.copy(keep_values=False)
            now = self.elapsed()
            for t in THRESHOLDS:
                if self.crossed[str(t)] is None and score[0] >= t - 1e-9:
                    self.crossed[str(t)] = now

    def _event(self, kind: str, detail: str = "") -> ProgressEvent:
        graph = self.best_graph
        if self._notes:
            detail = f"{detail} [{'; '.join(self._notes)}]" if detail else "; ".join(self._notes)
            self._notes = []
        event = ProgressEvent(
            time_s=self.elapsed(), coverage=max(self.best[0], 0.0),
            goal_probability=max(self.best[1], 0.0),
            refined_nodes=sum(1 for n in graph.nodes.values() if n.refined) if graph else 0,
            prg_nodes=self.prg.number_of_nodes(), abstract_solves=self.planner.solves,
            kind=kind, detail=detail,
            dead_end_mass=max(0.0, self.best[0] - self.best[1]))
        self.events.append(event)
        return event
