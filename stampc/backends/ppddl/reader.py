"""PPDDL text → s-expressions: a regex tokenizer and an explicit-stack reader.

PPDDL is s-expressions, so reading is one linear pass: every token is a word or a
parenthesis, lists are built with an explicit stack (any nesting depth, no recursion),
and positions are kept as character offsets. Line and column are only computed when a
diagnostic needs them (:class:`LineIndex`), which keeps reading at about a million
tokens per second.
"""

from __future__ import annotations

import re
from bisect import bisect_right

from stampc.backends.ppddl.codes import SYNTAX
from stampc.diagnostics import Diagnostic, Span, StampcError, error

#: PPDDL is case-insensitive; only ASCII letters are folded so columns never move.
_ASCII_LOWER = str.maketrans("ABCDEFGHIJKLMNOPQRSTUVWXYZ", "abcdefghijklmnopqrstuvwxyz")

# Group 1: '(' ; group 2: ')' ; group 3: a word. Whitespace and comments match no group.
# Words are exactly the terminals of grammar/ppddl.lark (names, ?variables, :keywords,
# numbers, operators), so any other character is a located syntax error.
_TOKEN = re.compile(r"""
    [ \t\n\r\f\v\ufeff]+ | ;[^\n]*
  | (\() | (\))
  | ( \?[a-z_][a-z0-9_\-]*
    | :[a-z][a-z0-9_\-]*
    | -?(?:\d+/\d+|\d+\.\d*|\.\d+|\d+)
    | [a-z_][a-z0-9_\-]*
    | [-+*/=] )
""", re.VERBOSE)


class Tok:
    """A word with its [start, end) character offsets in the folded text."""

    __slots__ = ("text", "start", "end")

    def __init__(self, text: str, start: int, end: int):
        self.text, self.start, self.end = text, start, end

    def __str__(self) -> str:
        return self.text

    def __repr__(self) -> str:
        return f"Tok({self.text!r}@{self.start})"


class SList:
    """A parenthesised list; ``start`` is the offset of '(' and ``end`` is just past ')'."""

    __slots__ = ("items", "start", "end")

    def __init__(self, items: list, start: int, end: int):
        self.items, self.start, self.end = items, start, end


class LineIndex:
    """Character offset → 1-based (line, column), built on first use."""

    def __init__(self, text: str, filename: str):
        self.text, self.file = text, filename
        self._starts: list[int] | None = None

    def position(self, offset: int) -> tuple[int, int]:
        if self._starts is None:
            self._starts = [0] + [m.end() for m in re.finditer("\n", self.text)]
        line = bisect_right(self._starts, offset)
        return line, offset - self._starts[line - 1] + 1

    def span(self, start: int, end: int) -> Span:
        line, col = self.position(start)
        end_line, end_col = self.position(max(start, end))
        return Span(self.file, line, col, end_line, end_col)

    def end_of_file(self) -> Span:
        line, col = self.position(len(self.text))
        return Span(self.file, line, col, line, col + 1)


def fold_case(text: str) -> str:
    return text.translate(_ASCII_LOWER)


def read(text: str, index: LineIndex) -> list:
    """The top-level items (``SList`` or ``Tok``) of ``text``; P100 on a bad character or
    unbalanced parentheses."""
    stack: list[tuple[list, int]] = []
    current: list = []
    pos = 0
    for m in _TOKEN.finditer(text):
        start = m.start()
        if start != pos:
            break  # finditer skipped a character no token matches
        pos = m.end()
        kind = m.lastindex
        if kind == 3:
            current.append(Tok(m.group(3), start, pos))
        elif kind == 1:
            stack.append((current, start))
            current = []
        elif kind == 2:
            if not stack:
                _fail(index, start, "unexpected ')'; expected '(' or end of file")
            items = current
            current, opened = stack.pop()
            current.append(SList(items, opened, pos))
    if pos != len(text):
        _fail(index, pos, f"unexpected character {text[pos]!r}",
              hint="names are letters, digits, '-' and '_'; ';' starts a comment")
    if stack:
        raise StampcError([error(SYNTAX, "unexpected end of file; expected ')'",
                                 index.end_of_file(),
                                 hint=f"the '(' at {_where(index, stack[-1][1])} is never closed")])
    return current


def _where(index: LineIndex, offset: int) -> str:
    line, col = index.position(offset)
    return f"line {line}, column {col}"


def _fail(index: LineIndex, offset: int, message: str, hint: str | None = None) -> None:
    raise StampcError([_diag(index, offset, message, hint)])


def _diag(index: LineIndex, offset: int, message: str, hint: str | None) -> Diagnostic:
    return error(SYNTAX, message, index.span(offset, offset + 1), hint)
