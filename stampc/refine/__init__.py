"""The anytime refinement engine (ATM-MDP).

``run_refinement`` drives :class:`Engine` on a grounded model and an open world, calling
``on_event`` for each progress event; it always returns the best refined policy found,
also when interrupted (Ctrl-C) or stopped by the time limit.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping

from stampc.ir.grounded import GroundModel
from stampc.refine.engine import Engine
from stampc.refine.export import policy_json, write_outputs
from stampc.refine.graph import PolicyGraph
from stampc.refine.history import prg_history
from stampc.refine.options import ProgressEvent, RefineOptions, RefineResult, check_refine_options
from stampc.worlds.bindings import ResolvedBindings

__all__ = ["Engine", "ProgressEvent", "RefineOptions", "RefineResult", "RefinedPolicy",
           "run_refinement"]


@dataclass(frozen=True)
class RefinedPolicy:
    """The outcome of a refinement run: result figures plus the best policy graph."""

    result: RefineResult
    graph: PolicyGraph | None
    model: GroundModel
    initial_values: Mapping[str, Any]
    meta: Mapping[str, Any] = field(default_factory=dict)
    #: the PRG's revisions and the progress events (``stampc.refine.history``): prg.json
    history: Mapping[str, Any] | None = None

    def to_json(self) -> dict:
        if self.graph is None:
            return {}
        return policy_json(self.model, self.graph, self.result, self.initial_values, self.meta)

    def write(self, out_dir: str | Path) -> list[str]:
        """Write the outputs (see ``stampc.refine.export``); returns notes on anything
        shortened to keep writing bounded, e.g. a collapsed policy.svg."""
        if self.graph is None:
            return []
        return write_outputs(Path(out_dir), self.model, self.graph, self.result,
                             self.initial_values, self.meta, history=self.history)


def run_refinement(model: GroundModel, world: Any, bindings: ResolvedBindings,
                   options: RefineOptions = RefineOptions(), *,
                   on_event: Callable[[ProgressEvent], None] | None = None,
                   meta: Mapping[str, Any] | None = None,
                   pool: Any = None, backend: str = "local") -> RefinedPolicy:
    """Refine; with ``pool`` (``stampc.refine.workers``), concretizations run in its
    workers (``stampc.refine.parallel``)."""
    check_refine_options(options)
    if pool is None:
        engine = Engine(model, world, bindings, options)
    else:
        from stampc.refine.parallel import ParallelEngine
        engine = ParallelEngine(model, world, bindings, options, pool, backend)
    try:
        for event in engine.run():
            if on_event is not None:
                on_event(event)
    except KeyboardInterrupt:
        engine.stop_reason = "interrupted"
    result = engine.result()
    return RefinedPolicy(result, engine.best_graph, model, engine.initial_values,
                         dict(meta or {}), prg_history(engine.prg, result.events, engine.best_prg))
