"""Shared pieces of the s-expression → syntax-tree shaper: the tree node, word classes
and located syntax errors (P100, P101 unsupported, P108 too deep, P109 FOND ``oneof``).

The tree shape follows ``grammar/ppddl.lark`` rule for rule (``gd_and``, ``eff_prob``,
``typed_list`` ...), so the lowering reads one documented structure.
"""

from __future__ import annotations

from typing import NoReturn

from stampc.backends.ppddl import codes
from stampc.backends.ppddl.reader import LineIndex, SList, Tok
from stampc.diagnostics import StampcError, error

#: Deepest nesting of formulas, effects and numeric expressions (``not``, ``imply``,
#: quantifiers, ``when``, ``probabilistic``, arithmetic). ``and``/``or`` chains are
#: flattened while reading, so they may nest to any depth. Documented in docs/ppddl.md.
MAX_NESTING = 100

#: Well-known PDDL constructs outside the supported dialect: reported as P101.
UNSUPPORTED_WORDS = {
    ":durative-action": "durative actions",
    ":constraints": "state-trajectory constraints",
    ":process": "processes",
    ":event": "events",
    "assign": "numeric assignment effects",
    "scale-up": "numeric scale-up effects",
    "scale-down": "numeric scale-down effects",
    "preference": "preferences",
}
FOND_WORD = "oneof"
_OPS = frozenset("-+*/=")
#: first characters of a name / of a term (name or ?variable): one set lookup per word
NAME_START = frozenset("abcdefghijklmnopqrstuvwxyz_")
TERM_START = NAME_START | {"?"}


class Node:
    """A syntax-tree node: grammar rule name, children (``Node`` / ``Tok``), offsets."""

    __slots__ = ("data", "children", "start", "end")

    def __init__(self, data: str, children: list, start: int, end: int):
        self.data, self.children, self.start, self.end = data, children, start, end

    def __repr__(self) -> str:
        return f"Node({self.data!r}, {self.children!r})"


def is_name(x) -> bool:
    return type(x) is Tok and x.text[0] in NAME_START


def is_var(x) -> bool:
    return isinstance(x, Tok) and x.text[0] == "?"


def is_keyword(x) -> bool:
    return isinstance(x, Tok) and x.text[0] == ":"


def is_number(x) -> bool:
    if not isinstance(x, Tok):
        return False
    c = x.text[0]
    return c.isdigit() or c == "." or (c == "-" and len(x.text) > 1)


def is_op(x) -> bool:
    return isinstance(x, Tok) and x.text in _OPS


def head(sl: SList) -> str | None:
    """The first word of a list, if it is a word."""
    return sl.items[0].text if sl.items and isinstance(sl.items[0], Tok) else None


class ShapeBase:
    def __init__(self, index: LineIndex):
        self.index = index

    # ------------------------------------------------------------ errors
    def fail(self, found, expected: str) -> NoReturn:
        """P100 at ``found`` (a word, a list, or ``None`` with ``closing`` for a missing
        item); P101/P109 when the offending word names a known unsupported construct."""
        word = found if isinstance(found, Tok) else None
        if isinstance(found, SList) and found.items and isinstance(found.items[0], Tok):
            first = found.items[0]
            word = first if first.text in UNSUPPORTED_WORDS or first.text == FOND_WORD else None
        if word is not None:
            self._unsupported(word)
        if isinstance(found, Tok):
            start, shown = found.start, f"'{found.text}'"
        else:
            start, shown = found.start, "'('"
        self.raise_at(codes.SYNTAX, f"unexpected {shown}; expected {expected}", start,
                      start + (len(found.text) if isinstance(found, Tok) else 1))

    def missing(self, sl: SList, expected: str) -> NoReturn:
        """P100 at the ')' closing ``sl``, which came before an expected item."""
        self.raise_at(codes.SYNTAX, f"unexpected ')'; expected {expected}", sl.end - 1, sl.end)

    def check_end(self, sl: SList, i: int) -> None:
        """``sl`` must end after item ``i - 1``."""
        if len(sl.items) > i:
            self.fail(sl.items[i], "')'")

    def _unsupported(self, word: Tok) -> None:
        if word.text == FOND_WORD:
            self.raise_at(codes.FOND, "FOND (oneof ...) effects are not supported: stampc "
                          "reads probabilistic PPDDL (MDPs/SSPs)", word.start, word.end,
                          hint="give each outcome a probability: (probabilistic p1 e1 p2 e2 ...)")
        if word.text in UNSUPPORTED_WORDS:
            self.raise_at(codes.UNSUPPORTED,
                          f"unsupported construct: {UNSUPPORTED_WORDS[word.text]}",
                          word.start, word.end,
                          hint="stampc reads the IPPC PPDDL dialect; see docs/ppddl.md")

    def too_deep(self, x) -> NoReturn:
        self.raise_at(codes.TOO_DEEP, f"nested more than {MAX_NESTING} levels deep",
                      x.start, x.start + 1,
                      hint=f"stampc reads formulas, effects and numeric expressions up to "
                           f"{MAX_NESTING} levels deep (and/or chains of any depth)")

    def raise_at(self, code: str, message: str, start: int, end: int,
                 hint: str | None = None) -> NoReturn:
        raise StampcError([error(code, message, self.index.span(start, end), hint)])

    # ----------------------------------------------------------- helpers
    def item(self, sl: SList, i: int, expected: str):
        if i >= len(sl.items):
            self.missing(sl, expected)
        return sl.items[i]

    def name(self, sl: SList, i: int, expected: str = "a name") -> Tok:
        x = self.item(sl, i, expected)
        if not is_name(x):
            self.fail(x, expected)
        return x

    def typed(self, sl: SList, first: int, variables: bool) -> Node:
        """A flat ``typed_list`` (names) or ``typed_vars`` (variables) from item ``first``:
        words and ``type_mark`` nodes, grouped later by the lowering."""
        accept = is_var if variables else is_name
        expected = ("a variable such as ?x, '-' or ')'" if variables
                    else "a name, '-' or ')'")
        children: list = []
        items = sl.items
        i = first
        while i < len(items):
            x = items[i]
            if isinstance(x, Tok) and x.text == "-":
                spec = self._type_spec(sl, i + 1)
                children.append(Node("type_mark", [spec], x.start, spec.end))
                i += 2
                continue
            if not accept(x):
                self.fail(x, expected)
            children.append(x)
            i += 1
        return Node("typed_vars" if variables else "typed_list", children, sl.start, sl.end)

    def _type_spec(self, sl: SList, i: int):
        x = self.item(sl, i, "a type name")
        if is_name(x):
            return x
        if isinstance(x, SList) and head(x) == "either":
            names = [self.name(x, j, "a type name") for j in range(1, max(2, len(x.items)))]
            return Node("either_type", names, x.start, x.end)
        self.fail(x, "a type name or (either ...)")
