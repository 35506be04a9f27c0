"""Conditions of the grounded IR: literals, conjunctions, disjunctions over fact indices.

A :class:`GroundCondition` keeps its conjunctive part as two fact sets (``pos`` ⊆ state,
``neg`` ∩ state = ∅) and anything else (disjunctions, nested formulas) in ``rest``.
Split out of ``grounded.py``, which re-exports every name here.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterator, Union

from stampc.ir.masks import DENSE_BITS, FactSet, as_int, pack


def bits(mask: int) -> Iterator[int]:
    """Indices of the set bits of ``mask``, ascending."""
    if mask.bit_length() <= 256:
        while mask:
            low = mask & -mask
            yield low.bit_length() - 1
            mask ^= low
        return
    # A large mask: each ``mask & -mask`` above costs O(size), so peeling k bits costs
    # O(k·size) (a 60-can table's relaxed model spent 3.7 s here). Scanning its binary
    # text from the low end with str.rfind costs O(size) in all.
    text = bin(mask)
    last = len(text) - 1
    i = text.rfind("1", 2)
    while i >= 2:
        yield last - i
        i = text.rfind("1", 2, i)


# ------------------------------------------------------------ conditions
@dataclass(frozen=True, slots=True)
class GLit:
    fact: int
    positive: bool = True


@dataclass(frozen=True, slots=True)
class GAnd:
    args: tuple["GFormula", ...]


@dataclass(frozen=True, slots=True)
class GOr:
    args: tuple["GFormula", ...]


GFormula = Union[GLit, GAnd, GOr]


_DENSE_LIMIT = 1 << DENSE_BITS


def fact_set(mask: FactSet) -> FactSet:
    """``mask`` as stored: an int, or a sorted index tuple where an int would be sparse."""
    # pack()'s common case first: grounding builds millions of conditions and effects
    return mask if mask.__class__ is int and 0 <= mask < _DENSE_LIMIT else pack(mask)


@dataclass(frozen=True, init=False, slots=True)
class GroundCondition:
    """Conjunction ``pos ⊆ s``, ``neg ∩ s = ∅`` plus non-conjunctive remainder ``rest``.

    ``never`` marks a condition simplified to false during grounding. ``pos`` and ``neg``
    accept and give int bitsets; they are stored as fact sets (``pos_facts``,
    ``neg_facts``).
    """

    pos_facts: FactSet
    neg_facts: FactSet
    rest: tuple[GFormula, ...]
    never: bool

    def __init__(self, pos: FactSet = 0, neg: FactSet = 0, rest: tuple[GFormula, ...] = (),
                 never: bool = False) -> None:
        setattr_ = object.__setattr__  # frozen
        setattr_(self, "pos_facts", fact_set(pos))
        setattr_(self, "neg_facts", fact_set(neg))
        setattr_(self, "rest", rest)
        setattr_(self, "never", never)

    @property
    def pos(self) -> int:
        return as_int(self.pos_facts)

    @property
    def neg(self) -> int:
        return as_int(self.neg_facts)

    def holds(self, state: int) -> bool:
        if self.never:
            return False
        pos, neg = self.pos_facts, self.neg_facts
        if pos.__class__ is not int:
            pos = as_int(pos)
        if (state & pos) != pos or (state & (neg if neg.__class__ is int else as_int(neg))):
            return False
        return all(_eval(f, state) for f in self.rest)

    @property
    def is_trivial(self) -> bool:
        return not (self.pos_facts or self.neg_facts or self.rest or self.never)


TRIVIAL = GroundCondition()


def _eval(f: GFormula, state: int) -> bool:
    if isinstance(f, GLit):
        return bool((state >> f.fact) & 1) == f.positive
    if isinstance(f, GAnd):
        return all(_eval(a, state) for a in f.args)
    return any(_eval(a, state) for a in f.args)


# --------------------------------------------------------------- effects
