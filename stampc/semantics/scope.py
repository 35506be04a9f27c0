"""Symbol tables of a domain: types (with the hierarchy), constants, predicates,
functions, generators, evaluators and actions; duplicate and cycle detection."""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from typing import Iterable, Mapping

from stampc.diagnostics import Diagnostic, Label, Span
from stampc.semantics.codes import diag
from stampc.semantics.loader import DomainSource
from stampc.syntax import ast


@dataclass(frozen=True)
class TypeInfo:
    name: str
    parent: str | None
    declared_continuous: bool
    ident: ast.Ident
    parent_ident: ast.Ident | None = None


@dataclass(frozen=True)
class Symbol:
    """A constant or problem object."""

    name: str
    type: str
    ident: ast.Ident


@dataclass(frozen=True)
class DomainInfo:
    name: str
    span: Span
    types: Mapping[str, TypeInfo]
    constants: Mapping[str, Symbol]
    predicates: Mapping[str, ast.PredicateDecl]
    functions: Mapping[str, ast.FunctionDecl]
    generators: Mapping[str, ast.GeneratorDecl]
    evaluators: tuple[ast.EvaluatorDecl, ...]
    actions: tuple[ast.ActionDecl, ...]
    local_files: frozenset[str]

    def ancestors(self, name: str) -> list[str]:
        """``name`` and its ancestors, nearest first (stops on cycles and unknown types)."""
        chain: list[str] = []
        current: str | None = name
        while current is not None and current not in chain:
            chain.append(current)
            info = self.types.get(current)
            current = info.parent if info is not None else None
        return chain

    def is_subtype(self, sub: str, sup: str) -> bool:
        return sup in self.ancestors(sub)

    def is_continuous(self, name: str) -> bool:
        return any(self.types[t].declared_continuous for t in self.ancestors(name) if t in self.types)

    def is_local(self, span: Span) -> bool:
        return span.file in self.local_files


def suggest(name: str, candidates: Iterable[str]) -> str | None:
    close = difflib.get_close_matches(name, list(candidates), n=1, cutoff=0.75)
    return f"did you mean `{close[0]}`?" if close else None


def duplicate(kind: str, ident: ast.Ident, first: Span) -> Diagnostic:
    return diag("E203", f"{kind} `{ident.name}` is defined more than once", ident.span,
                labels=(Label(first, "first defined here"),))


def build_domain(src: DomainSource, diags: list[Diagnostic]) -> DomainInfo:
    types: dict[str, TypeInfo] = {}
    constants: dict[str, Symbol] = {}
    predicates: dict[str, ast.PredicateDecl] = {}
    functions: dict[str, ast.FunctionDecl] = {}
    generators: dict[str, ast.GeneratorDecl] = {}
    evaluators: dict[str, ast.EvaluatorDecl] = {}
    actions: dict[str, ast.ActionDecl] = {}
    for d in src.decls:
        if isinstance(d, ast.TypeDecl):
            for n in d.names:
                if n.name in types:
                    diags.append(duplicate("type", n, types[n.name].ident.span))
                    continue
                types[n.name] = TypeInfo(n.name, d.parent.name if d.parent else None, d.continuous, n, d.parent)
        elif isinstance(d, ast.ConstantDecl):
            for n in d.names:
                if n.name in constants:
                    diags.append(duplicate("constant", n, constants[n.name].ident.span))
                    continue
                constants[n.name] = Symbol(n.name, d.type.name, n)
        elif isinstance(d, (ast.PredicateDecl, ast.FunctionDecl)):
            name = d.name.name
            first = predicates.get(name) or functions.get(name)
            if first is not None:
                diags.append(duplicate("predicate or function", d.name, first.name.span))
                continue
            (predicates if isinstance(d, ast.PredicateDecl) else functions)[name] = d
        elif isinstance(d, ast.GeneratorDecl):
            _add(generators, d.name, d, "generator", diags)
        elif isinstance(d, ast.EvaluatorDecl):
            _add(evaluators, d.predicate, d, "evaluator for", diags)
        elif isinstance(d, ast.ActionDecl):
            _add_action(actions, d, src.local_files, diags)
    header = src.header
    name = header.name.name if header else "anonymous"
    span = header.span if header else Span.point(src.file)
    info = DomainInfo(name, span, types, constants, predicates, functions, generators,
                      tuple(evaluators.values()), tuple(actions.values()), src.local_files)
    _check_hierarchy(info, diags)
    return info


def _add(table: dict, ident: ast.Ident, decl, kind: str, diags: list[Diagnostic]) -> None:
    if ident.name in table:
        first = table[ident.name]
        first_span = first.name.span if hasattr(first, "name") else first.predicate.span
        diags.append(duplicate(kind, ident, first_span))
        return
    table[ident.name] = decl


def _add_action(actions: dict, d: ast.ActionDecl, local: frozenset[str], diags: list[Diagnostic]) -> None:
    """A domain's own action replaces a same-named action of a used module (override)."""
    first = actions.get(d.name.name)
    if first is not None:
        mine, theirs = d.name.span.file in local, first.name.span.file in local
        if mine and not theirs:
            actions[d.name.name] = d
            return
        if theirs and not mine:
            return
    _add(actions, d.name, d, "action", diags)


def _check_hierarchy(info: DomainInfo, diags: list[Diagnostic]) -> None:
    reported: set[str] = set()
    for t in info.types.values():
        if t.parent is not None and t.parent not in info.types:
            diags.append(undefined_type(t.parent_ident or t.ident, info))
        chain = [t.name]
        current = t.parent
        while current is not None and current in info.types:
            if current == t.name:
                if not reported & set(chain):
                    cycle = " < ".join(chain + [t.name])
                    diags.append(diag("E205", f"cyclic type hierarchy: {cycle}", t.ident.span,
                                      "a type cannot be its own ancestor"))
                reported.update(chain)
                break
            if current in chain:
                break
            chain.append(current)
            current = info.types[current].parent


def undefined_type(ident: ast.Ident, info: DomainInfo) -> Diagnostic:
    return diag("E101", f"undefined type `{ident.name}`", ident.span,
                suggest(ident.name, info.types) or "declare it with `type NAME`")
