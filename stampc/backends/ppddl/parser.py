"""PPDDL text → syntax trees of its definitions, with located syntax errors.

PPDDL is s-expressions: :mod:`reader` tokenizes with one regular expression and builds
lists with an explicit stack; :mod:`shape` checks each list against the dialect of
``grammar/ppddl.lark`` (the reference grammar; a test checks both accept the same
benchmarks) and builds :class:`~stampc.backends.ppddl.shape_base.Node` trees. No
recursion depends on the input's paren depth except through formulas, which stop at
``MAX_NESTING`` (P108). No Lark at run time: imports stay cheap and reading runs at
roughly a million tokens per second (``bench/ppddl_import.py``).
"""

from __future__ import annotations

from dataclasses import dataclass

from stampc.backends.ppddl.reader import LineIndex, fold_case, read
from stampc.backends.ppddl.shape import Shaper
from stampc.backends.ppddl.shape_base import Node

GRAMMAR_NAME = "ppddl.lark"

__all__ = ["Parsed", "fold_case", "parse_text"]


@dataclass(frozen=True)
class Parsed:
    """The definitions of one source and the index that locates their offsets."""

    definitions: tuple[Node, ...]
    index: LineIndex


def parse_text(text: str, filename: str) -> Parsed:
    """Parse PPDDL ``text``; raise :class:`StampcError` (P100/P101/P108/P109) on syntax
    errors (the first one found)."""
    folded = fold_case(text)
    index = LineIndex(folded, filename)
    return Parsed(tuple(Shaper(index).definitions(read(folded, index))), index)
