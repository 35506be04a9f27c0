"""The search space the algorithms run on: stationary or time-indexed, as int nodes.

A *node* is an int. For the indefinite-horizon SSP a node is the state itself. For a
finite horizon H a node packs the time step above the state bits,
``node = state | t << n_facts``, so LAO*, LRTDP and VI run unchanged on the
time-indexed (acyclic) problem and produce non-stationary policies π(s, t).

Conventions (IPPC / MDP-Lib): goal nodes cost 0; a node without applicable action, or
that the heuristic recognises as a dead end, costs the dead-end cost D; every Q-value is
capped at D (a give-up action of cost D is available everywhere); with a finite horizon a
non-goal node at t = H costs D (failing to reach the goal in time is a give-up).
"""

from __future__ import annotations

import math
from typing import AbstractSet, Callable, Mapping

from stampc.solvers.heuristics import Heuristic
from stampc.solvers.successors import SuccessorCache, Transition

#: the state of a ``forbidden`` pair that bans its action in every state
ANY_STATE = -1


def is_forbidden(forbidden: AbstractSet[tuple[int, int]], state: int, action: int) -> bool:
    """Whether ``action`` is banned in ``state``: there, or in every state."""
    return (state, action) in forbidden or (ANY_STATE, action) in forbidden


def banned_everywhere(forbidden: AbstractSet[tuple[int, int]]) -> frozenset[int]:
    """The actions of ``forbidden`` banned in every state."""
    return frozenset(a for s, a in forbidden if s == ANY_STATE)


class Space:
    def __init__(self, cache: SuccessorCache, heuristic: Heuristic, dead_end_cost: float,
                 horizon: int | None = None,
                 forbidden: frozenset[tuple[int, int]] = frozenset(),
                 warm: Mapping[int, float] | None = None,
                 guide: Mapping[int, float] | None = None,
                 steps: Heuristic | None = None):
        self.cache = cache
        self.h = heuristic
        self.dead_end_cost = float(dead_end_cost)
        self.horizon = horizon
        self.shift = len(cache.model.facts)
        self.state_mask = (1 << self.shift) - 1
        self.forbidden = forbidden
        self._forbidden_states = frozenset(s for s, _ in forbidden)
        self._forbidden_anywhere = banned_everywhere(forbidden)
        self.warm = warm or {}
        #: Finite horizon only: state -> lower bound on the *stationary* optimal value.
        #: V_H(s, t) >= V*(s): a finite-horizon policy is a history-dependent policy of
        #: the stationary SSP that gives up (cost D) at the horizon, and stationary
        #: policies are optimal among those. Far more informed than h_max.
        self.guide = guide if guide is not None else {}
        #: Finite horizon only: a lower bound on the number of steps to the goal (h_max
        #: with unit costs); more than the steps left means the node costs exactly D.
        self.steps = steps
        #: node -> estimate carried over from a previous solve (``api._transfer``), or
        #: None; used instead of the heuristic when it answers
        self.transfer: Callable[[int], float | None] | None = None
        #: nodes whose initial value came from ``transfer`` (statistics)
        self.transferred = 0

    # ----------------------------------------------------------- encoding
    def node(self, state: int, t: int = 0) -> int:
        return state if self.horizon is None else state | (t << self.shift)

    def state(self, node: int) -> int:
        return node if self.horizon is None else node & self.state_mask

    def time(self, node: int) -> int:
        return 0 if self.horizon is None else node >> self.shift

    # ------------------------------------------------------------ queries
    def initial_value(self, node: int) -> tuple[float, bool]:
        """(value, terminal) for a node seen for the first time.

        Terminal nodes are never expanded: goals (0), horizon nodes (D unless goal) and
        recognised dead ends (D).
        """
        if self.horizon is None:
            state = node
        else:
            state = node & self.state_mask
        if self.cache.is_goal(state):
            return 0.0, True
        d = self.dead_end_cost
        if self.horizon is not None:
            left = self.horizon - (node >> self.shift)
            if left <= 0 or (self.steps is not None and self.steps(state) > left):
                return d, True
        if self.transfer is not None:
            carried = self.transfer(node)
            if carried is not None:
                self.transferred += 1
                return (carried if carried < d else d), False
        h = self.h(state)
        if h == math.inf:
            return d, True
        if self.guide:
            g = self.guide.get(state)
            if g is not None and g > h:
                h = g
        warm = self.warm.get(node)
        if warm is not None and warm > h:
            h = warm
        return (h if h < d else d), False

    def transitions(self, node: int) -> tuple[Transition, ...]:
        """Transitions of a non-terminal node, next nodes already encoded (the caller,
        ``Search.expand``, stores them)."""
        if self.horizon is None:
            result = self.cache.transitions(node)
            if node in self._forbidden_states or self._forbidden_anywhere:
                result = tuple(t for t in result if not self._banned(node, t[0]))
            return result
        state = node & self.state_mask
        step = ((node >> self.shift) + 1) << self.shift
        return tuple((a, c, probs, tuple(n | step for n in nexts))
                     for a, c, probs, nexts in
                     self.cache.transitions(state, eliminate_self_loops=False)
                     if not self._banned(state, a))

    def _banned(self, state: int, action: int) -> bool:
        return is_forbidden(self.forbidden, state, action)
