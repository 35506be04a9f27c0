"""The grounded (propositional) abstract SSP IR.

States are Python ``int`` bitsets over ``GroundModel.facts`` (bit i set = fact i true):
hashable, compact and fast to mask. Static facts are compiled away during grounding.
Conditions and effects store their fact sets as :data:`stampc.ir.masks.FactSet` (an int,
or a sorted index tuple when an int would be mostly zeros: a model whose actions each
touch facts of their own would otherwise need memory quadratic in its size); their
``pos``/``neg``/``add``/``delete``/``unknown`` attributes are always int bitsets.

Effects stay *factored* (independent probabilistic blocks, conditional effects kept as
conditions) because enumerating joint outcomes up front explodes on domains such as
SysAdmin; :func:`outcome_distribution` enumerates them per state on demand, and
:meth:`GroundAction.static_outcomes` caches the enumeration when no condition depends
on the state.

Semantics (PPDDL/MDPSim): all conditions are evaluated in the *old* state; deletes are
applied before adds, so a fact both added and deleted ends up true, unless grounding
with ``conflicting_effects="delete-wins"`` (mini-gpt's rule) set
``GroundAction.delete_wins`` on the actions where that can happen.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Iterable

from stampc.ir.ground_conditions import TRIVIAL as TRIVIAL  # re-exported
from stampc.ir.ground_conditions import GAnd as GAnd
from stampc.ir.ground_conditions import GFormula as GFormula
from stampc.ir.ground_conditions import GLit as GLit
from stampc.ir.ground_conditions import GOr as GOr
from stampc.ir.ground_conditions import GroundCondition as GroundCondition
from stampc.ir.ground_conditions import fact_set
from stampc.ir.ground_conditions import bits as bits
from stampc.ir.lifted import Model
from stampc.ir.masks import FactSet, as_int


@dataclass(frozen=True, order=True, slots=True)
class GroundAtom:
    predicate: str
    args: tuple[str, ...]

    def __str__(self) -> str:
        return f"{self.predicate}({', '.join(self.args)})"




@dataclass(frozen=True, slots=True)
class GProb:
    """An independent probabilistic block; probabilities may sum below 1 (rest: no-op)."""

    outcomes: tuple[tuple[Fraction, "GEffect"], ...]
    #: the outcomes' ``as NAME`` labels (aligned with ``outcomes``; may be empty) and the
    #: label of the effect-free rest, if one was named — for executors, not semantics
    labels: tuple[str | None, ...] = field(default=(), compare=False)
    rest_label: str | None = field(default=None, compare=False)


_NO_COST = Fraction(0)  # the default cost object, shared (grounding tests it by identity)


@dataclass(frozen=True, init=False, slots=True)
class GEffect:
    """A conjunction of literal adds/deletes, a cost, conditional sub-effects and
    independent probabilistic blocks.

    ``unknown`` marks facts that a ``?`` effect made unknown; their optimistic value is
    already folded into ``add``/``delete`` so solvers need not care. ``add``, ``delete``
    and ``unknown`` accept and give int bitsets; they are stored as fact sets
    (``add_facts``, ``delete_facts``, ``unknown_facts``).
    """

    add_facts: FactSet
    delete_facts: FactSet
    cost: Fraction
    unknown_facts: FactSet
    whens: tuple[tuple[GroundCondition, "GEffect"], ...]
    blocks: tuple[GProb, ...]

    def __init__(self, add: FactSet = 0, delete: FactSet = 0, cost: Fraction = _NO_COST,
                 unknown: FactSet = 0, whens: tuple[tuple[GroundCondition, "GEffect"], ...] = (),
                 blocks: tuple[GProb, ...] = ()) -> None:
        setattr_ = object.__setattr__  # frozen
        setattr_(self, "add_facts", fact_set(add))
        setattr_(self, "delete_facts", fact_set(delete))
        setattr_(self, "cost", cost)
        setattr_(self, "unknown_facts", fact_set(unknown))
        setattr_(self, "whens", whens)
        setattr_(self, "blocks", blocks)

    @property
    def add(self) -> int:
        return as_int(self.add_facts)

    @property
    def delete(self) -> int:
        return as_int(self.delete_facts)

    @property
    def unknown(self) -> int:
        return as_int(self.unknown_facts)

    @property
    def state_independent(self) -> bool:
        return not self.whens and all(
            e.state_independent for b in self.blocks for _, e in b.outcomes)


EMPTY_EFFECT = GEffect()


@dataclass(frozen=True, slots=True)
class Successor:
    """One joint outcome: probability, add mask, delete mask, cost, outcome labels."""

    probability: Fraction
    add: int
    delete: int
    cost: Fraction
    unknown: int = 0

    def apply(self, state: int) -> int:
        return (state & ~self.delete) | self.add


@dataclass(frozen=True, slots=True)
class GroundGeneratorUse:
    """Generator ``generator`` applied to ``inputs`` (object/symbol names) produces the
    symbols ``outputs`` for one ground action."""

    generator: str
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class GroundAction:
    index: int
    name: str
    args: tuple[str, ...]
    precondition: GroundCondition
    effect: GEffect
    base_cost: Fraction = Fraction(1)
    #: Index of the lifted action schema in ``GroundModel.lifted.domain.actions``.
    schema: int = -1
    #: Generator applications that concretize this action's generated symbols, in order.
    generated: tuple[GroundGeneratorUse, ...] = ()
    #: A fact one outcome both adds and deletes ends up false (mini-gpt) instead of true.
    delete_wins: bool = False
    _cache: dict = field(default_factory=dict, compare=False, hash=False, repr=False)

    @property
    def label(self) -> str:
        return f"{self.name}({', '.join(self.args)})" if self.args else self.name

    def static_outcomes(self) -> tuple[Successor, ...] | None:
        """Joint outcomes if they do not depend on the state (cached), else ``None``."""
        if "static" not in self._cache:
            self._cache["static"] = (
                outcome_distribution(self, 0) if self.effect.state_independent else None)
        return self._cache["static"]

    def basic_outcomes(self, state: int) -> tuple[Successor, ...]:
        """Joint outcomes in ``state`` as the effects write them (derived facts untouched)."""
        cached = self.static_outcomes()
        return cached if cached is not None else outcome_distribution(self, state)

    def outcomes(self, state: int) -> tuple[Successor, ...]:
        """Joint outcomes in ``state``; with axioms, each one's masks also update the
        derived facts (the successor is closed), aligned with :meth:`basic_outcomes`."""
        outs = self.basic_outcomes(state)
        axioms = self._cache.get("axioms")
        return outs if axioms is None else tuple(_closed(o, state, axioms) for o in outs)


# ------------------------------------------------------ derived facts
@dataclass(frozen=True)
class GroundAxiom:
    """``head`` (a derived fact's index) holds whenever ``body`` does."""

    head: int
    body: GroundCondition
    stratum: int = 0


@dataclass(frozen=True)
class AxiomProgram:
    """Ground axioms sorted by stratum, and the mask of all derived facts."""

    rules: tuple[GroundAxiom, ...] = ()
    derived: int = 0
    _strata: list = field(default_factory=list, compare=False, hash=False, repr=False)

    def __bool__(self) -> bool:
        return bool(self.derived)

    def strata(self) -> list[tuple[GroundAxiom, ...]]:
        if not self._strata and self.rules:
            groups: dict[int, list[GroundAxiom]] = {}
            for rule in self.rules:
                groups.setdefault(rule.stratum, []).append(rule)
            self._strata.extend(tuple(groups[k]) for k in sorted(groups))
        return self._strata

    def close(self, state: int) -> int:
        """``state`` with its derived facts recomputed from its basic facts."""
        if not self.derived:
            return state
        state &= ~self.derived
        for rules in self.strata():
            pending = [r for r in rules if not r.body.never]
            fired = True
            while fired:  # naive iteration: a rule fires once its body holds
                fired = False
                waiting = []
                for rule in pending:
                    if (state >> rule.head) & 1:
                        continue
                    if rule.body.holds(state):
                        state |= 1 << rule.head
                        fired = True
                    else:
                        waiting.append(rule)
                pending = waiting
        return state


NO_AXIOMS = AxiomProgram()


@dataclass(frozen=True, slots=True)
class GroundModel:
    facts: tuple[GroundAtom, ...]
    actions: tuple[GroundAction, ...]
    init: int
    goal: GroundCondition
    objects: tuple[tuple[str, str], ...]  # (name, type)
    #: Static facts true in every state (compiled away from conditions).
    static_facts: tuple[GroundAtom, ...] = ()
    horizon: int | None = None
    #: True when the lifted model declares costs/rewards (PPDDL :rewards or stamp costs).
    has_costs: bool = False
    lifted: Model | None = field(default=None, compare=False, hash=False, repr=False)
    #: Grounding warnings (G201 no actions, G202 all costs 0, G203 conflicting effects).
    diagnostics: tuple = field(default=(), compare=False, hash=False, repr=False)
    #: Axioms deriving the derived facts of every state (empty: no derived facts).
    axioms: AxiomProgram = NO_AXIOMS
    _index: dict = field(default_factory=dict, compare=False, hash=False, repr=False)

    def __post_init__(self) -> None:
        # Successors are closed under the axioms where they are made, in
        # GroundAction.outcomes: each action learns its model's program here.
        if self.axioms:
            for action in self.actions:
                action._cache["axioms"] = self.axioms

    def fact_index(self, atom: GroundAtom) -> int:
        if not self._index:
            self._index.update({f: i for i, f in enumerate(self.facts)})
        return self._index[atom]

    def has_fact(self, atom: GroundAtom) -> bool:
        if not self._index:
            self._index.update({f: i for i, f in enumerate(self.facts)})
        return atom in self._index

    def state_facts(self, state: int) -> list[GroundAtom]:
        return [f for i, f in enumerate(self.facts) if (state >> i) & 1]

    def state_of(self, atoms: Iterable[GroundAtom]) -> int:
        s = 0
        for a in atoms:
            s |= 1 << self.fact_index(a)
        return s

    def is_goal(self, state: int) -> bool:
        return self.goal.holds(state)


# ------------------------------------------------------------- semantics
def _closed(o: Successor, state: int, axioms: AxiomProgram) -> Successor:
    after = axioms.close(o.apply(state))
    return Successor(o.probability, after & ~state, state & ~after, o.cost, o.unknown)


def _effect_branches(eff: GEffect, state: int) -> list[tuple[Fraction, int, int, Fraction, int]]:
    """All joint outcomes of ``eff`` in ``state`` as (p, add, del, cost, unknown)."""
    add, delete, cost, unknown = eff.add, eff.delete, eff.cost, eff.unknown
    branches = [(Fraction(1), add, delete, cost, unknown)]
    for cond, sub in eff.whens:
        if cond.holds(state):
            branches = _product(branches, _effect_branches(sub, state))
    for block in eff.blocks:
        options: list[tuple[Fraction, int, int, Fraction, int]] = []
        rest = Fraction(1)
        for p, sub in block.outcomes:
            rest -= p
            for q, a, d, c, u in _effect_branches(sub, state):
                options.append((p * q, a, d, c, u))
        if rest > 0:
            options.append((rest, 0, 0, Fraction(0), 0))
        branches = _product(branches, options)
    return branches


def _product(left, right):
    return [(p * q, a1 | a2, d1 | d2, c1 + c2, u1 | u2)
            for p, a1, d1, c1, u1 in left for q, a2, d2, c2, u2 in right if p * q > 0]


def outcome_distribution(action: GroundAction, state: int) -> tuple[Successor, ...]:
    """Joint outcome distribution of ``action`` in ``state``; identical outcomes merged."""
    merged: dict[tuple[int, int, Fraction, int], Fraction] = {}
    delete_wins = action.delete_wins
    for p, a, d, c, u in _effect_branches(action.effect, state):
        key = (a & ~d, d, c, u) if delete_wins else (a, d & ~a, c, u)
        merged[key] = merged.get(key, Fraction(0)) + p
    return tuple(Successor(p, a, d, action.base_cost + c, u)
                 for (a, d, c, u), p in merged.items())
