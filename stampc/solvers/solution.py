"""Public solver types: options and solutions."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

from stampc.solvers.core import Search
from stampc.solvers.names import ALGORITHMS  # noqa: F401  (re-exported)
from stampc.solvers.successors import SuccessorCache


@dataclass(frozen=True)
class SolverOptions:
    algorithm: str = "lao"        # "lao" | "lrtdp" | "vi"
    heuristic: str = "hmax"       # "zero" | "hmax" | "hadd" (inadmissible)
    epsilon: float = 1e-4
    dead_end_cost: float = 500.0
    unit_cost: bool = False
    #: Finite horizon (time-indexed values, non-stationary policy); ``None`` uses the
    #: model's own horizon, if any, else the indefinite-horizon SSP.
    horizon: int | None = None
    time_limit: float | None = None
    #: cap on the search's work (``Search.work``: units of about one h_add evaluation on
    #: the 25-can cluttered table, ~130 µs); unlike ``time_limit``, where it stops a
    #: search is the same on every machine and under any load, so a capped solve is
    #: reproducible
    work_limit: int | None = None
    seed: int = 0                 # LRTDP trials
    #: (state, action index) pairs the policy must not use; (ANY_STATE, action index)
    #: forbids the action in every state (``stampc.solvers.space.ANY_STATE``).
    forbidden: frozenset[tuple[int, int]] = frozenset()
    #: heuristic weight (weighted LAO*): > 1 trades optimality for speed; 1 keeps an
    #: admissible heuristic admissible
    weight: float = 1.0
    #: LAO* leaves unexpanded every tip the greedy policy reaches with probability below
    #: this (0: off). The result is a *partial* policy whose low-probability tips keep
    #: their heuristic values; the refinement engine plans them when it gets there.
    prune_probability: float = 0.0
    #: Solve over orbit representatives of interchangeable objects (``symmetry.py``):
    #: every next state becomes its orbit's representative (same optimal value). The
    #: initial state is kept; the policy graph's other states are representatives.
    #: Ignored with ``forbidden`` actions (they need not respect the symmetry).
    symmetry: bool = False
    #: Clear the facts no reachable action reads from every next state (``relevance.py``;
    #: same optimal value). Like ``symmetry``, the initial state is kept as it is.
    relevance: bool = False


class PolicyTable(Protocol):
    """A policy and values over a whole state space (``dense.py``'s solutions)."""
    n_states: int

    def action(self, state: int) -> int | None: ...

    def value(self, state: int) -> float: ...

    def states(self, first: int) -> list[int]: ...


@dataclass(frozen=True)
class Solution:
    init: int
    expected_cost: float
    goal_probability: float
    states_expanded: int
    solve_time_s: float
    converged: bool
    options: SolverOptions
    #: The horizon actually used (options or model), ``None`` for the indefinite SSP.
    horizon: int | None = None
    #: The value tables; shared with warm re-solves (which copy before changing them).
    search: Search | None = field(default=None, compare=False, repr=False)
    #: Set when a dense solver valued every state (``dense_api.py``): the policy and the
    #: values come from it; ``search`` then only holds the successor cache.
    table: PolicyTable | None = field(default=None, compare=False, repr=False)

    @property
    def successors(self) -> SuccessorCache:
        """The successor cache the solve used (shareable with the engine)."""
        return self.search.space.cache

    @property
    def states_generated(self) -> int:
        if self.table is not None:
            return self.table.n_states
        return len(self.search.V) if self.search else 0

    def _node(self, state: int, t: int) -> int:
        return self.search.space.node(state, t)

    def action(self, state: int, t: int = 0) -> int | None:
        """Greedy ground action index in ``state`` at step ``t``; ``None`` at a goal, a
        dead end, the horizon, or where giving up (cost D) is best."""
        if self.horizon is not None and t >= self.horizon:
            return None
        if self.table is not None:
            return self.table.action(state)
        search = self.search
        x = self._node(state, t)
        search.seed(x)
        if x in search.terminal:
            return None
        if x not in search.best:
            # Off the solved graph (e.g. a state the engine reached by surprise, or a
            # solve cut short): one-step lookahead on the current values, kept in the tables.
            if x not in search.expanded:
                search.expand(x)
                if x in search.terminal:
                    return None
            search.backup(x)
        bi = search.best[x]
        if bi < 0:
            return None
        return search.expanded[x][bi][0]

    def planned(self, state: int, t: int = 0) -> bool:
        """Did the search expand and back up ``(state, t)`` (or find it terminal)?"""
        if self.table is not None:
            return True
        x = self._node(state, t)
        return x in self.search.best or x in self.search.terminal

    def value(self, state: int, t: int = 0) -> float:
        """Current value estimate (exact within ε on the solved policy graph)."""
        search = self.search
        if self.horizon is not None and t >= self.horizon:
            return 0.0 if search.space.cache.is_goal(state) else search.dead_end_cost
        if self.table is not None:
            return self.table.value(state)
        x = self._node(state, t)
        search.seed(x)
        return search.V[x]

    def policy_nodes(self) -> list[tuple[int, int]]:
        """(state, t) pairs reachable from ``init`` under the policy, DFS preorder."""
        if self.table is not None:
            return [(s, 0) for s in self._table_policy_states()]
        space = self.search.space
        return [(space.state(x), space.time(x))
                for x in self.search.policy_graph(space.node(self.init, 0))]

    def _table_policy_states(self) -> list[int]:
        # a dense solution has no transition tables, and enumerating its outcomes is what
        # it avoids (2^16 per state on SysAdmin p06): every state of its space, init first
        return self.table.states(first=self.init)
