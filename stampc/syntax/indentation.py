"""Syntax errors caused by indentation, told as such.

The layout pass turns indentation into ``_INDENT``/``_DEDENT`` tokens, so a badly
indented clause surfaces as "unexpected indentation; expected a declaration" or
"unexpected end of file; expected an indented line", with a hint about column 1 that
does not fit. Here the error is recognised from the failing token and the chunk's
lines, and reported at the offending line with its indentation and the one expected.
"""

from __future__ import annotations

from stampc.diagnostics import Diagnostic, Span, error

CODE = "E001"
DEEPER_HINT = ("a line goes deeper than the one above only to continue it (after `,` `and` `or` "
               "`implies` `->` or inside parentheses) or inside a `probabilistic`, `when` or "
               "`forall` block")


def _indent(line: str) -> int:
    return len(line.expandtabs(8)) - len(line.expandtabs(8).lstrip())


def _is_code(line: str) -> bool:
    stripped = line.strip()
    return bool(stripped) and not stripped.startswith("#")


def indentation_error(tok: tuple, expected: frozenset[str], lines: list[str], file: str,
                      offset: int) -> Diagnostic | None:
    """An indentation-specific E001 for a parse failure at ``tok`` in a chunk whose
    lines are ``lines`` (first line ``offset + 1``), or None if indentation is not it."""
    kind = tok[0]
    index = tok[2] - offset - 1
    code_lines = [i for i, line in enumerate(lines) if _is_code(line)]
    at_indentation = 0 <= index < len(lines) and tok[3] == len(lines[index]) - len(lines[index].lstrip()) + 1
    if kind in ("_INDENT", "_DEDENT") and at_indentation and _is_code(lines[index]):
        return _misindented(index, code_lines, lines, file, offset)
    if expected == {"_INDENT"} and kind != "_INDENT":  # only an indented line could follow
        return _missing_indent(tok, index, at_indentation, code_lines, lines, file, offset)
    return None


def _span(index: int, lines: list[str], file: str, offset: int) -> Span:
    line = lines[index]
    col = len(line) - len(line.lstrip()) + 1
    return Span(file, index + offset + 1, col, index + offset + 1, len(line.rstrip()) + 1)


def _misindented(index: int, code_lines: list[int], lines: list[str], file: str,
                 offset: int) -> Diagnostic:
    here = _indent(lines[index])
    before = [i for i in code_lines if i < index]
    span = _span(index, lines, file, offset)
    if not before:
        return error(CODE, "unexpected indentation at the start of a declaration", span,
                     "a declaration starts at column 1; only its clauses are indented")
    previous = before[-1]
    if here > _indent(lines[previous]):
        return error(CODE, f"unexpected indentation: this line is indented deeper ({here} columns) than "
                           f"line {previous + offset + 1} above ({_indent(lines[previous])})", span, DEEPER_HINT)
    clauses = [i for i in before if _indent(lines[i]) > 0]
    if here > 0 and clauses and here < _indent(lines[clauses[0]]):
        previous = clauses[0]  # dedented past the declaration's clause column
    target = _indent(lines[previous])
    return error(CODE, f"inconsistent indentation: this line is indented {here} columns, line "
                       f"{previous + offset + 1} above {target}", span,
                 f"indent the lines of one block to the same column (line {previous + offset + 1} "
                 f"starts at column {target + 1})")


def _missing_indent(tok: tuple, index: int, at_indentation: bool, code_lines: list[int], lines: list[str],
                    file: str, offset: int) -> Diagnostic:
    """An indented line was needed before ``tok`` (on line ``index``). Layout tokens at
    the end of a line stand for what comes after it, so that line is the opener."""
    layout = tok[0] in ("$END", "_DEDENT", "_NL")
    last = index + 1 if layout and not at_indentation else index
    before = [i for i in code_lines if i < last]
    opener = before[-1] if before else 0
    if layout or not (0 <= index < len(lines)):
        span = _span(opener, lines, file, offset)
        head = lines[opener].strip()
        head = head if len(head) <= 40 else head[:37] + "..."
        return error(CODE, f"`{head}` opens a block, but no indented line follows it", span,
                     "write the block (a declaration's clauses, outcomes, effects) on the following "
                     "lines, indented deeper; a line at column 1 starts a new declaration")
    span = _span(index, lines, file, offset)
    return error(CODE, f"this line must be indented deeper than line {opener + offset + 1} above "
                       f"({_indent(lines[opener])} columns), whose block it belongs to", span,
                 "indent it further than the line that opens the block (`eff`, `probabilistic`, "
                 "`when ...:`, an outcome)")
