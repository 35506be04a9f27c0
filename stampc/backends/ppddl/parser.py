"""PPDDL text → Lark parse tree, with syntax errors turned into located diagnostics.

The grammar (``grammar/ppddl.lark``) is compiled once (cached on disk) with
Lark's LALR(1) parser and contextual lexer, which keeps importing the largest IPPC
benchmark (SysAdmin p15, 90 kB, 1920 objects) at about 0.2 s.
"""

from __future__ import annotations

import re
from functools import lru_cache
from importlib import resources
from pathlib import Path

import lark
from lark.lexer import PatternStr

from stampc.backends.ppddl.codes import SYNTAX, UNSUPPORTED
from stampc.diagnostics import Diagnostic, Span, StampcError, error
from stampc.grammar_cache import cached_lark

GRAMMAR_NAME = "ppddl.lark"

#: PPDDL is case-insensitive; only ASCII letters are folded so columns never move.
_ASCII_LOWER = str.maketrans("ABCDEFGHIJKLMNOPQRSTUVWXYZ", "abcdefghijklmnopqrstuvwxyz")

#: Words for the regex terminals when listing what the parser expected.
_TERMINAL_WORDS = {
    "NAME": "a name",
    "VAR": "a variable such as ?x",
    "NUMBER": "a number",
    "REQUIREMENT": "a requirement flag such as :typing",
    "NUMOP": "an arithmetic operator (+ - * /)",
    "$END": "end of file",
}

#: Well-known PDDL constructs outside the supported dialect: reported as P101.
_UNSUPPORTED_WORDS = {
    ":derived": "derived predicates (:derived)",
    ":durative-action": "durative actions",
    ":constraints": "state-trajectory constraints",
    ":process": "processes",
    ":event": "events",
    "assign": "numeric assignment effects",
    "scale-up": "numeric scale-up effects",
    "scale-down": "numeric scale-down effects",
    "oneof": "non-deterministic oneof effects",
    "preference": "preferences",
}

_WORD_AT = re.compile(r"[^\s()]+")


def grammar_path() -> Path | None:
    """``<repo>/grammar/ppddl.lark`` relative to this package, if present."""
    candidate = Path(__file__).resolve().parents[3] / "grammar" / GRAMMAR_NAME
    return candidate if candidate.is_file() else None


def grammar_text() -> str:
    """The grammar source: the repository copy first, then the installed package data."""
    path = grammar_path()
    if path is not None:
        return path.read_text(encoding="utf-8")
    return resources.files("stampc.grammar").joinpath(GRAMMAR_NAME).read_text(encoding="utf-8")


@lru_cache(maxsize=1)
def ppddl_parser() -> lark.Lark:
    # Positions are propagated so diagnostics on a construct start at its '('. The compiled
    # parser is kept on disk between processes (start-up time; see stampc.grammar_cache).
    return cached_lark(grammar_text(), parser="lalr", lexer="contextual",
                     propagate_positions=True, maybe_placeholders=False)


def fold_case(text: str) -> str:
    return text.translate(_ASCII_LOWER)


def parse_text(text: str, filename: str) -> lark.Tree:
    """Parse PPDDL ``text``; raise :class:`StampcError` (P100/P101) on syntax errors."""
    folded = fold_case(text)
    try:
        return ppddl_parser().parse(folded)
    except lark.exceptions.UnexpectedInput as exc:
        raise StampcError([syntax_diagnostic(exc, folded, filename)]) from None


# ------------------------------------------------------------------ errors
def syntax_diagnostic(exc: lark.exceptions.UnexpectedInput, text: str,
                      filename: str) -> Diagnostic:
    """A located P100 (or P101 for a known unsupported construct) for a Lark error."""
    if isinstance(exc, lark.exceptions.UnexpectedToken) and exc.token.type != "$END":
        line, col = exc.token.line, exc.token.column
        expected = exc.accepts or exc.expected
    elif isinstance(exc, (lark.exceptions.UnexpectedToken, lark.exceptions.UnexpectedEOF)):
        line, col = _end_position(text)
        expected = getattr(exc, "accepts", None) or exc.expected
    else:  # UnexpectedCharacters
        line, col = exc.line, exc.column
        expected = exc.allowed
    offset = _offset(text, line, col)
    word = _word_at(text, offset)
    span = Span(filename, line, col, line, col + max(1, len(word)))
    expected_words = describe_expected(expected)
    if word in _UNSUPPORTED_WORDS:
        return error(UNSUPPORTED, f"unsupported construct: {_UNSUPPORTED_WORDS[word]}", span,
                     hint="stampc reads the IPPC PPDDL dialect; see docs/ppddl.md")
    found = f"'{word}'" if word else "end of file"
    return error(SYNTAX, f"unexpected {found}; expected {expected_words}", span)


def describe_expected(terminals) -> str:
    names = {t.name: t.pattern for t in ppddl_parser().terminals}
    words = set()
    for term in terminals or ():
        if term in _TERMINAL_WORDS:
            words.add(_TERMINAL_WORDS[term])
        elif term in names and isinstance(names[term], PatternStr):
            words.add(f"'{names[term].value}'")
        else:
            words.add(term.lower())
    ordered = sorted(words, key=lambda w: (not w.startswith("'"), w))
    if not ordered:
        return "nothing more"
    if len(ordered) == 1:
        return ordered[0]
    return "one of " + ", ".join(ordered)


def _end_position(text: str) -> tuple[int, int]:
    lines = text.split("\n")
    return len(lines), len(lines[-1]) + 1


def _offset(text: str, line: int, col: int) -> int:
    pos = 0
    for _ in range(line - 1):
        nxt = text.find("\n", pos)
        if nxt < 0:
            return len(text)
        pos = nxt + 1
    return min(len(text), pos + col - 1)


def _word_at(text: str, offset: int) -> str:
    if offset < len(text) and text[offset] in "()":
        return text[offset]
    match = _WORD_AT.match(text, offset)
    return match.group(0) if match else ""
