"""Located diagnostics shared by every pipeline stage.

A :class:`Diagnostic` always carries a :class:`Span` (file, line, column, end) so that
users are told *where* something is wrong. Stages never raise bare Python exceptions for
bad input: they collect diagnostics, and API entry points raise :class:`StampcError`
carrying them.
"""

from __future__ import annotations

import json
import unicodedata
from dataclasses import dataclass, field
from enum import Enum
from typing import Iterable, Sequence


class Severity(str, Enum):
    ERROR = "error"
    WARNING = "warning"
    NOTE = "note"


@dataclass(frozen=True, order=True, slots=True)
class Span:
    """A half-open source region; lines and columns are 1-based (``slots``: a large
    domain has millions of spans, and a ``__dict__`` would double their memory)."""

    file: str
    line: int
    col: int
    end_line: int
    end_col: int

    @staticmethod
    def point(file: str, line: int = 1, col: int = 1) -> "Span":
        return Span(file, line, col, line, col + 1)

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}"


@dataclass(frozen=True)
class Label:
    """A secondary span with a short message (e.g. 'first defined here')."""

    span: Span
    message: str


@dataclass(frozen=True)
class Diagnostic:
    code: str
    severity: Severity
    message: str
    span: Span
    hint: str | None = None
    labels: tuple[Label, ...] = ()

    @property
    def is_error(self) -> bool:
        return self.severity is Severity.ERROR

    def to_json(self) -> dict:
        def span_json(s: Span) -> dict:
            return {"file": s.file, "line": s.line, "col": s.col,
                    "end_line": s.end_line, "end_col": s.end_col}

        return {
            "code": self.code,
            "severity": self.severity.value,
            "message": self.message,
            "span": span_json(self.span),
            "hint": self.hint,
            "labels": [{"span": span_json(l.span), "message": l.message} for l in self.labels],
        }


def error(code: str, message: str, span: Span, hint: str | None = None,
          labels: Sequence[Label] = ()) -> Diagnostic:
    return Diagnostic(code, Severity.ERROR, message, span, hint, tuple(labels))


def warning(code: str, message: str, span: Span, hint: str | None = None,
            labels: Sequence[Label] = ()) -> Diagnostic:
    return Diagnostic(code, Severity.WARNING, message, span, hint, tuple(labels))


class StampcError(Exception):
    """The one exception type the public API raises for bad input."""

    def __init__(self, diagnostics: Iterable[Diagnostic]):
        self.diagnostics: tuple[Diagnostic, ...] = tuple(diagnostics)
        first = next((d for d in self.diagnostics if d.is_error), None)
        summary = f"{first.span}: {first.code} {first.message}" if first else "stampc error"
        super().__init__(summary)


def has_errors(diags: Iterable[Diagnostic]) -> bool:
    return any(d.is_error for d in diags)


def sort_key(d: Diagnostic) -> tuple:
    return (d.span.file, d.span.line, d.span.col, d.code)


# ---------------------------------------------------------------- rendering

@dataclass
class SourceCache:
    """Maps file names to their text so renderers can quote source lines."""

    texts: dict[str, str] = field(default_factory=dict)
    _lines: dict[str, list[str]] = field(default_factory=dict, repr=False)

    def add(self, file: str, text: str) -> None:
        self.texts[file] = text.removeprefix("\ufeff")  # a byte-order mark is not a column
        self._lines.pop(file, None)

    def line(self, file: str, lineno: int) -> str | None:
        lines = self._lines.get(file)
        if lines is None:  # split once per file: quoting many diagnostics stays linear
            text = self.texts.get(file)
            if text is None:
                try:
                    with open(file, encoding="utf-8", errors="replace") as fh:
                        text = fh.read().removeprefix("\ufeff")
                except OSError:
                    return None
                self.texts[file] = text
            lines = self._lines[file] = text.splitlines()
        if 1 <= lineno <= len(lines):
            return lines[lineno - 1]
        return None


def render_human(d: Diagnostic, sources: SourceCache | None = None) -> str:
    """rustc/ruff style: header, quoted line, caret underline, labels, help."""
    sources = sources or SourceCache()
    out = [f"{d.span}: {d.code} {d.severity.value}: {d.message}"]
    out.extend(_quote(d.span, sources, ""))
    for label in d.labels:
        out.append(f"  note: {label.message} at {label.span}")
        out.extend(_quote(label.span, sources, ""))
    if d.hint:
        out.append(f"  help: {d.hint}")
    return "\n".join(out)


def _quote(span: Span, sources: SourceCache, _prefix: str) -> list[str]:
    text = sources.line(span.file, span.line)
    if text is None:
        return []
    text = text.expandtabs(4) if "\t" not in text[: span.col] else text
    text, col = _window(_printable(text), span.col)
    gutter = f"{span.line:>4} | "
    end_col = span.end_col - (span.col - col)
    width = max(1, (end_col - col) if span.end_line == span.line else len(text) - col + 1)
    caret = " " * (len(gutter) - 2) + "| " + " " * (col - 1) + "^" * min(width, QUOTE_WIDTH)
    return [gutter + text, caret]


QUOTE_WIDTH = 160  # longer source lines (minified or binary input) are quoted in part


def _window(text: str, col: int) -> tuple[str, int]:
    """At most QUOTE_WIDTH characters of ``text`` around column ``col`` (and its new column)."""
    if len(text) <= QUOTE_WIDTH:
        return text, col
    start = max(0, min(col - 1 - QUOTE_WIDTH // 4, len(text) - QUOTE_WIDTH))
    shown = text[start:start + QUOTE_WIDTH]
    prefix = "…" if start > 0 else ""
    suffix = "…" if start + QUOTE_WIDTH < len(text) else ""
    return prefix + shown + suffix, col - start + len(prefix)


def _printable(text: str) -> str:
    """Control characters (NULs of a binary file, escape codes) never reach the terminal;
    each becomes one U+FFFD so that carets stay aligned."""
    return "".join(c if c == "\t" or unicodedata.category(c)[0] != "C" else "\ufffd"
                   for c in text)


def render_json(diags: Sequence[Diagnostic]) -> str:
    return json.dumps([d.to_json() for d in diags], indent=2)


def summary_line(diags: Sequence[Diagnostic]) -> str:
    errors = sum(1 for d in diags if d.severity is Severity.ERROR)
    warnings = sum(1 for d in diags if d.severity is Severity.WARNING)
    return f"{errors} error{'s' if errors != 1 else ''}, {warnings} warning{'s' if warnings != 1 else ''}"
