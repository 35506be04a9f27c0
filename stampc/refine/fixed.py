"""Facts of ``? predicate``s: fixed facts the abstraction does not know.

No action changes them, so a value refinement learns at one node holds in every state of
the run — unlike a ``?`` effect's fact, which the next such effect makes unknown again.
Written only into the learning node's state, the sibling branches planned before would
each learn it once more (Keva tower-24: ``reaches(left, feed2)`` learned 41 times in one
run). Instead every ground action that needs the other value is banned in every state,
for good: a fact is not a guess, so these bans are never lifted.
"""

from __future__ import annotations

from typing import Sequence

from stampc.ir.ground_context import iter_effect_atoms
from stampc.ir.grounded import GroundModel
from stampc.refine.concretize import unknowable_predicates


def fixed_facts(model: GroundModel) -> frozenset[int]:
    """Facts of unknowable predicates that no action's effect writes."""
    lifted = model.lifted
    if lifted is None:
        return frozenset()
    written = {atom.predicate for action in lifted.domain.actions
               for atom, _ in iter_effect_atoms(action.effect)}
    fixed = unknowable_predicates(model) - written
    return frozenset(i for i, f in enumerate(model.facts) if f.predicate in fixed)


def needing_otherwise(model: GroundModel, learned: Sequence[tuple[int, bool]]) -> set[int]:
    """Ground actions whose precondition needs a learned fact at the other value."""
    pos = sum(1 << f for f, value in learned if not value)  # learned false, needed true
    neg = sum(1 << f for f, value in learned if value)
    return {a.index for a in model.actions
            if a.precondition.pos & pos or a.precondition.neg & neg}
