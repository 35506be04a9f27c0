"""The anytime refinement engine (ATM-MDP).

``run_refinement`` drives :class:`Engine` on a grounded model and an open world, calling
``on_event`` for each progress event; it always returns the best refined policy found,
also when interrupted (Ctrl-C), stopped by the time limit, or cut short by a bug in the
engine (``RefinedPolicy.error``: the traceback; the run's work is not lost with it).
"""

from __future__ import annotations

import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping

from stampc.diagnostics import StampcError
from stampc.ir.grounded import GroundModel
from stampc.refine.engine import Engine
from stampc.refine.export import policy_json, write_outputs
from stampc.refine.graph import PolicyGraph
from stampc.refine.history import prg_history
from stampc.refine.options import (ProgressEvent, RefineOptions, RefineResult,
                                   check_refine_options, options_record)
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
    #: the traceback when a bug in the engine ended the run (stop reason "internal
    #: error: ..."); ``write`` puts it in error.txt beside the partial policy
    error: str | None = None

    def to_json(self) -> dict:
        if self.graph is None:
            return {}
        return policy_json(self.model, self.graph, self.result, self.initial_values, self.meta)

    def write(self, out_dir: str | Path) -> list[str]:
        """Write the outputs (see ``stampc.refine.export``); returns notes on anything
        shortened to keep writing bounded, e.g. a collapsed policy.svg."""
        if self.graph is None:
            return []
        notes = write_outputs(Path(out_dir), self.model, self.graph, self.result,
                              self.initial_values, self.meta, history=self.history)
        if self.error is not None:
            (Path(out_dir) / "error.txt").write_text(self.error)
        return notes


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
    error = None
    try:
        for event in engine.run():
            if on_event is not None:
                on_event(event)
    except KeyboardInterrupt:
        engine.stop_reason = "interrupted"
    except StampcError:
        raise  # bad input, a failing generator: located diagnostics
    except Exception as exc:  # a bug in the engine: keep what was refined (anytime)
        engine.stop_reason = f"internal error: {_describe(exc)}"
        error = traceback.format_exc()
    result = engine.result()
    return RefinedPolicy(result, engine.best_graph, model, engine.initial_values,
                         {**(meta or {}), "options": options_record(options)},
                         prg_history(engine.prg, result.events, engine.best_prg),
                         error=error)


def _describe(exc: BaseException) -> str:
    try:  # str() itself can fail: a KeyError on a 10,000-digit state
        text = str(exc)
    except ValueError:
        text = "(message not printable)"
    return f"{type(exc).__name__}: {text[:200]}"
