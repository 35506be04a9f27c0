"""Proving dead ends: is the abstract goal unreachable from a state?

A policy leaf where the solver gives up is only *covered* when it is a proven dead end,
not merely a state a (possibly timed-out, inadmissible) solver did not find a way out
of. The proof is a reachability fixpoint on the grounded model, ignoring the engine's
action bans (a ban is a give-up, not a proof), with everything learned so far in the
state:

1. the delete relaxation (h_max with negative literals as facts of their own) cannot
   reach the goal — sound, since every real plan is a relaxed plan; else
2. the exact forward closure of the state under every action and outcome, if it has at
   most ``limit`` states, contains no goal state.

Otherwise the leaf stays unproven (counted as unrefined mass).
"""

from __future__ import annotations

import math

from stampc.ir.grounded import GroundModel
from stampc.solvers.heuristics import make_heuristic
from stampc.solvers.successors import SuccessorCache


class DeadEndProver:
    def __init__(self, model: GroundModel, cache: SuccessorCache | None = None,
                 limit: int = 5_000):
        self.model = model
        self.cache = cache or SuccessorCache(model)
        self.limit = limit
        self._relaxed = make_heuristic("hmax", model, True)
        self._proven: dict[int, bool] = {}

    def proven(self, state: int) -> bool:
        """True iff no sequence of actions and outcomes reaches the goal from ``state``."""
        known = self._proven.get(state)
        if known is None:
            known = self._proven[state] = (self._relaxed(state) == math.inf
                                           or self._closure_has_no_goal(state))
        return known

    def _closure_has_no_goal(self, state: int) -> bool:
        is_goal = self.cache.is_goal
        seen = {state}
        stack = [state]
        while stack:
            s = stack.pop()
            if is_goal(s):
                return False
            for _, _, _, nexts in self.cache.transitions(s, eliminate_self_loops=False):
                for n in nexts:
                    if n not in seen:
                        if len(seen) >= self.limit:
                            return False  # too large to enumerate: not proven
                        seen.add(n)
                        stack.append(n)
        return True
