"""Irrelevant facts: states that differ only in facts no reachable action reads share V*.

In a state ``s``, let ``Reach(s)`` be the literals the delete relaxation reaches from
``s`` (negative literals are facts of their own, as in ``heuristics.py``) and ``R(s)`` the
ground actions whose precondition literals lie in ``Reach(s)``: every action applicable
in a state reachable from ``s`` is in ``R(s)``. A fact that no action of ``R(s)`` reads
(precondition or ``when`` condition, either polarity) and that the goal does not mention
is *irrelevant* in ``s``. Clearing such a fact ``p`` gives a state ``c(s)`` with the same
optimal value provided ``¬p`` cannot enable anything new: ``¬p`` is in ``Reach(s)``
already, or no precondition or condition anywhere needs ``¬p``. Then
``Reach(c(s)) ⊆ Reach(s) ∪ {¬p}``, so from ``s`` and from ``c(s)`` the same actions of
``R(s)`` apply with the same outcomes and costs; the two runs differ only in facts those
actions never read, and reach the goal together (a coupling: ``V*(s) = V*(c(s))``).

So the SSP can be solved with every next state replaced by a reduction, as
``symmetry.py`` replaces it by an orbit representative. The argument only needs a set of
literals closed under the relaxation that contains the state's: ``Reach(parent)`` is
one for every next state of ``parent``, so the search walks the relaxation once per
expansion and clears the parent's clearable facts from all its next states (a next
state's own walk would clear more, at one walk per next state: exploding blocksworld
p08 certified in 45 s that way, timed out at 57 s the other). Triangle-tireworld's roads only
lead forward and ``loadtire`` needs the car at the spare's location: once the car has
passed a location, its ``spare-in`` fact is irrelevant, and the states that differ in the
spares left behind collapse into one. Models with derived facts are left alone.
"""

from __future__ import annotations

from typing import Sequence

from stampc.ir.grounded import GEffect, GLit, GroundCondition, GroundModel
from stampc.solvers.heuristics import _relaxed_adds, condition_facts, relaxed_state
from stampc.solvers.layered import CarriedCounts, released
from stampc.solvers.successors import Outcome

#: After this many next states without a single cleared fact the reduction switches
#: itself off (a count, not a time: deterministic). Blocksworld-like models read every
#: fact from every state; the reachability walk would only cost.
GIVE_UP_AFTER = 3000


def condition_reads(cond: GroundCondition) -> int:
    """Every fact a condition mentions, in either polarity (disjunctions included)."""
    mask = cond.pos | cond.neg
    stack = list(cond.rest)
    while stack:
        f = stack.pop()
        if isinstance(f, GLit):
            mask |= 1 << f.fact
        else:
            stack.extend(f.args)
    return mask


def effect_reads(effect: GEffect) -> int:
    """Every fact the ``when`` conditions of an effect mention, nested ones included."""
    mask = 0
    for cond, sub in effect.whens:
        mask |= condition_reads(cond) | effect_reads(sub)
    for block in effect.blocks:
        for _, sub in block.outcomes:
            mask |= effect_reads(sub)
    return mask


class _Entries:
    """Precondition literals -> (literals added, facts read), merged per precondition:
    the relaxed actions (per outcome and ``when`` branch) and the ground actions."""

    def __init__(self, model: GroundModel, n: int):
        adds: dict[frozenset[int], int] = {}
        reads: dict[frozenset[int], int] = {}
        for action in model.actions:
            if action.precondition.never:
                continue
            pre = condition_facts(action.precondition, n)
            _relaxed_adds(action.effect, pre, adds, n)
            reads[pre] = reads.get(pre, 0) | condition_reads(action.precondition) \
                | effect_reads(action.effect)
        keys = sorted(set(adds) | set(reads), key=sorted)
        self.pres = [tuple(sorted(k)) for k in keys]
        self.adds = [adds.get(k, 0) for k in keys]
        self.reads = [reads.get(k, 0) for k in keys]
        self.pre_masks = [sum(1 << lit for lit in pre) for pre in self.pres]
        self.users: list[list[int]] = [[] for _ in range(2 * n)]
        for i, pre in enumerate(self.pres):
            for lit in pre:
                self.users[lit].append(i)
        #: negative literals some precondition needs (clearing a fact could enable it)
        self.needed_negative = 0
        for pre in self.pres:
            for lit in pre:
                if lit >= n:
                    self.needed_negative |= 1 << (lit - n)


class Relevance:
    """``canonical(state)``: ``state`` with its irrelevant facts cleared (module doc)."""

    def __init__(self, model: GroundModel):
        n = self.n = len(model.facts)
        self.full = (1 << n) - 1
        self.entries = _Entries(model, n)
        #: goal facts (either polarity) are never cleared
        self.goal_reads = condition_reads(model.goal)
        goal_negative = sum(1 << (lit - n) for lit in condition_facts(model.goal, n) if lit >= n)
        #: facts whose negative literal nothing needs: clearing them is always safe
        self.free_negative = self.full & ~(self.entries.needed_negative | goal_negative)
        self._cache: dict[int, int] = {}
        # counters carried from walk to walk (layered.py's): consecutive expansions
        # are near each other; the initial state's at first
        init = model.init & self.full
        lacking = ~relaxed_state(init, n, self.full)
        counts = [(m & lacking).bit_count() for m in self.entries.pre_masks]
        self._counts = CarriedCounts(self.entries.users, n, init, counts,
                                     {i for i, c in enumerate(counts) if not c})
        self.seen = 0     # next states canonicalised
        self.reduced = 0  # ... of which lost at least one fact
        self.active = True

    def __bool__(self) -> bool:
        return True

    def _clearable(self, state: int) -> int:
        """The relaxation from ``state`` walked until it settles which facts that can
        hold in a next state (``state``'s and those its applicable entries add) some
        reachable entry reads; the rest of them is clearable where ``¬p`` is harmless
        or reached. The walk stops early once all of them are read."""
        e = self.entries
        full = self.full
        reached = relaxed_state(state, self.n, full)
        counts, zero = self._counts(state)
        adds, users, entry_reads = e.adds, e.users, e.reads
        may_hold = state
        for i in zero:
            may_hold |= adds[i] & full
        reads = self.goal_reads
        watch = may_hold & ~reads  # facts still possibly clearable
        queue = list(zero)  # the closure does not depend on the order
        while queue and watch:
            i = queue.pop()
            if entry_reads[i] & watch:
                reads |= entry_reads[i]
                watch &= ~reads
            new = adds[i] & ~reached
            if not new:
                continue
            reached |= new
            queue += released(new, users, counts)
        return watch & (self.free_negative | (reached >> self.n))

    def clearable(self, state: int) -> int:
        """The facts that may be cleared from the next states of ``state`` and from every
        state reachable from them: irrelevant in ``state``, their absence harmless or
        reachable, and possibly true in a next state."""
        got = self._cache.get(state)
        if got is None:
            got = self._cache[state] = self._clearable(state)
        return got

    def canonical(self, state: int) -> int:
        """``state`` without the irrelevant facts that can be cleared (same V*)."""
        return state & ~self.clearable(state)

    def reduce(self, parent: int, outcomes: Sequence[Outcome]) -> Sequence[Outcome]:
        """``outcomes`` (probability, next state, cost) of an action in ``parent`` with
        the facts clearable from ``parent`` cleared from each next state: whatever a
        next state reaches, ``parent`` reaches, so those are irrelevant there too — one
        reachability walk per expanded state, not per next state. After GIVE_UP_AFTER
        next states with nothing cleared, ``outcomes`` unchanged from then on."""
        if not self.active:
            return outcomes
        clear = self.clearable(parent)
        self.seen += len(outcomes)
        if clear:
            hit = sum(1 for o in outcomes if o[1] & clear)
            if hit:
                self.reduced += hit
                keep = ~clear
                return [(p, n & keep, c) for p, n, c in outcomes]
        if not self.reduced and self.seen >= GIVE_UP_AFTER:
            self.active = False
        return outcomes


def find_relevance(model: GroundModel) -> Relevance | None:
    """The reduction for ``model``, or None when it has derived facts (axioms)."""
    if model.axioms.rules or model.axioms.derived:
        return None
    return Relevance(model)
