"""h_max by breadth-first layers when every relaxed action costs the same (unit costs).

The literals reached by the delete relaxation grow layer by layer (as bitmasks); h_max is
the first layer containing the goal times the common cost. Per relaxed action a counter
holds how many of its precondition literals are still missing; it fires (its adds join
the next layer) when the counter reaches 0.

The counters of a state are not counted from scratch: they are the *previously evaluated*
state's, corrected for the facts the two differ in. A search evaluates the successors of
one expansion in a row, and siblings differ in a few facts (exploding blocksworld p08:
5.5 flips from the previous state against 24 from the initial state), so the correction
is short. The set of actions with no missing precondition (the first layer's supporters)
is carried along the same way, instead of a scan over every counter.

Only *relevant* relaxed actions take part: those adding a goal literal or a precondition
literal of a relevant action (backwards from the goal, once per model). The others can
never support the goal, so dropping them changes no value (exploding blocksworld: 200 of
300 relaxed actions are relevant).
"""

from __future__ import annotations

import math
from typing import Protocol, Sequence


class _Relaxed(Protocol):  # the fields of heuristics.RelaxedModel read here
    n: int
    full: int
    users: list[list[int]]
    add_masks: list[int]
    goal_mask: int
    ref_state: int
    ref_counts: list[int]
    pres: list[tuple[int, ...]]
    adders: dict[int, list[int]]


def relevant_actions(rm: _Relaxed) -> set[int]:
    """Relaxed actions that add a goal literal or a precondition literal of a relevant
    action (a backward fixpoint from the goal)."""
    relevant: set[int] = set()
    seen = {g for g in range(2 * rm.n) if (rm.goal_mask >> g) & 1}
    stack = list(seen)
    while stack:
        for i in rm.adders.get(stack.pop(), ()):
            if i not in relevant:
                relevant.add(i)
                for p in rm.pres[i]:
                    if p not in seen:
                        seen.add(p)
                        stack.append(p)
    return relevant


def released(literals: int, users: Sequence[list[int]], counts: list[int]) -> list[int]:
    """The actions whose last missing precondition is among ``literals`` (newly
    reached): every user's counter drops by one, those reaching 0 are returned."""
    out = []
    while literals:
        low = literals & -literals
        literals ^= low
        for i in users[low.bit_length() - 1]:
            c = counts[i] - 1
            counts[i] = c
            if not c:
                out.append(i)
    return out


def literal_flips(old: int, new: int, full: int, n: int) -> list[tuple[int, int]]:
    """(literal gained, literal lost) for each fact the states ``old`` and ``new`` differ
    in (literal ``n + i`` is fact ``i`` false): a fact now true gains its positive
    literal and loses its negative one, and vice versa."""
    out = []
    diff = (old ^ new) & full
    while diff:
        low = diff & -diff
        diff ^= low
        f = low.bit_length() - 1
        out.append((f, n + f) if new & low else (n + f, f))
    return out


class CarriedCounts:
    """Per relaxed action, how many precondition literals a state lacks, and the actions
    at 0: the previous state's counters corrected for the facts the two differ in
    (``users[literal]`` lists the actions needing the literal; literal ``n + i`` is fact
    ``i`` false). Each call's state becomes the reference of the next."""

    def __init__(self, users: Sequence[list[int]], n: int, state: int,
                 counts: list[int], zero: set[int]):
        self.users, self.n, self.full = users, n, (1 << n) - 1
        self.ref_state, self.ref_counts, self.ref_zero = state, list(counts), set(zero)

    def __call__(self, state: int) -> tuple[list[int], set[int]]:
        users = self.users
        counts = list(self.ref_counts)
        zero = set(self.ref_zero)
        for on, off in literal_flips(self.ref_state, state, self.full, self.n):
            for i in users[off]:  # a literal lost: its users miss one more
                if not counts[i]:
                    zero.discard(i)
                counts[i] += 1
            for i in users[on]:  # a literal gained: one fewer missing
                c = counts[i] - 1
                counts[i] = c
                if not c:
                    zero.add(i)
        self.ref_state, self.ref_counts, self.ref_zero = state, list(counts), set(zero)
        return counts, zero


class LayeredHmax:
    """h_max of a state (``inf``: the relaxation cannot reach the goal) for relaxed
    actions that all cost ``unit`` (> 0)."""

    def __init__(self, rm: _Relaxed, unit: float):
        self.n, self.full, self.unit = rm.n, rm.full, unit
        relevant = relevant_actions(rm)
        #: literal -> the relevant relaxed actions needing it
        self.users: Sequence[list[int]] = [[i for i in u if i in relevant] for u in rm.users]
        self.add_masks: Sequence[int] = rm.add_masks
        self.goal = rm.goal_mask
        #: literals some relevant action needs: the only ones whose users are walked
        self.has_users = sum(1 << lit for lit, u in enumerate(self.users) if u)
        # counters carried from the last state evaluated (those of irrelevant actions
        # are never read)
        self._counts = CarriedCounts(self.users, self.n, rm.ref_state, rm.ref_counts,
                                     {i for i, c in enumerate(rm.ref_counts)
                                      if not c and i in relevant})

    def __call__(self, state: int) -> float:
        n = self.n
        reached = state | ((self.full & ~state) << n)
        goal = self.goal
        if reached & goal == goal:
            return 0.0
        counts, zero = self._counts(state)
        users, add_masks, has_users = self.users, self.add_masks, self.has_users
        new = 0
        for i in zero:
            new |= add_masks[i]
        level = 0
        while True:
            new &= ~reached
            if not new:
                return math.inf
            level += 1
            reached |= new
            if reached & goal == goal:
                return level * self.unit
            frontier, new = new & has_users, 0
            for i in released(frontier, users, counts):
                new |= add_masks[i]
