"""Certified bounds on the optimal value V*(init): solve until upper - lower <= ε.

*Lower bound.* With an admissible heuristic (``hmax``, ``lmcut``, ``zero``; weight 1) every
value in the search tables is ≤ V*: the initial values are, and a Bellman backup keeps
``V <= V*`` because the operator is monotone and V* is its fixed point (the self-loop
folding of ``successors.py`` does not change that fixed point). So ``V[init]`` is a lower
bound whenever the algorithm stops — converged or not.

*Upper bound.* The greedy policy π is evaluated on the states it reaches from ``init``;
where it has no action (give-up, unexpanded tip of a search cut short, or its value would
exceed D) it gives up at cost D, so what is evaluated is a real policy and its value is
≥ V*. The evaluation is iterative (Gauss-Seidel in post-order of the policy graph) and
certified without trusting convergence: with ρ the largest Bellman residual
``c + Σ p·u − u`` of the final iterate ``u`` and ``c_min > ρ`` the smallest expected
action cost in the graph, ``w = u · c_min / (c_min − ρ)`` satisfies ``T^π w ≤ w``, and an
excessive non-negative ``w`` bounds the policy's value from above (unroll ``T^π``).

*Loop.* The algorithm runs with Bellman residual ε, the bounds are computed, and while the
gap exceeds the target the residual is divided by 10 and the search resumes warm (same
tables). The gap is *relative* by default: done when ``upper − lower ≤ ε · upper``;
``relative=False`` makes it absolute: ``upper − lower ≤ ε``.

Inadmissible modes (``hadd``, ``hff``, weight > 1) get no lower bound: only the exact
evaluation (cost, goal probability) of the policy they return.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

from stampc.ir.grounded import GroundModel
from stampc.solvers.core import Search
from stampc.solvers.dense_choice import auto_dense
from stampc.solvers.fret import eliminate_traps, repair_policy
from stampc.solvers.names import ADMISSIBLE
from stampc.solvers.solution import Solution, SolverOptions

#: The Bellman residual is not tightened below this (float noise on values ~1e3).
MIN_RESIDUAL = 1e-12
#: Policy repairs (fret.py) per evaluation, at most.
REPAIR_ROUNDS = 10
#: Searches resumed after raising zero-cost traps (fret.py), at most.
MAX_TRAP_ROUNDS = 50
#: Policy evaluation: at most this many Gauss-Seidel sweeps per bound computation.
MAX_EVAL_SWEEPS = 20_000


@dataclass(frozen=True)
class PolicyValue:
    """Exact-up-to-ρ evaluation of a policy: cost upper bound and goal probability."""
    upper: float
    goal_probability: float
    states: int
    residual: float
    looping: int = 0  # nodes of a complete policy graph that never reach the goal (traps)


@dataclass(frozen=True)
class Bounds:
    lower: float | None       # None: inadmissible mode, no claim of optimality
    upper: float              # the evaluated cost of the returned policy (≥ V*)
    goal_probability: float   # of the evaluated policy
    relative: bool            # gap mode of the stopping test
    target: float             # ε of the stopping test
    rounds: int               # algorithm runs (residual tightened between runs)
    policy_states: int

    @property
    def gap(self) -> float | None:
        return None if self.lower is None else max(0.0, self.upper - self.lower)

    @property
    def relative_gap(self) -> float | None:
        gap = self.gap
        if gap is None:
            return None
        return 0.0 if gap == 0 else gap / abs(self.upper)

    @property
    def certified(self) -> bool:
        """The gap meets the target (always false without a lower bound)."""
        gap = self.gap
        if gap is None:
            return False
        return gap <= (self.target * abs(self.upper) if self.relative else self.target)

    def as_json(self) -> dict:
        return {"lower_bound": self.lower, "upper_bound": self.upper, "gap": self.gap,
                "relative_gap": self.relative_gap,
                "gap_mode": "relative" if self.relative else "absolute",
                "certified": self.certified, "policy_cost": self.upper,
                "policy_goal_probability": self.goal_probability,
                "bound_rounds": self.rounds}


def admissible(options: SolverOptions) -> bool:
    return ADMISSIBLE.get(options.heuristic, False) and options.weight == 1.0


def _policy_rows(search: Search, init: int):
    """(node, cost, probs, nexts) of the policy graph's acting nodes, post-order."""
    best, terminal, expanded = search.best, search.terminal, search.expanded
    nodes = search.policy_graph(init)
    rows = []
    for x in reversed(nodes):  # reversed DFS preorder: successors mostly before parents
        bi = best.get(x, -1)
        if bi >= 0 and x not in terminal and x in expanded:
            _, c, probs, nexts = expanded[x][bi]
            rows.append((x, c, probs, nexts))
    return nodes, rows


def _goal_reaching(rows: list, goals: set[int]) -> set[int]:
    """The nodes from which the policy reaches a goal with positive probability.

    The others loop forever without the goal: with zero-cost cycles (a trap) their
    Bellman fixed point is any constant, so the iterate would certify a value the policy
    never earns. They give up (cost D) instead, which makes the evaluated policy a real
    one that fails there, as the dead-end convention prices failure."""
    preds: dict[int, list[int]] = {}
    for x, _, _, nexts in rows:
        for n in nexts:
            preds.setdefault(n, []).append(x)
    good, stack = set(goals), list(goals)
    while stack:
        for x in preds.get(stack.pop(), ()):
            if x not in good:
                good.add(x)
                stack.append(x)
    return good


def evaluate_policy(search: Search, init: int, tolerance: float = 1e-12,
                    deadline: float | None = None, repair: bool = False) -> PolicyValue:
    """Certified upper bound on V*(init): the greedy policy's value (give-up = D where it
    has no action), see the module docstring for the residual correction."""
    D = search.dead_end_cost
    V, terminal = search.V, search.terminal
    is_goal = search.space.cache.is_goal
    state_of = search.space.state
    def goal_node(x: int) -> bool:
        return x in terminal and is_goal(state_of(x))

    # repairs (and trap detection) only for a search that has converged: between LAO*
    # passes they would re-point choices mid-search and cost time on large graphs
    for _ in range(REPAIR_ROUNDS if repair else 1):
        nodes, rows = _policy_rows(search, init)
        good = _goal_reaching(rows, {x for x in nodes if goal_node(x)})
        # valued below D yet never reaching the goal: a trap (a node whose policy only
        # leads to give-ups is worth ~D already and needs no repair)
        bad = [row[0] for row in rows if row[0] not in good and V[row[0]] < D * (1 - 1e-9)]
        # only a complete policy graph (no unexpanded tip) can hold a trap worth repairing
        if not bad or any(x not in search.expanded and x not in terminal for x in nodes):
            bad = []  # partial graph: its failures are unexpanded tips, not traps
            break
        if not repair or not repair_policy(search, init, bad, goal_node):
            break
    rows = [row for row in rows if row[0] in good]
    acting = {x for x, _, _, _ in rows}
    u: dict[int, float] = {}
    P: dict[int, float] = {}
    for x in nodes:
        if x in acting:
            u[x], P[x] = min(V[x], D), 0.0
        elif x in terminal and is_goal(state_of(x)):
            u[x], P[x] = 0.0, 1.0
        else:  # dead end, horizon, give-up, or a tip never expanded: give up
            u[x], P[x] = D, 0.0
    for sweep in range(MAX_EVAL_SWEEPS):
        change = 0.0
        for x, c, probs, nexts in rows:
            v, g = c, 0.0
            for p, n in zip(probs, nexts):
                v += p * u[n]
                g += p * P[n]
            if v >= D:
                v, g = D, 0.0  # giving up here is cheaper than following π
            d = abs(v - u[x]) + abs(g - P[x])
            if d > change:
                change = d
            u[x], P[x] = v, g
        if change <= tolerance:
            break
        if deadline is not None and sweep % 8 == 7 and time.perf_counter() > deadline:
            break
    rho, cmin = 0.0, float("inf")
    for x, c, probs, nexts in rows:
        if u[x] >= D:
            continue  # gives up: a fixed value D, no residual
        v = c
        for p, n in zip(probs, nexts):
            v += p * u[n]
        if v - u[x] > rho:
            rho = v - u[x]
        if c < cmin:
            cmin = c
    if rho <= 0.0:
        upper = u[init]
    elif rho < cmin:
        upper = min(D, u[init] * cmin / (cmin - rho))
    else:
        upper = D  # cannot certify the iterate: giving up at once is always possible
    return PolicyValue(upper=upper, goal_probability=min(1.0, P[init]), states=len(nodes),
                       residual=rho, looping=len(bad))


class GapCheck:
    """``stop`` callback for LAO*: evaluates the bounds between passes and says when the
    certified gap is met. Throttled so that evaluations take at most about a fifth of
    the time: the next one waits 4x as long as the last one took (at least 0.5 s)."""

    def __init__(self, relative: bool, target: float, deadline: float | None,
                 min_interval: float = 0.5):
        self.relative, self.target, self.deadline = relative, target, deadline
        self.min_interval = min_interval
        self.next_at = time.perf_counter() + min_interval
        self.met = 0  # evaluations that found the gap met (statistics, tests)

    def __call__(self, search: Search, init: int) -> bool:
        now = time.perf_counter()
        if now < self.next_at:
            return False
        value = evaluate_policy(search, init, deadline=self.deadline)
        lower = min(search.V[init], value.upper)
        gap = value.upper - lower
        done = gap <= (self.target * abs(value.upper) if self.relative else self.target)
        spent = time.perf_counter() - now
        self.next_at = time.perf_counter() + max(self.min_interval, 4 * spent)
        self.met += done
        return done


def _try_dense(model: GroundModel, options: SolverOptions, relative: bool,
               init: int | None) -> tuple[Solution, Bounds] | None:
    """The dense solver's certified result when asked for (``algorithm="dense"``) or when
    it applies automatically (``dense_api.auto_dense``); ``None``: use the search."""
    if options.algorithm != "dense" and not (admissible(options) and auto_dense(model, options)):
        return None
    # numpy only when the dense solver runs (the CLI's light paths never load it)
    from stampc.solvers.dense_api import NotFactored, TooLarge, dense_or_error, solve_dense
    if options.algorithm == "dense":
        solution, result = dense_or_error(model, options, relative=relative, init=init)
    else:
        try:
            solution, result = solve_dense(model, options, relative=relative, init=init)
        except (NotFactored, TooLarge):
            return None  # the structure does not fit: LAO* as asked
    return solution, Bounds(lower=result.lower, upper=result.upper,
                            goal_probability=result.goal_probability, relative=relative,
                            target=options.epsilon, rounds=result.sweeps,
                            policy_states=int((result.policy >= 0).sum()))


def solve_bounded(model: GroundModel, options: SolverOptions, *, relative: bool = True,
                  init: int | None = None) -> tuple[Solution, Bounds]:
    """Solve, then tighten the residual until the certified gap meets ``options.epsilon``.
    ``solution.converged`` is false when the time limit stopped a run or the gap stayed
    above the target."""
    from stampc.solvers.api import solve

    dense = _try_dense(model, options, relative, init)
    if dense is not None:
        return dense
    start = time.perf_counter()
    deadline = None if options.time_limit is None else start + options.time_limit
    lower_ok = admissible(options)
    check = GapCheck(relative, options.epsilon, deadline) if lower_ok else None
    solution = solve(model, options, init=init, stop=check)
    expanded, rounds, residual = solution.states_expanded, 1, options.epsilon
    while True:
        x0 = solution.search.space.node(solution.init, 0)
        value = evaluate_policy(solution.search, x0, deadline=deadline,
                                repair=solution.converged)
        left = None if deadline is None else deadline - time.perf_counter()
        if (value.looping and lower_ok and solution.converged and rounds < MAX_TRAP_ROUNDS
                and (left is None or left > 0) and eliminate_traps(solution.search, x0)):
            # zero-cost traps raised to their exit value (fret.py): search on from there
            again = dataclasses.replace(options, epsilon=residual, time_limit=left)
            solution = solve(model, again, init=solution.init, warm=solution, stop=check)
            expanded += solution.states_expanded
            rounds += 1
            continue
        lower = min(solution.search.V[x0], value.upper) if lower_ok else None
        bounds = Bounds(lower=lower, upper=value.upper, goal_probability=value.goal_probability,
                        relative=relative, target=options.epsilon, rounds=rounds,
                        policy_states=value.states)
        left = None if deadline is None else deadline - time.perf_counter()
        if (not lower_ok or bounds.certified or residual <= MIN_RESIDUAL
                or not solution.converged or (left is not None and left <= 0)):
            break
        residual = max(MIN_RESIDUAL, residual / 10)
        tighter = dataclasses.replace(options, epsilon=residual, time_limit=left)
        solution = solve(model, tighter, init=solution.init, warm=solution, stop=check)
        expanded += solution.states_expanded
        rounds += 1
    # a run stopped by the time limit stays "not converged" (exit 3) even if its bounds
    # happen to meet: ``bounds.certified`` says so separately
    converged = solution.converged and (bounds.certified or not lower_ok)
    final = dataclasses.replace(solution, options=options, states_expanded=expanded,
                                solve_time_s=time.perf_counter() - start,
                                converged=converged)
    return final, bounds
