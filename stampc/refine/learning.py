"""Which failed sample's facts UpdateAbstraction writes back.

A full concretization search that fails reports the violated ``?`` facts of every sample
it tried (``Failure.alternatives``). Each set is true of its own sample, but the
abstraction has one symbol per generated value (one pick trajectory per can, pose and
base), so the set written stands for every sample from then on. Writing the wrong one
can lock an action for good: cluttered-60 seed 9 learned that can53 blocks the pick of
can46 from b0 while can46 was known to block can53's from there, when another grasp of
can46 met can18 and can40 instead; two such pairs made the target unreachable and the
engine accepted a dead end that no geometry forced.

The choice, in order (``LearningChoice.rank``):
1. not a relaxed dead end: the goal keeps a finite h_add with the set written;
2. fewest *locks*: facts ``F(x, t)`` (x obstructs the failing action's sample ``t``)
   where the state already holds ``F(o, t')`` for the failing action's object ``o`` and
   a symbol ``t'`` generated for an action on ``x`` with the failing action's other
   objects (the pick of can53 from the same base b0);
3. fewest facts (the previous rule, alone);
4. the lowest h_add of the goal with the set written.
A quick failure (one sample) whose facts would lock an action is not learned: the node
searches every sample first (``Updating._locks_on_one_sample``).

h_add alone hardly separates the sets: the relaxation moves a blocker from another base
pose, so it does not see the lock (the sets of that pick cost 11.0 each).
"""

from __future__ import annotations

from collections import defaultdict
from typing import Callable, Iterable

from stampc.ir.grounded import GroundModel
from stampc.refine.concretize import continuous_objects, unknowable_predicates

Facts = tuple[tuple[int, bool], ...]


class LearningChoice:
    """Ranks the violated-fact sets of a failed search (lower ranks are learned)."""

    def __init__(self, model: GroundModel, cost: Callable[[int], float]):
        self.model = model
        self.cost = cost
        self._symbols = continuous_objects(model)
        unknowable = unknowable_predicates(model)
        #: symbol -> the objects (not symbols) of the actions that generate it
        self._owners: dict[str, set[str]] = defaultdict(set)
        #: object -> the symbols generated for actions on it
        self._owned: dict[str, set[str]] = defaultdict(set)
        for action in model.actions:
            objects = self._objects(action.args)
            for use in action.generated:
                for symbol in use.outputs:
                    self._owners[symbol] |= objects
                    for o in objects:
                        self._owned[o].add(symbol)
        #: symbol -> the facts of ``?`` predicates naming it
        self._facts_of: dict[str, list[int]] = defaultdict(list)
        for i, fact in enumerate(model.facts):
            if fact.predicate in unknowable:
                for a in fact.args:
                    if a in self._symbols:
                        self._facts_of[a].append(i)

    def _objects(self, args: Iterable[str]) -> set[str]:
        return {a for a in args if a not in self._symbols}

    def objects_of(self, action: int) -> set[str]:
        """The ground action's arguments that are objects, not generated symbols."""
        return self._objects(self.model.actions[action].args)

    def best(self, state: int, action: int, options: tuple[Facts, ...],
             written: Callable[[int, Facts], int]) -> Facts:
        """The set to learn at ``state`` for the failing ground ``action``
        (``written``: the state with a set written)."""
        mine = self.objects_of(action)
        return min(options, key=lambda facts: self.rank(state, mine, facts, written))

    def rank(self, state: int, mine: set[str], facts: Facts,
             written: Callable[[int, Facts], int]) -> tuple:
        h = self.cost(written(state, facts))
        return (h == float("inf"), self.locks(state, mine, facts), len(facts), h)

    def locks(self, state: int, mine: set[str], facts: Facts) -> int:
        """How many facts learned true name an object whose own action the state already
        has obstructed by one of ``mine`` (the failing action's objects)."""
        count = 0
        for fact, value in facts:
            atom = self.model.facts[fact]
            if value and any(self._obstructed_by(state, atom.predicate, x, mine)
                             for x in self._objects(atom.args) - mine):
                count += 1
        return count

    def _obstructed_by(self, state: int, predicate: str, x: str, mine: set[str]) -> bool:
        """Whether the state holds ``predicate(o, t')`` true for an ``o`` in ``mine`` and
        a symbol ``t'`` generated for an action on ``x`` in the same situation: its
        objects are the failing action's but ``o`` (the same base pose; x's pick from
        another base is no lock)."""
        facts = self.model.facts
        for symbol in self._owned.get(x, ()):
            owners = self._owners[symbol]
            for g in self._facts_of.get(symbol, ()):
                if not state >> g & 1 or facts[g].predicate != predicate:
                    continue
                for o in mine.intersection(facts[g].args) - owners:
                    if mine - {o} <= owners:
                        return True
        return False
