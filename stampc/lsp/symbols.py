"""Every name in a parsed stamp file, classified by what it names and whether it
declares or uses it — read from the AST's fields, so the language server sees exactly
the identifiers (and spans) the front end sees.

Kinds: ``type``, ``predicate``, ``function`` (a use of either resolves to either),
``generator``, ``action``, ``constant`` (constants and problem objects) and ``param``
(action, generator, predicate and quantifier parameters). A name in an argument
position is a ``term``: the parameter of that name in its declaration, else a
constant or object.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, is_dataclass
from typing import Iterator

from stampc.diagnostics import Span
from stampc.syntax import ast, indexed

DEFINES: dict[tuple[type, str], str] = {
    (ast.TypeDecl, "names"): "type", (ast.PredicateDecl, "name"): "predicate",
    (ast.FunctionDecl, "name"): "function", (ast.GeneratorDecl, "name"): "generator",
    (ast.ActionDecl, "name"): "action", (ast.ConstantDecl, "names"): "constant",
    (ast.ObjectDecl, "items"): "constant", (ast.ObjectRange, "first"): "constant",
    (ast.ObjectRange, "last"): "constant", (ast.Param, "name"): "param",
}
USES: dict[tuple[type, str], str] = {
    (ast.TypeDecl, "parent"): "type", (ast.Param, "type"): "type",
    (ast.ConstantDecl, "type"): "type", (ast.ObjectDecl, "type"): "type",
    (ast.Atom, "predicate"): "predicate", (ast.EvaluatorDecl, "predicate"): "predicate",
    (ast.FuncApp, "function"): "function", (ast.Sample, "generator"): "generator",
    (ast.Atom, "args"): "term", (ast.Eq, "left"): "term", (ast.Eq, "right"): "term",
    (ast.FuncApp, "args"): "term", (ast.Sample, "inputs"): "term",
    (ast.Sample, "outputs"): "term",
    # problem comprehensions (`init forall (i: 0..3) adjacent(cell(i), cell(i + 1))`):
    # the predicate and the plain-name arguments; indexed names are built, not declared
    (indexed.IndexedAtom, "predicate"): "predicate", (indexed.IndexedAtom, "args"): "term",
}
#: the kinds a use of each kind may resolve to
RESOLVES_TO = {"type": ("type",), "predicate": ("predicate", "function"),
               "function": ("function", "predicate"), "generator": ("generator",),
               "action": ("action",), "constant": ("constant",), "param": ("param",),
               "term": ("constant", "param")}


@dataclass(frozen=True)
class Occurrence:
    name: str
    kind: str
    defines: bool
    span: Span
    #: the top-level declaration it appears in (parameters are looked up there)
    decl: ast.Decl


def occurrences(program: ast.Program) -> Iterator[Occurrence]:
    """Every classified identifier of ``program``, in source order per declaration."""
    for decl in program.decls:
        yield from _walk(decl, decl)


def _walk(node: object, decl: ast.Decl) -> Iterator[Occurrence]:
    for f in fields(node):
        value = getattr(node, f.name)
        items = value if isinstance(value, tuple) else (value,)
        for item in items:
            if isinstance(item, ast.Ident):
                kind, defines = _classify(type(node), f.name)
                if kind is not None:
                    yield Occurrence(item.name, kind, defines, item.span, decl)
            elif is_dataclass(item) and not isinstance(item, (Span, type)):
                yield from _walk(item, decl)


def _classify(owner: type, field_name: str) -> tuple[str | None, bool]:
    key = (owner, field_name)
    if key in DEFINES:
        return DEFINES[key], True
    return USES.get(key), False


def at_position(program: ast.Program, line: int, col: int) -> Occurrence | None:
    """The occurrence whose span holds 1-based ``line``/``col`` (the column just past an
    identifier counts: a cursor at its end is on it)."""
    for occ in occurrences(program):
        s = occ.span
        if s.line == line == s.end_line and s.col <= col <= s.end_col:
            return occ
    return None


def enclosing_param(occ: Occurrence) -> Occurrence | None:
    """The parameter a variable use names, in the same top-level declaration."""
    for other in _walk(occ.decl, occ.decl):
        if other.kind == "param" and other.defines and other.name == occ.name:
            return other
    return None
