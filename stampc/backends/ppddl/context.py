"""Shared state and helpers for lowering a PPDDL parse tree to the lifted IR.

:class:`Lowering` is a per-import working context (symbol tables + collected
diagnostics); it never outlives one ``import_ppddl`` call.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction

from stampc.backends.ppddl import codes
from stampc.backends.ppddl.reader import LineIndex, Tok
from stampc.backends.ppddl.shape_base import Node
from stampc.diagnostics import Diagnostic, Span, error, warning
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
    #: locates the offsets of the source's tokens and nodes
    index: LineIndex | None = None
    #: --lenient: accept what mini-gpt accepts, as warnings with implicit declarations
    lenient: bool = False
    #: lowering the domain (False: the problem)
    in_domain: bool = True
    #: names --lenient declared as constants while lowering the domain
    implicit_constants: set[str] = field(default_factory=set)
    _ancestors: dict[str, frozenset[str]] = field(default_factory=dict, repr=False)
    #: object name -> (Const term, type): large :init sections repeat names many times
    const_terms: dict = field(default_factory=dict, repr=False)

    # ------------------------------------------------------------ reporting
    def err(self, code: str, message: str, node, hint: str | None = None) -> None:
        self.diags.append(error(code, message, self.span(node), hint))

    def warn(self, code: str, message: str, node, hint: str | None = None) -> None:
        self.diags.append(warning(code, message, self.span(node), hint))

    def span(self, node) -> Span:
        if isinstance(node, Span):
            return node
        if isinstance(node, (Tok, Node)) and self.index is not None:
            return self.index.span(node.start, node.end)
        return Span.point(self.file)

    # ---------------------------------------------------------------- types
    def ancestors(self, name: str) -> frozenset[str]:
        """``name``, its ancestors and ``object`` (cached: the hierarchy is fixed once
        the :types section is read)."""
        cached = self._ancestors.get(name)
        if cached is None:
            cached = self._ancestors[name] = frozenset(self._walk_ancestors(name))
        return cached

    def _walk_ancestors(self, name: str) -> set[str]:
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

    def check_type(self, tok: Tok) -> str:
        name = str(tok)
        if name != ROOT_TYPE and name not in self.types:
            self.err(codes.UNDEFINED_TYPE, f"undefined type '{name}'", tok,
                     hint="declare it in (:types ...)")
        return name


# --------------------------------------------------------------- typed lists
def typed_items(cx: Lowering, node: Node) -> list[tuple[Tok, str, Tok | Node | None]]:
    """Group a flat ``typed_list``/``typed_vars`` into (name token, type, type node).

    Names after the last ``- type`` mark are of type ``object``.
    """
    out: list[tuple[Tok, str, Tok | Node | None]] = []
    pending: list[Tok] = []
    for item in node.children:
        if isinstance(item, Tok):
            pending.append(item)
            continue
        spec = item.children[0]  # the type_mark's type
        if not pending:
            cx.err(codes.SYNTAX, "'-' must follow at least one name", item)
        if isinstance(spec, Node):  # (either ...)
            cx.err(codes.UNSUPPORTED, "unsupported construct: (either ...) types", spec,
                   hint="declare a common supertype instead")
            type_name = ROOT_TYPE
        else:
            type_name = str(spec)
        out.extend((tok, type_name, spec) for tok in pending)
        pending = []
    out.extend((tok, ROOT_TYPE, None) for tok in pending)
    return out


def typed_params(cx: Lowering, node: Node, declaration: bool = False) -> tuple[Param, ...]:
    """``?a ?b - t`` → Params (names without '?'); checks types and duplicates.

    In a predicate or function ``declaration`` the names only give the arity, so under
    --lenient a repeated name is a warning (mini-gpt ignores it) instead of an error.
    """
    params: list[Param] = []
    seen: set[str] = set()
    for tok, type_name, spec in typed_items(cx, node):
        name = str(tok).lstrip("?")
        if name in seen:
            _repeated(cx, name, tok, declaration)
        seen.add(name)
        if isinstance(spec, Tok):
            cx.check_type(spec)
        params.append(Param(name, type_name))
    return tuple(params)


def _repeated(cx: Lowering, name: str, tok: Tok, declaration: bool) -> None:
    if declaration and cx.lenient:
        cx.warn(codes.REPEATED_VARIABLE, f"variable '?{name}' repeated in a declaration; "
                "accepted as mini-gpt does (the names only give the arity)", tok)
    else:
        cx.err(codes.DUPLICATE, f"parameter '?{name}' declared twice", tok,
               hint=codes.LENIENT_HINT if declaration else None)


# ------------------------------------------------------------------ numbers
def parse_number(cx: Lowering, tok: Tok) -> Fraction:
    """Exact value of an integer, decimal, ``.8`` or ``1/3`` literal."""
    text = str(tok)
    try:
        return Fraction(text)
    except (ValueError, ZeroDivisionError):
        cx.err(codes.BAD_NUMBER, f"malformed number '{text}'", tok)
        return Fraction(0)
