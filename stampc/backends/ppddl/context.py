"""Shared state and helpers for lowering a PPDDL parse tree to the lifted IR.

:class:`Lowering` is a per-import working context (symbol tables + collected
diagnostics); it never outlives one ``import_ppddl`` call.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

from lark import Token, Tree

from stampc.backends.ppddl import codes
from stampc.diagnostics import Diagnostic, Span, error
from stampc.ir.lifted import Function, Object, Param, Predicate, Type

ROOT_TYPE = "object"


@dataclass
class Lowering:
    file: str
    diags: list[Diagnostic] = field(default_factory=list)
    types: dict[str, Type] = field(default_factory=dict)
    #: domain constants and, while lowering a problem, the problem's objects
    objects: dict[str, Object] = field(default_factory=dict)
    predicates: dict[str, Predicate] = field(default_factory=dict)
    functions: dict[str, Function] = field(default_factory=dict)

    # ------------------------------------------------------------ reporting
    def err(self, code: str, message: str, node, hint: str | None = None) -> None:
        self.diags.append(error(code, message, self.span(node), hint))

    def span(self, node) -> Span:
        if isinstance(node, Span):
            return node
        if isinstance(node, Token):
            return Span(self.file, node.line, node.column, node.end_line, node.end_column)
        if isinstance(node, Tree) and not node.meta.empty:
            m = node.meta  # includes the filtered-out parentheses
            return Span(self.file, m.line, m.column, m.end_line, m.end_column)
        if isinstance(node, Tree):
            tokens = list(node.scan_values(lambda v: isinstance(v, Token)))
            if tokens:
                first, last = tokens[0], tokens[-1]
                return Span(self.file, first.line, first.column, last.end_line, last.end_column)
        return Span.point(self.file)

    # ---------------------------------------------------------------- types
    def ancestors(self, name: str) -> set[str]:
        seen: set[str] = set()
        current: str | None = name
        while current is not None and current not in seen:
            seen.add(current)
            t = self.types.get(current)
            current = t.parent if t is not None else None
        seen.add(ROOT_TYPE)
        return seen

    def compatible(self, arg_type: str, param_type: str) -> bool:
        """Lenient PPDDL typing: one type must be a (reflexive) subtype of the other."""
        return param_type in self.ancestors(arg_type) or arg_type in self.ancestors(param_type)

    def check_type(self, tok: Token) -> str:
        name = str(tok)
        if name != ROOT_TYPE and name not in self.types:
            self.err(codes.UNDEFINED_TYPE, f"undefined type '{name}'", tok,
                     hint="declare it in (:types ...)")
        return name


# --------------------------------------------------------------- typed lists
def typed_items(cx: Lowering, node: Tree) -> list[tuple[Token, str, Token | Tree | None]]:
    """Group a flat ``typed_list``/``typed_vars`` into (name token, type, type node).

    Names after the last ``- type`` mark are of type ``object``.
    """
    out: list[tuple[Token, str, Token | Tree | None]] = []
    pending: list[Token] = []
    for item in node.children:
        if isinstance(item, Token):
            pending.append(item)
            continue
        spec = item.children[0]  # the type_mark's type
        if not pending:
            cx.err(codes.SYNTAX, "'-' must follow at least one name", item)
        if isinstance(spec, Tree):  # (either ...)
            cx.err(codes.UNSUPPORTED, "unsupported construct: (either ...) types", spec,
                   hint="declare a common supertype instead")
            type_name = ROOT_TYPE
        else:
            type_name = str(spec)
        out.extend((tok, type_name, spec) for tok in pending)
        pending = []
    out.extend((tok, ROOT_TYPE, None) for tok in pending)
    return out


def typed_params(cx: Lowering, node: Tree) -> tuple[Param, ...]:
    """``?a ?b - t`` → Params (names without '?'); checks types and duplicates."""
    params: list[Param] = []
    seen: set[str] = set()
    for tok, type_name, spec in typed_items(cx, node):
        name = str(tok).lstrip("?")
        if name in seen:
            cx.err(codes.DUPLICATE, f"parameter '?{name}' declared twice", tok)
        seen.add(name)
        if isinstance(spec, Token):
            cx.check_type(spec)
        params.append(Param(name, type_name))
    return tuple(params)


# ------------------------------------------------------------------ numbers
def parse_number(cx: Lowering, tok: Token) -> Fraction:
    """Exact value of an integer, decimal, ``.8`` or ``1/3`` literal."""
    text = str(tok)
    try:
        return Fraction(text)
    except (ValueError, ZeroDivisionError):
        cx.err(codes.BAD_NUMBER, f"malformed number '{text}'", tok)
        return Fraction(0)
