"""Helpers for building AST nodes: fast spans, span merging, flattening of lists."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from stampc.diagnostics import Span
from stampc.syntax import ast

_NONE_SPAN = ast.NOWHERE


def _span_factory():
    """``Span(file, line, col, end_line, end_col)`` at half the cost of the frozen
    dataclass ``__init__`` (the parser creates one per identifier). Falls back to the
    regular constructor if ``Span`` ever stops being a plain ``__dict__`` dataclass."""
    probe = Span("f", 1, 2, 3, 4)
    if not hasattr(probe, "__dict__") or hasattr(Span, "__post_init__") or list(probe.__dict__) != \
            ["file", "line", "col", "end_line", "end_col"]:
        return Span
    new = object.__new__

    def make(file: str, line: int, col: int, end_line: int, end_col: int) -> Span:
        span = new(Span)
        fields = span.__dict__
        fields["file"], fields["line"], fields["col"] = file, line, col
        fields["end_line"], fields["end_col"] = end_line, end_col
        return span

    return make


make_span = _span_factory()


def merge(first: Span, last: Span) -> Span:
    if first is _NONE_SPAN:
        return last
    if last is _NONE_SPAN:
        return first
    return make_span(first.file, first.line, first.col, last.end_line, last.end_col)


def span_of(item: Any) -> Span:
    """Span of a node, or from the first to the last located node of a sequence."""
    if isinstance(item, list) or (isinstance(item, tuple) and not (item and isinstance(item[0], str))):
        first = next((s for s in map(span_of, item) if s is not _NONE_SPAN), _NONE_SPAN)
        last = next((s for s in map(span_of, reversed(item)) if s is not _NONE_SPAN), _NONE_SPAN)
        return merge(first, last)
    span = getattr(item, "span", None)
    return span if isinstance(span, Span) else _NONE_SPAN


def flat(items: Any) -> list:
    out: list = []
    for x in items:
        if isinstance(x, list):
            out.extend(flat(x))
        elif x is not None:
            out.append(x)
    return out


def conj(parts: list) -> "ast.Formula":
    """Conjunction of ``parts`` with nested conjunctions flattened (canonical form)."""
    args: list = []
    for p in parts:
        args.extend(p.args if isinstance(p, ast.And) else [p])
    if len(args) == 1:
        return args[0]
    return ast.And(tuple(args), merge(args[0].span, args[-1].span) if args else _NONE_SPAN)


def seq(parts: list) -> "ast.Effect":
    """Sequence of effects with nested sequences flattened (canonical form)."""
    effects: list = []
    for p in parts:
        effects.extend(p.effects if isinstance(p, ast.EffAnd) else [p])
    if len(effects) == 1:
        return effects[0]
    return ast.EffAnd(tuple(effects), span_of(effects))


@dataclass(frozen=True, slots=True)
class Clause:
    kind: str
    value: Any


class Args(list):
    """Arguments of an atom with the span of their parentheses."""

    span: Span = _NONE_SPAN


def is_token(x: Any, kind: str) -> bool:
    return type(x) is tuple and x[0] == kind
