"""``solve``: option checking, warm starts and algorithm dispatch."""

from __future__ import annotations

import copy
import math
import time
from dataclasses import replace
from typing import Callable

from stampc.diagnostics import Span, StampcError, error
from stampc.ir.grounded import GroundModel
from stampc.solvers.core import Search, SolverTimeout
from stampc.solvers.heuristic_choice import make_heuristic
from stampc.solvers.heuristics import HEURISTICS
from stampc.solvers.lao import lao
from stampc.solvers.lrtdp import lrtdp
from stampc.solvers.solution import ALGORITHMS, Solution, SolverOptions
from stampc.solvers.space import Space, banned_everywhere
from stampc.solvers.successors import SuccessorCache
from stampc.solvers.vi import value_iteration

_OPTIONS_SPAN = Span.point("<solver options>")


def check_options(options: SolverOptions) -> None:
    """Raise ``StampcError`` (codes S0xx) for option values no solver accepts."""
    problems = []
    if options.algorithm not in ALGORITHMS:
        problems.append(error("S001", f"unknown algorithm {options.algorithm!r}", _OPTIONS_SPAN,
                              hint=f"choose one of {', '.join(ALGORITHMS)}"))
    if options.heuristic not in HEURISTICS:
        problems.append(error("S002", f"unknown heuristic {options.heuristic!r}", _OPTIONS_SPAN,
                              hint=f"choose one of {', '.join(HEURISTICS)}"))
    if not (options.epsilon > 0 and math.isfinite(options.epsilon)):
        problems.append(error("S003", f"epsilon must be a positive number, got {options.epsilon}",
                              _OPTIONS_SPAN))
    if not (options.dead_end_cost > 0 and math.isfinite(options.dead_end_cost)):
        problems.append(error("S004", "dead-end cost must be a positive finite number, "
                                      f"got {options.dead_end_cost}", _OPTIONS_SPAN))
    if options.horizon is not None and options.horizon < 0:
        problems.append(error("S005", f"horizon must be >= 0, got {options.horizon}", _OPTIONS_SPAN))
    if not (options.weight >= 1.0 and options.weight < float("inf")):
        problems.append(error("S008", f"heuristic weight must be a finite number >= 1, "
                              f"got {options.weight}", _OPTIONS_SPAN))
    if not 0.0 <= options.prune_probability < 1.0:  # also refuses nan
        problems.append(error("S010", "prune probability must be in [0, 1), got "
                              f"{options.prune_probability}", _OPTIONS_SPAN,
                              hint="0 plans every outcome; see docs/refine.md"))
    if options.time_limit is not None and not options.time_limit > 0:
        problems.append(error("S006", f"time limit must be positive, got {options.time_limit}",
                              _OPTIONS_SPAN))
    if options.work_limit is not None and not options.work_limit > 0:
        problems.append(error("S006", f"work limit must be positive, got {options.work_limit}",
                              _OPTIONS_SPAN))
    if problems:
        raise StampcError(problems)


def _compatible(warm: Solution, model: GroundModel, options: SolverOptions,
                horizon: int | None) -> bool:
    """Can ``warm``'s tables seed a solve of ``model`` with ``options``?

    Values stay admissible lower bounds when the cost convention, dead-end cost, horizon
    and heuristic are unchanged and no previously banned action is allowed again (banning
    more actions can only raise optimal values).
    """
    w = warm.options
    return (warm.search is not None and warm.search.space.cache.model is model
            and w.unit_cost == options.unit_cost and w.dead_end_cost == options.dead_end_cost
            and warm.horizon == horizon and w.heuristic == options.heuristic
            and w.weight == options.weight and w.symmetry == options.symmetry
            and w.relevance == options.relevance
            and w.forbidden <= options.forbidden)


def _transfer(warm: Solution, learned: tuple[int, int]):
    """Initial estimates for nodes that differ from ``warm``'s only by learned facts.

    ``learned`` = (facts learned true, facts learned false). A node of the new search
    maps to the node with those facts reverted; if ``warm`` had *expanded* that node, its
    backed-up value is a far better estimate than the heuristic — exact wherever the
    learned facts do not matter (other cans, other branches), a lower bound where they
    only remove options (a learned obstruction). Only expanded nodes are used: their
    values are backed up, an unexpanded one is just its heuristic."""
    true_mask, false_mask = learned
    values, expanded = warm.search.V, warm.search.expanded

    def lookup(node: int) -> float | None:
        old = (node & ~true_mask) | false_mask
        if old != node and old in expanded:
            return values.get(old)
        return None

    return lookup


def _symmetry(model: GroundModel, options: SolverOptions):
    """The interchangeable object classes when ``options.symmetry`` applies, else None."""
    if not options.symmetry or options.forbidden:
        return None
    from stampc.solvers.symmetry import find_symmetry
    return find_symmetry(model) or None


def _relevance(model: GroundModel, options: SolverOptions):
    """The irrelevant-fact reduction when ``options.relevance`` applies, else None."""
    if not options.relevance:
        return None
    from stampc.solvers.relevance import find_relevance
    return find_relevance(model)


def _make_h(model: GroundModel, options: SolverOptions):
    """The search heuristic, relaxing the model *without* the actions banned in every
    state: a state whose every relaxed way to the goal needs one of them is then a
    recognised dead end (cost D, never expanded) instead of the root of a search that
    must enumerate everything reachable to find no goal (cluttered-25 seed 5: a pick
    banned everywhere left two obstruction locks as the only ways on; its re-solves ran
    to their caps, 180-440 s each, over 500,000+ states). Bans in one state only cannot
    enter a relaxation, which forgets states."""
    banned = banned_everywhere(options.forbidden)
    if banned:
        model = replace(model, actions=tuple(a for a in model.actions if a.index not in banned))
    return make_heuristic(options.heuristic, model, options.unit_cost, options.weight)


def _make_search(model: GroundModel, options: SolverOptions, horizon: int | None,
                 warm: Solution | None, learned: tuple[int, int] | None = None) -> Search:
    if warm is not None and _compatible(warm, model, options, horizon):
        old = warm.search
        transfer = _transfer(warm, learned) if learned and any(learned) else None
        if warm.options.forbidden == options.forbidden:
            # Same transitions: continue from a copy of the whole table set.
            space = copy.copy(old.space)
            space.transfer, space.transferred = transfer, 0
            search = Search(space, options.time_limit, options.work_limit)
            search.V = dict(old.V)
            search.best = dict(old.best)
            search.terminal = set(old.terminal)
            search.expanded = dict(old.expanded)
            search.guide = old.guide
            return search
        cache, h = old.space.cache, old.space.h
        if banned_everywhere(warm.options.forbidden) != banned_everywhere(options.forbidden):
            h = _make_h(model, options)
        warm_values = dict(old.V)
    else:
        cache = SuccessorCache(model, options.unit_cost, _symmetry(model, options),
                               _relevance(model, options))
        h = _make_h(model, options)
        warm_values = transfer = None
    guide = steps = None
    if horizon is not None:
        steps = h if options.unit_cost and options.heuristic == "hmax" else \
            make_heuristic("hmax", model, True)
        if options.algorithm not in ("vi", "tvi"):  # VI enumerates everything: no guide
            guide = Search(Space(cache, h, options.dead_end_cost, None, options.forbidden))
    space = Space(cache, h, options.dead_end_cost, horizon, options.forbidden,
                  warm=warm_values, guide=guide.V if guide else None, steps=steps)
    space.transfer = transfer
    search = Search(space, options.time_limit, options.work_limit)
    search.guide = guide
    return search


def _run_guide(search: Search, state: int, epsilon: float) -> None:
    """Solve the stationary SSP from ``state`` (LAO*) to seed a finite-horizon search."""
    guide = search.guide
    if guide is None:
        return
    guide.deadline, guide.work_limit = search.deadline, search.work_limit
    lao(guide, state, epsilon)


def solve(model: GroundModel, options: SolverOptions = SolverOptions(), *,
          init: int | None = None, warm: Solution | None = None,
          learned: tuple[int, int] | None = None,
          stop: Callable[[Search, int], bool] | None = None) -> Solution:
    """Solve the SSP of ``model`` from ``init`` (default ``model.init``).

    ``warm`` reuses the value tables of a previous solution on the same model where they
    are still valid lower bounds (see :func:`_compatible`), which makes re-solving from a
    state with newly learned facts cheap. ``learned`` = (facts learned true, facts
    learned false) since ``warm`` was computed: nodes that differ from ``warm``'s
    expanded nodes only by them start from those nodes' values (see :func:`_transfer`).
    ``stop(search, node)``, asked by LAO* after each pass, ends the search early (counted
    as converged: the caller has its own criterion, e.g. a certified gap).
    """
    check_options(options)
    if options.algorithm == "dense":  # every state at once (dense.py): no search tables
        from stampc.solvers.dense_api import dense_or_error
        return dense_or_error(model, options, init=init)[0]
    start = time.perf_counter()
    horizon = options.horizon if options.horizon is not None else model.horizon
    search = _make_search(model, options, horizon, warm, learned)
    if stop is not None:
        search.stop = lambda x: stop(search, x)
    state = model.init if init is None else init
    x0 = search.space.node(state, 0)
    guide_before = len(search.guide.expanded) if search.guide else 0
    expanded_before = len(search.expanded) + guide_before
    converged = True
    # the root always gets its heuristic value: a carried-over estimate would hide a
    # root the relaxation recognises as a dead end at once
    carried, search.space.transfer = search.space.transfer, None
    search.seed(x0)
    search.space.transfer = carried
    try:
        search.seed(x0)
        if x0 not in search.terminal:
            _run_guide(search, state, options.epsilon)
        if options.algorithm == "lao":
            lao(search, x0, options.epsilon, prune=options.prune_probability)
        elif options.algorithm == "lrtdp":
            lrtdp(search, x0, options.epsilon, options.seed)
        elif options.algorithm == "tvi":  # issue 15: topological VI in its own module
            from stampc.solvers.tvi import topological_vi
            topological_vi(search, x0, options.epsilon)
        else:
            value_iteration(search, x0, options.epsilon)
    except SolverTimeout:
        converged = False
    search.seed(x0)
    # past the time limit: one more second at most (the bounds evaluate it again anyway)
    goal_probability = search.goal_probability(
        x0, deadline=None if search.deadline is None else max(search.deadline,
                                                              time.perf_counter()) + 1.0)
    expanded = len(search.expanded) + (len(search.guide.expanded) if search.guide else 0)
    elapsed = time.perf_counter() - start
    return Solution(init=state, expected_cost=search.V[x0], goal_probability=goal_probability,
                    states_expanded=expanded - expanded_before, solve_time_s=elapsed,
                    converged=converged, options=options, horizon=horizon, search=search)

