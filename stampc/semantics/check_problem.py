"""Problem checks: objects (with ranges), init facts and values, goal, horizon, scene."""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Mapping

from stampc.diagnostics import Diagnostic, Label, Span
from stampc.semantics.check_domain import BINDING, BINDING_HINT
from stampc.semantics.codes import diag
from stampc.semantics.comprehensions import expand_forall, expand_grid
from stampc.semantics.loader import ProblemSource
from stampc.semantics.scope import DomainInfo, Symbol, duplicate, suggest, undefined_type
from stampc.semantics.terms import Ctx, check_args, check_atom, check_formula
from stampc.syntax import ast

RANGE_END = re.compile(r"^(.*?)(\d+)$")


@dataclass(frozen=True)
class ProblemInfo:
    name: str
    domain: str
    span: Span
    objects: Mapping[str, Symbol]        # declaration order, ranges expanded
    init: tuple[ast.Atom, ...]
    init_values: tuple[ast.InitValue, ...]
    goal: ast.Formula | None
    horizon: int | None
    scene: ast.SceneDecl | None
    file: str


def expand_range(r: ast.ObjectRange) -> list[str] | None:
    """``can0..can14`` → can0 … can14 (same prefix, integer suffixes, first ≤ last)."""
    a, b = RANGE_END.match(r.first.name), RANGE_END.match(r.last.name)
    if a is None or b is None or a.group(1) != b.group(1):
        return None
    lo, hi = int(a.group(2)), int(b.group(2))
    if lo > hi:
        return None
    width = len(a.group(2)) if a.group(2).startswith("0") and len(a.group(2)) > 1 else 0
    return [f"{a.group(1)}{i:0{width}d}" for i in range(lo, hi + 1)]


def build_problem(src: ProblemSource, info: DomainInfo, diags: list[Diagnostic]) -> ProblemInfo:
    objects: dict[str, Symbol] = {}
    init: list[ast.Atom] = []
    values: list[ast.InitValue] = []
    goals: list[ast.Formula] = []
    horizon: int | None = None
    scene: ast.SceneDecl | None = None
    comprehensions: list[ast.InitForall] = []
    for d in src.decls:
        if isinstance(d, ast.ObjectDecl):
            _declare_objects(d, info, objects, diags)
        elif isinstance(d, ast.InitDecl):
            for f in d.facts:
                if isinstance(f, ast.InitForall):
                    comprehensions.append(f)  # expanded once every object is declared
                else:
                    (values if isinstance(f, ast.InitValue) else init).append(f)
        elif isinstance(d, ast.GoalDecl):
            goals.append(d.formula)
        elif isinstance(d, ast.HorizonDecl):
            v = d.value.value
            if v.denominator != 1 or v < 0:
                diags.append(diag("E004", f"horizon must be a non-negative integer, not {d.value.text}", d.span))
            else:
                horizon = int(v)
        elif isinstance(d, ast.SceneDecl):
            if scene is not None:
                diags.append(duplicate("scene", ast.Ident("scene", d.span), scene.span))
            scene = d
    for f in comprehensions:
        init.extend(expand_forall(f, lambda n: n in objects or n in info.constants, diags))
    goal = None
    if goals:
        goal = goals[0] if len(goals) == 1 else ast.And(tuple(goals), goals[0].span)
    header = src.header
    return ProblemInfo(header.name.name, header.domain.name, header.span, objects, tuple(init),
                       tuple(values), goal, horizon, scene, src.file)


def _declare_objects(d: ast.ObjectDecl, info: DomainInfo, objects: dict[str, Symbol],
                     diags: list[Diagnostic]) -> None:
    if d.type.name not in info.types:
        diags.append(undefined_type(d.type, info))
    for item in d.items:
        if isinstance(item, ast.ObjectRange):
            names = expand_range(item)
            if names is None:
                diags.append(diag("E005", f"invalid object range `{item.first.name}..{item.last.name}`",
                                  item.span, "a range is PREFIX<i>..PREFIX<j> with the same prefix and i <= j"))
                continue
            idents = [ast.Ident(n, item.span) for n in names]
        elif isinstance(item, ast.ObjectGrid):
            idents = expand_grid(item, diags)
        else:
            idents = [item]
        for ident in idents:
            first = objects.get(ident.name) or info.constants.get(ident.name)
            if first is not None:
                diags.append(duplicate("object", ident, first.ident.span))
                continue
            objects[ident.name] = Symbol(ident.name, d.type.name, ident)


def check_problem(p: ProblemInfo, info: DomainInfo, diags: list[Diagnostic]) -> None:
    symbols = {c.name: c.type for c in info.constants.values()}
    symbols.update({o.name: o.type for o in p.objects.values()})
    init_ctx = Ctx(info, diags, symbols, "E103")
    for atom in p.init:
        check_atom(atom, {}, init_ctx)
    for value in p.init_values:
        _check_value(value, init_ctx)
    if p.goal is not None:
        check_formula(p.goal, {}, Ctx(info, diags, symbols, "E307"))
    if p.scene is not None and p.scene.kind == "builder" and not BINDING.match(p.scene.target.value):
        diags.append(diag("E306", f'malformed scene builder binding "{p.scene.target.value}"',
                          p.scene.target.span, BINDING_HINT))
    if p.scene is not None and p.scene.kind == "file" and not p.scene.target.value.strip():
        diags.append(diag("E306", "empty scene file name", p.scene.target.span))


def _check_value(v: ast.InitValue, ctx: Ctx) -> None:
    name = v.atom.predicate
    decl = ctx.info.functions.get(name.name)
    if decl is None:
        msg = (f"`{name.name}` is a predicate, not a numeric function" if name.name in ctx.info.predicates
               else f"undefined function `{name.name}`")
        ctx.diags.append(diag("E102", msg, name.span, suggest(name.name, ctx.info.functions)))
        return
    check_args("function", name, v.atom.args, decl.params, decl.name.span, {}, ctx)


def check_problem_domain(p: ProblemInfo, info: DomainInfo, header: ast.ProblemHeader) -> list[Diagnostic]:
    if p.domain != info.name:
        return [diag("E107", f"problem `{p.name}` is for domain `{p.domain}`, but the domain loaded is "
                             f"`{info.name}`", header.domain.span, labels=(Label(info.span, "this domain"),))]
    return []
