"""Lexing and line layout for stamp: text → token tuples with ``_NL``/``_INDENT``/``_DEDENT``.

Tokens are plain tuples ``(type, text, line, col, end_line, end_col)`` (fast to create;
the parser in :mod:`stampc.syntax.parser` consumes them). Keywords are the grammar's
alphabetic string terminals and are reserved everywhere.

A physical line continues onto the next one (no token is produced) when it ends inside
parentheses or with a token that cannot end a statement (``,``, ``and``, ``or``,
``implies``, ``->``). Indentation is forgiving: dedenting to a column between two open
levels closes the deeper level and opens a new one, so hanging alignment such as
``eff  a`` followed by ``     b`` works as users expect.
"""

from __future__ import annotations

import re
import unicodedata
from typing import Iterator
from dataclasses import dataclass

Tok = tuple  # (type, text, line, col, end_line, end_col)

NL, INDENT, DEDENT, END = "_NL", "_INDENT", "_DEDENT", "$END"
# combining marks (accents typed as separate code points) continue a name, as in Python
COMBINING = "\u0300-\u036f\u1ab0-\u1aff\u1dc0-\u1dff\u20d0-\u20ff\ufe20-\ufe2f"
CONTINUES_LINE = frozenset({"COMMA", "AND", "OR", "IMPLIES", "ARROW"})


class LexError(Exception):
    """An unexpected character; carries its position (absolute line, 1-based column)."""

    def __init__(self, char: str, line: int, col: int):
        super().__init__(f"unexpected character {char!r}")
        self.char, self.line, self.col = char, line, col


@dataclass(frozen=True)
class LexerSpec:
    """Keyword and punctuation terminal names, taken from the grammar."""

    keywords: dict[str, str]
    punctuation: dict[str, str]

    def pattern(self) -> re.Pattern:
        """One regex for every token; leading blanks are consumed by the same match and
        anything unmatched lands in ``ERR`` (so ``finditer`` never skips text)."""
        puncts = sorted(self.punctuation, key=len, reverse=True)
        return re.compile("[ \\t\\f]*(?:" + "|".join([
            # the most frequent tokens first (no two alternatives start alike, except
            # NL before COMMENT and FRACTION before NUMBER, which keep their order)
            rf"(?P<NAME>[^\W\d][\w{COMBINING}]*)",  # letters of any script, digits, `_`
            "(?P<PUNCT>" + "|".join(re.escape(p) for p in puncts) + ")",
            r"(?P<NL>(?:\n[ \t\f]*|#[^\n]*)*\n[ \t\f]*)",
            r"(?P<COMMENT>#[^\n]*)",
            r'(?P<STRING>"(?:\\.|[^"\\\n])*")',
            r"(?P<FRACTION>\d+/\d+)",
            r"(?P<NUMBER>\d+(?:\.\d+)?)",
            r"(?P<ERR>.)",
        ]) + ")")


def tokenize(text: str, spec: LexerSpec, pattern: re.Pattern, line_offset: int = 0) -> Iterator[Tok]:
    """Layout-processed tokens for ``text`` whose first line is ``line_offset + 1``
    (a generator: tokens are consumed as they are made, keeping memory small)."""
    keywords, punctuation = spec.keywords, spec.punctuation
    levels = [0]
    depth = 0
    prev_type = None  # type of the last significant token (None at start of input)
    line, line_start, n = line_offset + 1, 0, len(text)
    for m in pattern.finditer(text):
        kind = m.lastgroup
        if kind is None:  # trailing blanks at the end of the text
            continue
        start = m.start(kind)
        if kind == "NAME":
            value = m.group(kind)
            if not value.isascii():
                col = start - line_start + 1
                name = unicode_name(value, line, col)
                yield (keywords.get(name, "NAME"), name, line, col, line, col + len(value))
                prev_type = "NAME"
                continue
            kind = keywords.get(value, "NAME")
        elif kind == "NL":
            chunk = m.group(kind)
            col = start - line_start + 1
            nl_line = line
            line += chunk.count("\n")
            end = m.end()
            line_start = start + chunk.rfind("\n") + 1
            if depth or prev_type is None or prev_type in CONTINUES_LINE or prev_type == NL:
                continue
            yield (NL, "", nl_line, col, nl_line, col + 1)
            prev_type = NL
            indent = len(text[line_start:end].expandtabs(8)) if end < n else 0
            yield from _relevel(levels, indent, line, end - line_start + 1)
            continue
        elif kind == "COMMENT":
            continue
        elif kind == "PUNCT":
            value = m.group(kind)
            kind = punctuation[value]
            if kind == "LPAR":
                depth += 1
            elif kind == "RPAR" and depth:
                depth -= 1
        elif kind == "ERR":
            raise LexError(m.group(kind), line, start - line_start + 1)
        else:
            value = m.group(kind)
        col = start - line_start + 1
        yield (kind, value, line, col, line, col + len(value))
        prev_type = kind
    col = n - line_start + 1
    if prev_type is not None and prev_type != NL:
        yield (NL, "", line, col, line, col + 1)
    while len(levels) > 1:
        levels.pop()
        yield (DEDENT, "", line, col, line, col + 1)
    yield (END, "", line, col, line, col + 1)


def unicode_name(raw: str, line: int, col: int) -> str:
    """A non-ASCII name, NFKC-normalised as Python normalises identifiers (so both
    spellings of an accented letter are one name); a character that no Python
    identifier may hold (``x²``, checked before normalising, as Python does) is a
    :class:`LexError` at its column."""
    if raw.isidentifier():
        return unicodedata.normalize("NFKC", raw)
    for i, ch in enumerate(raw):
        if not ("a" + ch).isidentifier():
            raise LexError(ch, line, col + i)
    raise LexError(raw[0], line, col)


def _relevel(levels: list[int], indent: int, line: int, col: int) -> Iterator[Tok]:
    if indent > levels[-1]:
        levels.append(indent)
        yield (INDENT, "", line, col, line, col + 1)
        return
    while indent < levels[-1]:
        levels.pop()
        yield (DEDENT, "", line, col, line, col + 1)
    if indent > levels[-1]:  # dedent between two levels: reopen at the new column
        levels.append(indent)
        yield (INDENT, "", line, col, line, col + 1)
