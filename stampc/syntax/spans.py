"""Helpers for building AST nodes: fast spans, span merging, flattening of lists."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, Callable

from stampc.diagnostics import Span
from stampc.syntax import ast

_NONE_SPAN = ast.NOWHERE


def _span_factory():
    """``Span(file, line, col, end_line, end_col)`` at half the cost of the frozen
    dataclass ``__init__`` (the parser creates one per identifier): the slots are filled
    through their member descriptors. Falls back to the regular constructor if ``Span``
    ever stops being a plain ``slots`` dataclass with these five fields."""
    names = ("file", "line", "col", "end_line", "end_col")
    if vars(Span).get("__slots__") != names or hasattr(Span, "__post_init__"):
        return Span
    new = object.__new__
    s_file, s_line, s_col, s_end_line, s_end_col = [vars(Span)[n].__set__ for n in names]

    def make(file: str, line: int, col: int, end_line: int, end_col: int) -> Span:
        span = new(Span)
        s_file(span, file), s_line(span, line), s_col(span, col)
        s_end_line(span, end_line), s_end_col(span, end_col)
        return span

    return make


make_span = _span_factory()


def fast_constructor(cls: type) -> Callable[..., Any]:
    """A positional constructor for a frozen ``slots`` dataclass with 2 to 4 fields, every
    field passed. The generated ``__init__`` of a frozen dataclass stores each field with
    ``object.__setattr__``; filling the slots through their member descriptors builds the
    same object in about half the time (the parser makes ~300,000 nodes for a large
    domain). Falls back to ``cls`` itself for any other kind of class."""
    names = tuple(f.name for f in dataclasses.fields(cls))
    if vars(cls).get("__slots__") != names or hasattr(cls, "__post_init__") or not 2 <= len(names) <= 4:
        return cls
    new = object.__new__
    setters = [vars(cls)[name].__set__ for name in names]
    if len(setters) == 2:
        s0, s1 = setters

        def make2(a, b):
            obj = new(cls)
            s0(obj, a), s1(obj, b)
            return obj
        return make2
    if len(setters) == 3:
        s0, s1, s2 = setters

        def make3(a, b, c):
            obj = new(cls)
            s0(obj, a), s1(obj, b), s2(obj, c)
            return obj
        return make3
    s0, s1, s2, s3 = setters

    def make4(a, b, c, d):
        obj = new(cls)
        s0(obj, a), s1(obj, b), s2(obj, c), s3(obj, d)
        return obj
    return make4


def merge(first: Span, last: Span) -> Span:
    if first is _NONE_SPAN:
        return last
    if last is _NONE_SPAN:
        return first
    return make_span(first.file, first.line, first.col, last.end_line, last.end_col)


def span_of(item: Any) -> Span:
    """Span of a node, or from the first to the last located node of a sequence."""
    if isinstance(item, list) or (isinstance(item, tuple) and not (item and isinstance(item[0], str))):
        if item:  # fast path: the ends are nodes with real spans (params, effects, outcomes)
            first, last = getattr(item[0], "span", None), getattr(item[-1], "span", None)
            if type(first) is Span and type(last) is Span and first is not _NONE_SPAN \
                    and last is not _NONE_SPAN:
                return make_span(first.file, first.line, first.col, last.end_line, last.end_col)
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


@dataclass(frozen=True, slots=True)
class Args:
    """Arguments of an atom, with the closing parenthesis token (where the atom ends)."""

    idents: tuple
    rpar: tuple


def is_token(x: Any, kind: str) -> bool:
    return type(x) is tuple and x[0] == kind
