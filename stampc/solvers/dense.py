"""Policy iteration over every state of a product-form model, with certified bounds.

For models that :func:`stampc.solvers.factored.compile_factored` accepts (at most 18
varying facts, each probabilistic block changing one fact), a Bellman backup of every
state is a few numpy operations per action (``product.expect``), however many joint
outcomes an action has. The Bellman operator T is the solvers' own: goal states cost 0,
a Q-value is capped at D (give up), an outcome returning to the same state is folded in
(``(c + E[V] − p_stay·V(s)) / (1 − p_stay)``, same fixed point) and an action that cannot
leave its state is unusable.

*Iteration.* A few value-iteration sweeps from 0 give a first greedy policy; then policy
iteration: the policy is evaluated by solving its linear system with GMRES (matrix-free,
``krylov.py``: value-iteration sweeps converge at the chain's mixing rate, thousands of
sweeps on SysAdmin p06) and improved by one sweep, until the bounds meet.

*Bounds from any iterate u* (one sweep gives ``Tu`` and its greedy policy π; c_min is a
lower bound on every folded action cost, D included):

- upper: π gives up where no Q-value is below D (``u = D`` there). With ρ the largest
  residual ``Q_π(u) − u`` where π acts and ``c_min(π) > ρ``, ``w = u·c_min/(c_min − ρ)``
  is excessive for π, hence ≥ π's value ≥ V* (as in ``bounds.py``).
- lower: with δ = max(u − Tu) over all states, following an optimal policy μ from s
  gives ``u(s) ≤ V*(s) + δ·E_μ[steps]`` and ``V*(s) ≥ c_min·E_μ[steps]``, so
  ``V*(s) ≥ u(s)·c_min/(c_min + δ)`` (and ``u ≤ V*`` outright when δ ≤ 0: the value
  iteration from 0 stays below V*).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from stampc.solvers.factored import FactoredModel
from stampc.solvers.krylov import gmres
from stampc.solvers.product import Plan, expect, make_plan

#: An action whose probability of staying put is this close to 1 is unusable there.
_NOOP = 1.0 - 1e-12


#: Iterations without progress (bounds and iterate unchanged) before giving up.
MAX_STALLED = 50


class TooLarge(Exception):
    """The expectation plans would cost more than the work budget per sweep."""


@dataclass(frozen=True)
class DenseResult:
    values: np.ndarray        # the last iterate per state index (not itself a bound)
    policy: np.ndarray        # ground action index per state index, -1 = none/give up
    lower: float
    upper: float
    goal_probability: float   # of the certified policy (GMRES: approximate)
    sweeps: int
    certified: bool
    timed_out: bool


@dataclass(frozen=True)
class _Action:
    index: int
    rows: np.ndarray
    cost: np.ndarray          # folded expected cost (inf where unusable)
    usable: np.ndarray
    plan: Plan


def _prepare(model: FactoredModel, max_work: float) -> list[_Action]:
    out, work = [], 0
    for a in model.actions:
        plan = make_plan(a.q, a.rows, max_work - work)
        if plan is None:
            raise TooLarge(f"more than {max_work:.3g} multiply-adds per sweep")
        work += plan.work
        usable = plan.stay < _NOOP
        leave = np.where(usable, 1.0 - plan.stay, 1.0)
        out.append(_Action(a.index, a.rows, np.where(usable, a.cost / leave, np.inf),
                           usable, plan))
    return out


def _q_values(action: _Action, values: np.ndarray) -> np.ndarray:
    """Folded Q-values of ``action`` on its rows (inf where it cannot leave)."""
    plan = action.plan
    leave = np.where(action.usable, 1.0 - plan.stay, 1.0)
    future = (expect(plan, values) - plan.stay * values[action.rows]) / leave
    return np.where(action.usable, action.cost + future, np.inf)


def _sweep(actions: list[_Action], values: np.ndarray, goal: np.ndarray, D: float):
    """One Bellman sweep: (new values, greedy action position or -1, folded cost of it)."""
    best_q = np.full(len(values), D)
    best = np.full(len(values), -1, dtype=np.int64)
    cost = np.full(len(values), np.inf)
    for pos, action in enumerate(actions):
        q = _q_values(action, values)
        better = q < best_q[action.rows]
        rows = action.rows[better]
        best_q[rows], best[rows], cost[rows] = q[better], pos, action.cost[better]
    best_q[goal] = 0.0
    return best_q, best, cost


def _upper(actions, u, q_pi, best, cost, goal, init, D) -> float:
    """Certified upper bound from iterate ``u`` and ``q_pi = Q_π(u)`` (see module doc)."""
    acting = best >= 0
    if not acting[init]:
        return 0.0 if goal[init] else D
    giving_up = ~acting & ~goal
    if np.any(u[giving_up] < D):
        # π gives up where u is still below D: residuals must be taken against D there
        u = np.where(giving_up, D, u)
        q_pi = np.full(len(u), -np.inf)
        for pos, action in enumerate(actions):
            mine = best[action.rows] == pos
            q_pi[action.rows[mine]] = _q_values(action, u)[mine]
    rho = float(np.max(q_pi[acting] - u[acting]))
    cmin = float(np.min(cost[acting]))
    if rho <= 0.0:
        return float(u[init])
    if rho < cmin:
        return min(D, float(u[init]) * cmin / (cmin - rho))
    return D


def _met(lower: float, upper: float, target: float, relative: bool) -> bool:
    return upper - lower <= (target * abs(upper) if relative else target)


def _policy_operator(model: FactoredModel, actions: list[_Action], best: np.ndarray,
                     fixed: np.ndarray, costs: bool):
    """(matvec, rhs, acting state indices) of π's linear system ``(I − P_π) v = c``
    over the states where π acts (``fixed``: the values of the others; ``costs=False``:
    c = 0, for reaching probabilities)."""
    pieces = []
    cost = np.zeros(model.n_states)
    for pos, (fa, action) in enumerate(zip(model.actions, actions)):
        sel = best[fa.rows] == pos
        if np.any(sel):
            plan = make_plan(fa.q[sel], fa.rows[sel])
            pieces.append((fa.rows[sel], plan, 1.0 - plan.stay))
            cost[fa.rows[sel]] = action.cost[sel]
    index = np.flatnonzero(best >= 0)

    def propagate(v: np.ndarray) -> np.ndarray:
        out = np.zeros(model.n_states)
        for rows, plan, leave in pieces:
            out[rows] = (expect(plan, v) - plan.stay * v[rows]) / leave
        return out[index]

    def matvec(x: np.ndarray) -> np.ndarray:
        v = np.zeros(model.n_states)
        v[index] = x
        return x - propagate(v)

    return matvec, cost[index] * costs + propagate(fixed), index


def _solve_policy(model, actions, best, fixed, costs, start, deadline) -> np.ndarray:
    matvec, rhs, index = _policy_operator(model, actions, best, fixed, costs)
    v = fixed.copy()
    v[index] = gmres(matvec, rhs, start[index], deadline=deadline)
    return v


def _evaluate(model, actions, best, u, D, deadline) -> np.ndarray:
    """π's values (approximately: the bounds never trust them), clipped to [0, D]."""
    fixed = np.where((best < 0) & ~model.goal, D, 0.0)
    return np.clip(_solve_policy(model, actions, best, fixed, True, u, deadline), 0.0, D)


def goal_probability(model: FactoredModel, actions: list[_Action], best: np.ndarray,
                     deadline: float | None) -> float:
    """Probability that π reaches a goal from the initial state (π's linear system by
    GMRES: approximate, like the other solvers' sweeps)."""
    goal = model.goal.astype(float)
    reach = _solve_policy(model, actions, best, goal, False, goal, deadline)
    return float(np.clip(reach[model.init], 0.0, 1.0))


def _lower(u: np.ndarray, new: np.ndarray, goal: np.ndarray, init: int, cmin: float) -> float:
    """Lower bound on V*(init) from iterate ``u`` and ``new = Tu`` (see module doc)."""
    delta = float(np.max(np.where(goal, 0.0, u - new)))
    if delta <= 0.0:
        return float(new[init])
    return float(u[init]) * cmin / (cmin + delta)


def dense_solve(model: FactoredModel, dead_end_cost: float, target: float,
                relative: bool = True, deadline: float | None = None,
                max_work: float = 2e9, first_sweeps: int = 30) -> DenseResult:
    """Value then policy iteration until the certified gap on V*(init) meets ``target``."""
    D = float(dead_end_cost)
    actions = _prepare(model, max_work)
    cmin = min([D] + [float(np.min(a.cost[a.usable])) for a in actions if np.any(a.usable)])
    if cmin <= 0.0:
        # zero-cost actions: the lower bound rests on value iteration from 0 alone (the
        # δ bound needs c_min > 0), and no policy is certified proper: no policy iteration
        first_sweeps = 1 << 62
    goal, init = model.goal, model.init
    u = np.zeros(model.n_states)
    lower, upper, sweeps, timed_out = 0.0, D, 0, False
    best = np.full(model.n_states, -1, dtype=np.int64)
    stalled = 0
    while True:
        new, greedy, cost = _sweep(actions, u, goal, D)
        sweeps += 1
        before = (lower, upper)
        lower = max(lower, _lower(u, new, goal, init, cmin))
        bound = _upper(actions, u, new, greedy, cost, goal, init, D)
        if bound <= upper:
            upper, best = bound, greedy
        if _met(lower, upper, target, relative):
            break
        if deadline is not None and time.perf_counter() > deadline:
            timed_out = True
            break
        # no progress: neither bound moved and the iterate is a fixed point up to float
        # noise (value-iteration sweeps that still change far-away states do progress)
        still = (lower, upper) == before and float(np.max(np.abs(new - u))) <= 1e-9 * D
        stalled = stalled + 1 if still else 0
        if stalled >= MAX_STALLED:
            break
        # value iteration first (cheap sweeps, a sensible first policy), then policy
        # iteration: evaluate the greedy policy exactly and improve it — but only a
        # policy the bound certified (bound < D: proper wherever it acts); an improper
        # one has no finite value and its linear system no meaningful solution
        if sweeps < first_sweeps or bound >= D:
            u = new
        else:
            u = _evaluate(model, actions, greedy, u, D, deadline)
    policy = np.full(model.n_states, -1, dtype=np.int64)
    for pos, action in enumerate(actions):
        mine = best[action.rows] == pos
        policy[action.rows[mine]] = action.index
    prob = goal_probability(model, actions, best, deadline)
    return DenseResult(values=u, policy=policy, lower=min(lower, upper), upper=upper,
                       goal_probability=prob, sweeps=sweeps,
                       certified=_met(lower, upper, target, relative), timed_out=timed_out)
