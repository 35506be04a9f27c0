"""AST nodes of integer-indexed names and problem comprehensions (re-exported by
:mod:`stampc.syntax.ast`).

``cell(i + 1, j)`` names the object ``cell_<i+1>_<j>``; with literal indices the builder
resolves it to a plain :class:`~stampc.syntax.ast.Ident` at once (``cell(4, 3)`` is
``cell_4_3``), so only comprehension bodies hold :class:`IndexedName`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Union

from stampc.diagnostics import Span

NOWHERE = Span("<none>", 1, 1, 1, 1)


def span_field() -> Span:
    """A span excluded from equality: trees that differ only in layout compare equal."""
    return field(default=NOWHERE, compare=False, repr=False)


_span = span_field


@dataclass(frozen=True, slots=True)
class IndexNum:
    value: int
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class IndexVar:
    name: str
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class IndexOp:
    op: str  # "+" | "-" | "*"
    left: "IndexExpr"
    right: "IndexExpr"
    span: Span = _span()


IndexExpr = Union[IndexNum, IndexVar, IndexOp]


@dataclass(frozen=True, slots=True)
class IndexedName:
    """``cell(i, j + 1)``: an object name built from integer indices."""

    base: str
    indices: tuple[IndexExpr, ...]
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class IndexedAtom:
    """An init atom whose arguments may be indexed names (a comprehension body)."""

    predicate: object  # ast.Ident
    args: tuple  # of Ident | IndexedName
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class IndexRange:
    """``i: 0..4`` (inclusive; bounds may use variables bound before)."""

    var: str
    first: IndexExpr
    last: IndexExpr
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class IndexCond:
    op: str  # "=" | "!=" | "<" | "<=" | ">" | ">="
    left: IndexExpr
    right: IndexExpr
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class InitForall:
    """``forall (i: 0..3, j: 0..4) when i != j: adjacent(cell(i, j), cell(i + 1, j))``."""

    ranges: tuple[IndexRange, ...]
    conditions: tuple[IndexCond, ...]
    atom: IndexedAtom
    span: Span = _span()


@dataclass(frozen=True, slots=True)
class ObjectGrid:
    """``cell(0..4, 0..3)`` in an object declaration: cell_0_0 … cell_4_3."""

    base: str
    bounds: tuple[tuple[int, int], ...]
    span: Span = _span()


def indexed_name(base: str, values: tuple[int, ...]) -> str:
    """The object an indexed name denotes: ``cell`` with (1, 2) is ``cell_1_2``."""
    return base + "".join(f"_{v}" for v in values)


def index_vars(e: IndexExpr) -> list[IndexVar]:
    """The variables of ``e``, left to right (an explicit stack: chains such as
    ``i + 1 + 1 + ...`` nest as deep as they are long)."""
    out: list[IndexVar] = []
    stack: list[IndexExpr] = [e]
    while stack:
        node = stack.pop()
        if isinstance(node, IndexVar):
            out.append(node)
        elif isinstance(node, IndexOp):
            stack.extend((node.right, node.left))
    return out


def evaluate(e: IndexExpr, env: dict[str, int]) -> int:
    """The value of ``e`` with variables from ``env`` (iterative, like :func:`index_vars`)."""
    values: list[int] = []
    stack: list[IndexExpr | str] = [e]
    while stack:
        node = stack.pop()
        if isinstance(node, str):  # an operator whose operands are computed
            b, a = values.pop(), values.pop()
            values.append(a + b if node == "+" else a - b if node == "-" else a * b)
        elif isinstance(node, IndexNum):
            values.append(node.value)
        elif isinstance(node, IndexVar):
            values.append(env[node.name])
        else:
            stack.extend((node.op, node.right, node.left))
    return values[0]
