"""Seeded Monte Carlo simulation of a policy.

A run's cost follows the solver's cost model, so its mean estimates the expected cost:
the sum of action costs (unit or declared, as in ``solution.options``), plus the
dead-end cost D when the run ends without reaching the goal (dead end, giving up,
horizon reached, or ``max_steps`` exhausted).
"""

from __future__ import annotations

import math
import random
import time
from dataclasses import dataclass

from stampc.diagnostics import Span, StampcError, error
from stampc.ir.grounded import GroundModel
from stampc.solvers.dense_choice import AUTO_MIN_BLOCKS, effect_blocks
from stampc.solvers.solution import Solution

_Z95 = 1.959963984540054


@dataclass(frozen=True)
class SimulationResult:
    runs: int
    seed: int
    mean_cost: float
    cost_ci95: tuple[float, float]
    goal_rate: float
    goal_rate_ci95: tuple[float, float]
    mean_steps: float
    truncated: int  # runs stopped by max_steps
    #: the deadline ended the simulation early: ``runs`` counts the completed runs only
    stopped_at_deadline: bool = False

    @property
    def cost_stderr(self) -> float:
        return (self.cost_ci95[1] - self.cost_ci95[0]) / (2 * _Z95)


def wilson_interval(successes: int, n: int, z: float = _Z95) -> tuple[float, float]:
    """Wilson score interval for a binomial proportion (well-behaved at 0 and 1)."""
    if n == 0:
        return (0.0, 1.0)
    p = successes / n
    denom = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    return (max(0.0, centre - half), min(1.0, centre + half))


class _PastDeadline(Exception):
    """A run was cut short by the simulation's deadline (it is discarded)."""


def _run(model: GroundModel, solution: Solution, rng: random.Random,
         max_steps: int, memo: dict, deadline: float | None) -> tuple[float, bool, int, bool]:
    cache = solution.search.space.cache
    penalty = solution.search.dead_end_cost
    horizon = solution.horizon
    state, cost, t = solution.init, 0.0, 0
    while True:
        if cache.is_goal(state):
            return cost, True, t, False
        if t >= max_steps:
            return cost + penalty, False, t, True
        if horizon is not None and t >= horizon:
            return cost + penalty, False, t, False
        if deadline is not None and time.perf_counter() > deadline:
            raise _PastDeadline  # off the solved graph every step is a lookahead search
        action = solution.action(state, t)
        if action is None:
            return cost + penalty, False, t, False
        if _explosive(model, action, memo):  # up to 2^blocks outcomes: draw block by block
            state, c = cache.sample_outcome(state, action, rng)
            cost += c
            t += 1
            continue
        # the solvers' float enumeration (the exact Fraction one is far slower on
        # conditional effects), once per (state, action): sysadmin p04 35 s -> 0.3 s
        outcomes = memo.get((state, action))
        if outcomes is None:
            outcomes = memo[state, action] = cache.float_outcomes(state, action)
        r = rng.random()
        acc = 0.0
        chosen = outcomes[-1]
        for outcome in outcomes:
            acc += outcome[0]
            if r < acc:
                chosen = outcome
                break
        _, state, c = chosen
        cost += c
        t += 1


def _explosive(model: GroundModel, action: int, memo: dict) -> bool:
    known = memo.get(action)
    if known is None:
        known = memo[action] = effect_blocks(model.actions[action].effect) >= AUTO_MIN_BLOCKS
    return known


def simulate(model: GroundModel, solution: Solution, *, runs: int, seed: int,
             max_steps: int = 1000, deadline: float | None = None) -> SimulationResult:
    """Simulate ``runs`` executions of ``solution``'s policy from ``solution.init``.

    Past ``deadline`` (a ``time.perf_counter()`` value) the simulation stops and reports
    the runs completed so far (none: NaN costs): an unfinished policy is completed by
    one-step lookahead at every state off its graph, which can outlast any budget."""
    if runs <= 0:
        raise StampcError([error("S007", f"number of simulation runs must be positive, got {runs}",
                                 Span.point("<simulation options>"))])
    rng = random.Random(seed)
    costs: list[float] = []
    goals = steps = truncated = 0
    memo: dict = {}
    stopped = False
    for _ in range(runs):
        try:
            cost, reached, n, cut = _run(model, solution, rng, max_steps, memo, deadline)
        except _PastDeadline:
            stopped = True
            break
        costs.append(cost)
        goals += reached
        steps += n
        truncated += cut
    done = len(costs)
    if not done:
        nan = math.nan
        return SimulationResult(runs=0, seed=seed, mean_cost=nan, cost_ci95=(nan, nan),
                                goal_rate=nan, goal_rate_ci95=(0.0, 1.0), mean_steps=nan,
                                truncated=0, stopped_at_deadline=True)
    mean = sum(costs) / done
    var = sum((c - mean) ** 2 for c in costs) / (done - 1) if done > 1 else 0.0
    half = _Z95 * math.sqrt(var / done)
    return SimulationResult(runs=done, seed=seed, mean_cost=mean, cost_ci95=(mean - half, mean + half),
                            goal_rate=goals / done, goal_rate_ci95=wilson_interval(goals, done),
                            mean_steps=steps / done, truncated=truncated,
                            stopped_at_deadline=stopped)
