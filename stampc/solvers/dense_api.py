"""The dense solver (``dense.py``) behind ``solve`` and ``solve_bounded``: when it applies,
and its result as a :class:`~stampc.solvers.solution.Solution`.

It is chosen explicitly (``algorithm="dense"``) or, by ``solve_bounded``, automatically
in place of LAO* when explicit successor enumeration explodes (``dense_choice.py``) and
the model fits the product form within the work budget.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from stampc.diagnostics import Span, StampcError, error
from stampc.ir.grounded import GroundModel
from stampc.solvers.core import Search
from stampc.solvers.dense import DenseResult, TooLarge, dense_solve
from stampc.solvers.factored import FactoredModel, NotFactored, compile_factored
from stampc.solvers.heuristics import make_heuristic
from stampc.solvers.solution import Solution, SolverOptions
from stampc.solvers.space import Space
from stampc.solvers.successors import SuccessorCache

#: Multiply-adds per Bellman sweep at most (SysAdmin p06, 2^16 states: ~2e8).
MAX_WORK = 1e9

__all__ = ["DenseTable", "NotFactored", "TooLarge", "dense_or_error", "solve_dense"]


@dataclass(frozen=True)
class DenseTable:
    """Policy and values of every state of a factored model (``Solution.table``)."""
    model: FactoredModel
    result: DenseResult

    @property
    def n_states(self) -> int:
        return self.model.n_states

    @cached_property
    def _varying(self) -> int:
        return sum(1 << f for f in self.model.facts)

    def _index(self, state: int) -> int | None:
        # once per policy lookup (every simulated step): the mask is computed once
        return None if state & ~self._varying != self.model.base else self.model.index(state)

    def action(self, state: int) -> int | None:
        k = self._index(state)
        if k is None:
            return None  # outside the enumerated space (a constant fact differs)
        a = int(self.result.policy[k])
        return None if a < 0 else a

    def value(self, state: int) -> float:
        k = self._index(state)
        return float("nan") if k is None else float(self.result.values[k])

    def states(self, first: int) -> list[int]:
        """Every state of the space, ``first`` first (the policy's exports list them all:
        a superset of the policy graph, found without enumerating outcomes)."""
        model = self.model
        rest = [model.state(k) for k in range(model.n_states)]
        return [first] + [s for s in rest if s != first]


def solve_dense(model: GroundModel, options: SolverOptions, *, relative: bool = True,
                init: int | None = None) -> tuple[Solution, DenseResult]:
    """Certified dense solve; raises ``NotFactored`` / ``TooLarge`` when it does not fit
    (finite horizons and forbidden actions are not supported: ``NotFactored``)."""
    start = time.perf_counter()
    if options.forbidden or (options.horizon if options.horizon is not None
                             else model.horizon) is not None:
        raise NotFactored("finite horizons and forbidden actions need a search solver")
    deadline = None if options.time_limit is None else start + options.time_limit
    state = model.init if init is None else init
    factored = compile_factored(model, options.unit_cost, init=state)
    result = dense_solve(factored, options.dead_end_cost, options.epsilon, relative,
                         deadline, MAX_WORK)
    cache = SuccessorCache(model, options.unit_cost)
    space = Space(cache, make_heuristic("zero", model, options.unit_cost),
                  options.dead_end_cost)
    solution = Solution(
        init=state, expected_cost=result.lower, goal_probability=result.goal_probability,
        states_expanded=int(np.count_nonzero(~factored.goal)),
        solve_time_s=time.perf_counter() - start,
        converged=result.certified and not result.timed_out, options=options,
        horizon=None, search=Search(space), table=DenseTable(factored, result))
    return solution, result


def dense_or_error(model: GroundModel, options: SolverOptions, *, relative: bool = True,
                   init: int | None = None) -> tuple[Solution, DenseResult]:
    """:func:`solve_dense` for an explicit ``algorithm="dense"``: a model it does not fit
    is an error (S009), not a silent switch to another algorithm."""
    try:
        return solve_dense(model, options, relative=relative, init=init)
    except (NotFactored, TooLarge) as why:
        raise StampcError([error("S009", f"the dense solver does not fit this model: {why}",
                                 Span.point("<solver options>"),
                                 hint="use --algorithm lao (or lrtdp, vi)")]) from None
