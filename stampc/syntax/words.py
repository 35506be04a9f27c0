"""Grammar terminals in words, for syntax error messages a human can act on."""

from __future__ import annotations

from typing import Iterable

NAMED = {
    "NAME": "a name",
    "NUMBER": "a number",
    "FRACTION": "a fraction",
    "STRING": "a string",
    "_NL": "end of line",
    "_INDENT": "an indented line",
    "_DEDENT": "end of the indented block",
    "$END": "end of file",
    "LPAR": "`(`", "RPAR": "`)`", "COMMA": "`,`", "COLON": "`:`", "EQUAL": "`=`",
    "QMARK": "`?`", "PLUS": "`+`", "MINUS": "`-`", "STAR": "`*`", "SLASH": "`/`",
    "LESS": "`<`", "ARROW": "`->`",
}
DECLARATION_KEYWORDS = {"DOMAIN", "PROBLEM", "ACTION", "PREDICATE", "TYPE", "USE"}
# keywords that start clauses or declarations: seeing one where a name is expected
# means something is missing before it, not that the user wanted it as a name
STRUCTURAL = {"pre", "eff", "cost", "executes", "sample", "certifies", "binds", "budget",
              "option", "domain", "problem", "module", "use", "type", "continuous", "static",
              "predicate", "function", "constant", "generator", "evaluator", "action", "object",
              "init", "goal", "horizon", "scene", "probabilistic", "when"}
FORMULA_STARTS = {"NOT", "FORALL", "EXISTS"}
CLAUSES = {"pre", "eff", "cost", "executes", "sample", "certifies", "binds", "budget", "option"}


def _word(terminal: str) -> str:
    if terminal in NAMED:
        return NAMED[terminal]
    if terminal.startswith("__ANON"):
        return "an operator"
    return f"`{terminal.lower()}`"


def describe_token(tok: tuple) -> str:
    kind, text = tok[0], tok[1]
    if kind == "_INDENT":
        return "indentation"
    if kind in ("_NL", "_DEDENT", "$END"):
        return NAMED[kind]
    if kind == "NAME":
        return f"name `{text}`"
    if kind in ("NUMBER", "FRACTION"):
        return f"number `{text}`"
    if kind == "STRING":
        return f"string {text}"
    if text.isidentifier():
        return f"keyword `{text}`"
    return f"`{text}`"


def describe_expected(expected: Iterable[str]) -> str:
    terms = set(expected)
    if terms & DECLARATION_KEYWORDS and len(terms) > 6:
        return "a declaration (`type`, `predicate`, `action`, `object`, `init`, `goal`, ...)"
    words: list[str] = []
    if "NAME" in terms and terms & FORMULA_STARTS:
        words.append("a predicate name")
        terms.discard("NAME")
    words.extend(sorted({_word(t) for t in terms}, key=_order))
    if not words:
        return "nothing more"
    if len(words) > 7:
        words = words[:6] + ["..."]
    if len(words) == 1:
        return words[0]
    return ", ".join(words[:-1]) + " or " + words[-1]


def _order(word: str) -> tuple[int, str]:
    # names and literals first, then keywords, then punctuation, then layout
    if word.startswith("a ") and "indented" not in word:
        rank = 0
    elif word.startswith("`") and word[1:-1].isalpha():
        rank = 1
    elif word.startswith("`") or word == "an operator":
        rank = 2
    else:
        rank = 3
    return (rank, word)


def non_ascii_hint(char: str) -> str:
    code = f"U+{ord(char):04X}"
    if char.isspace():
        return f"{code} is a non-ASCII space; use a plain space"
    return (f"{code} cannot be part of a name: names use letters of any script, digits and `_` "
            "(like Python identifiers); operators and punctuation are ASCII")


def hint_for(what: object, expected: frozenset[str]) -> str | None:
    """A short help line for common mistakes (``what`` is a token tuple or a character)."""
    if isinstance(what, str):
        if what in "[]{};":
            return "stamp uses indentation and commas instead of brackets and semicolons"
        if what == "\t":
            return "indent with spaces"
        if not what.isascii():
            return non_ascii_hint(what)
        return None
    kind, text = what[0], what[1]
    if kind == "_INDENT":
        return "only the clauses of a declaration are indented; declarations start at column 1"
    if text in CLAUSES and what[3] == 1 and expected & DECLARATION_KEYWORDS:
        return f"`{text}` starts a clause: indent it under the declaration it belongs to"
    if kind == "_NL" and "COMMA" in expected and "RPAR" not in expected:
        return "a list continues on the next line only after a trailing `,`"
    if kind not in ("NAME", "NUMBER", "FRACTION", "STRING") and text.isidentifier() \
            and "NAME" in expected and text not in STRUCTURAL:
        return f"`{text}` is a keyword and cannot be used as a name"
    return None
