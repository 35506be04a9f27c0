"""Fact sets of grounded conditions and effects, stored by density.

A Python ``int`` is a fast bitset, but one holding fact ``i`` takes ``i / 8`` bytes
whatever else it holds. In a model whose every action touches facts of its own (the
generated stamp domain: one Skolem trajectory, hence one ``collision`` fact, per action)
every action's masks are then as large as the model, and N actions need N²/8 bytes
(more than 20 GB at 165,000 actions). A :data:`FactSet` is therefore an ``int`` bitset
while that is compact — at most :data:`DENSE_BITS` bits, or at least one set bit in 64 —
and otherwise a :class:`Sparse` tuple of its ascending fact indices.

The representation is a function of the set alone (:func:`pack` is canonical), so two
equal sets are equal ``FactSet`` values and the dataclasses holding them keep comparing
and hashing by value. States stay ``int``: a state is as large as the model anyway.
Every normal benchmark (at most a few thousand facts) only ever has ``int`` fact sets.
"""

from __future__ import annotations

from itertools import chain
from typing import Iterable, Sequence, Union

#: Fact sets whose highest fact is below this stay ints, however sparse (512 bytes).
DENSE_BITS = 4096
#: An int of more bits is kept only if it has a set bit per this many bits (an index in
#: a tuple costs about 64 bits).
_BITS_PER_INDEX = 64
#: :func:`bits_to_list` peels the highest bits off one by one (a pass over the int
#: each); past this many it reads the rest word by word (one pass in all).
_PEEL = 64


class Sparse(tuple):
    """Ascending fact indices of a set too sparse for an int bitset (never empty)."""

    __slots__ = ()


FactSet = Union[int, Sparse]


def bits_to_list(mask: int) -> list[int]:
    """Indices of the set bits of ``mask``, ascending, in time linear in its size (a
    bit-by-bit loop is quadratic for an int whose few bits sit near bit 165,000)."""
    top_bits: list[int] = []
    while mask and len(top_bits) < _PEEL:
        top = mask.bit_length() - 1
        top_bits.append(top)
        mask ^= 1 << top
    out = _dense_bits(mask) if mask else []
    out.extend(reversed(top_bits))
    return out


def _dense_bits(mask: int) -> list[int]:
    out: list[int] = []
    words = memoryview(mask.to_bytes((mask.bit_length() + 63) // 64 * 8, "little")).cast("Q")
    for k, word in enumerate(words):
        base = 64 * k
        while word:
            low = word & -word
            out.append(base + low.bit_length() - 1)
            word ^= low
    return out


def list_to_int(indices: Sequence[int]) -> int:
    """The int bitset of non-negative ``indices`` (any order), in linear time."""
    if len(indices) <= _PEEL:
        mask = 0
        for i in indices:
            mask |= 1 << i
        return mask
    raw = bytearray((max(indices) >> 3) + 1)
    for i in indices:
        raw[i >> 3] |= 1 << (i & 7)
    return int.from_bytes(raw, "little")


def _dense(top: int, count: int) -> bool:
    return top <= DENSE_BITS or top <= _BITS_PER_INDEX * count


def pack(mask: FactSet) -> FactSet:
    """The canonical fact set of an int bitset (a :class:`Sparse` one is returned as is)."""
    if mask.__class__ is int:
        if mask.bit_length() <= DENSE_BITS:  # the common case: one C call
            return mask
        if mask < 0:
            raise ValueError("a fact set cannot be a negative int")
        return mask if _dense(mask.bit_length(), mask.bit_count()) else Sparse(bits_to_list(mask))
    if mask.__class__ is Sparse:
        return mask
    raise TypeError(f"a fact set is an int bitset or a Sparse tuple, got {mask!r}")


def from_indices(indices: Iterable[int]) -> FactSet:
    """The canonical fact set of non-negative fact ``indices`` (any order, repeats allowed)."""
    mask = 0
    high: list[int] = []
    for i in indices:
        if i < DENSE_BITS:
            mask |= 1 << i
        else:
            high.append(i)
    if not high:
        return mask
    ordered = sorted(set(high))
    if mask:
        ordered = bits_to_list(mask) + ordered
    if _dense(ordered[-1] + 1, len(ordered)):
        return list_to_int(ordered)
    return Sparse(ordered)


def single(fact: int) -> FactSet:
    """The fact set ``{fact}``."""
    return 1 << fact if fact < DENSE_BITS else Sparse((fact,))


def as_int(facts: FactSet) -> int:
    """The int bitset of a fact set (built on demand for a sparse one)."""
    return facts if facts.__class__ is int else list_to_int(facts)


def indices(facts: FactSet) -> Sequence[int]:
    """Ascending fact indices of a fact set."""
    return facts if facts.__class__ is Sparse else bits_to_list(facts)


def union_all(sets: Iterable[FactSet]) -> FactSet:
    """The union of fact sets (ints are OR-ed, sparse ones united by index)."""
    mask = 0
    high: list[int] = []
    for s in sets:
        if s.__class__ is int:
            mask |= s
        else:
            high.extend(s)
    return from_indices(chain(bits_to_list(mask), high)) if high else pack(mask)
