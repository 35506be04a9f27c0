"""Checking atoms, formulas, numeric expressions and parameter lists against a domain."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from types import MappingProxyType
from typing import Mapping

from stampc.diagnostics import Label
from stampc.semantics.codes import diag
from stampc.semantics.scope import DomainInfo, suggest, undefined_type
from stampc.semantics.scope_hints import formula_hints
from stampc.syntax import ast

Env = Mapping[str, str]  # variable name -> type


@dataclass(frozen=True)
class Ctx:
    """Where names are being resolved.

    ``symbols``: constants (and problem objects) by name → type. ``undefined``: the code
    for an unknown name (E105 in domains, E103 in init, E307 in goals). ``quantified``:
    every name some quantifier of the current declaration binds, with the help E106
    gives where the name is used unbound (see :mod:`scope_hints`).
    """

    info: DomainInfo
    diags: list
    symbols: Mapping[str, str]
    undefined: str = "E105"
    quantified: Mapping[str, str] = field(default_factory=dict)


def check_params(params: tuple[ast.Param, ...], ctx: Ctx, env: Env | None = None,
                 what: str = "parameter") -> dict[str, str]:
    """Types exist, names distinct; returns ``env`` extended with the parameters."""
    out = dict(env or {})
    seen: dict[str, ast.Ident] = {}
    for p in params:
        if p.type.name not in ctx.info.types:
            ctx.diags.append(undefined_type(p.type, ctx.info))
        if p.name.name in seen:
            ctx.diags.append(diag("E204", f"duplicate {what} `{p.name.name}`", p.name.span,
                                  "rename one of them",
                                  (Label(seen[p.name.name].span, "first declared here"),)))
            continue
        seen[p.name.name] = p.name
        out[p.name.name] = p.type.name
    return out


def term_type(ident: ast.Ident, env: Env, ctx: Ctx) -> str | None:
    name = ident.name
    if name in env:
        return env[name]
    if name in ctx.symbols:
        return ctx.symbols[name]
    if ctx.undefined == "E105" and name in ctx.quantified:
        ctx.diags.append(diag("E106", f"variable `{name}` is used outside the quantifier that binds it",
                              ident.span, ctx.quantified[name]))
        return None
    if ctx.undefined == "E105":
        hint = suggest(name, list(env) + list(ctx.symbols)) or "declare it as a parameter or a constant"
        ctx.diags.append(diag("E105", f"undefined variable `{name}`", ident.span, hint))
    elif ctx.undefined == "E307":
        ctx.diags.append(diag("E307", f"goal uses undeclared object `{name}`", ident.span,
                              suggest(name, ctx.symbols) or "declare it with `object NAME: TYPE`"))
    else:
        ctx.diags.append(diag("E103", f"undefined object or constant `{name}`", ident.span,
                              suggest(name, ctx.symbols) or "declare it with `object NAME: TYPE`"))
    return None


def check_args(kind: str, name: ast.Ident, args: tuple[ast.Ident, ...],
               params: tuple[ast.Param, ...], decl_span, env: Env, ctx: Ctx) -> None:
    types = [term_type(a, env, ctx) for a in args]
    if len(args) != len(params):
        ctx.diags.append(diag(
            "E201", f"{kind} `{name.name}` takes {_count(len(params))}, got {len(args)}",
            name.span, f"declared as {name.name}{_signature(params)}",
            (Label(decl_span, "declared here"),)))
        return
    for arg, t, p in zip(args, types, params):
        if t is None or p.type.name not in ctx.info.types or t not in ctx.info.types:
            continue
        if not ctx.info.is_subtype(t, p.type.name):
            ctx.diags.append(diag(
                "E202", f"argument `{arg.name}` of `{name.name}` has type `{t}`, expected `{p.type.name}`",
                arg.span, f"declared as {name.name}{_signature(params)}",
                (Label(decl_span, "declared here"),)))


def _count(n: int) -> str:
    return f"{n} argument{'s' if n != 1 else ''}"


def _signature(params: tuple[ast.Param, ...]) -> str:
    return "(" + ", ".join(f"{p.name.name}: {p.type.name}" for p in params) + ")"


def check_atom(atom: ast.Atom, env: Env, ctx: Ctx) -> ast.PredicateDecl | None:
    name = atom.predicate.name
    decl = ctx.info.predicates.get(name)
    if decl is None:
        for a in atom.args:
            term_type(a, env, ctx)
        if name in ctx.info.functions:
            ctx.diags.append(diag("E102", f"`{name}` is a numeric function, not a predicate",
                                  atom.predicate.span, "use it in `cost` expressions or `init f(..) = N`"))
        else:
            ctx.diags.append(diag("E102", f"undefined predicate `{name}`", atom.predicate.span,
                                  suggest(name, ctx.info.predicates) or "declare it with `predicate NAME(...)`"))
        return None
    check_args("predicate", atom.predicate, atom.args, decl.params, decl.name.span, env, ctx)
    return decl


def check_formula(f: ast.Formula, env: Env, ctx: Ctx) -> None:
    if isinstance(f, ast.Atom):
        check_atom(f, env, ctx)
    elif isinstance(f, ast.Eq):
        term_type(f.left, env, ctx)
        term_type(f.right, env, ctx)
    elif isinstance(f, ast.Not):
        check_formula(f.arg, env, ctx)
    elif isinstance(f, (ast.And, ast.Or)):
        _check_siblings(f.args, "and" if isinstance(f, ast.And) else "or", env, ctx)
    elif isinstance(f, ast.Implies):
        _check_siblings((f.left, f.right), "implies", env, ctx)
    elif isinstance(f, ast.Quantified):
        check_formula(f.body, check_params(f.params, ctx, env, "quantified variable"), ctx)


def _check_siblings(parts: tuple[ast.Formula, ...], joiner: str, env: Env, ctx: Ctx) -> None:
    """Operands in order; after a quantifier, its variables get an E106 hint that
    suggests the parentheses which would have kept them in scope."""
    for i, part in enumerate(parts):
        check_formula(part, env, ctx)
        if type(part) is ast.Quantified and i + 1 < len(parts) and ctx.undefined == "E105":
            ctx = replace(ctx, quantified=formula_hints(part, parts[i + 1:], joiner, ctx.quantified))


def check_numexpr(e: ast.NumExpr, env: Env, ctx: Ctx) -> None:
    if isinstance(e, ast.BinOp):
        check_numexpr(e.left, env, ctx)
        check_numexpr(e.right, env, ctx)
    elif isinstance(e, ast.FuncApp):
        name = e.function.name
        decl = ctx.info.functions.get(name)
        if decl is None:
            if name in ctx.info.predicates:
                msg = f"`{name}` is a predicate, not a numeric function"
            else:
                msg = f"undefined function `{name}`"
            ctx.diags.append(diag("E102", msg, e.function.span,
                                  suggest(name, ctx.info.functions) or "declare it with `function NAME(...)`"))
            return
        check_args("function", e.function, e.args, decl.params, decl.name.span, env, ctx)


# Children that can hold a quantifier, by exact node type: the walks below test each
# node once with a dict lookup instead of a chain of ``isinstance`` calls (leaves such as
# atoms, literals and costs are absent and end the walk at once).
_INNER = MappingProxyType({
    ast.Quantified: lambda n: (n.body,),
    ast.EffForall: lambda n: (n.effect,),
    ast.Not: lambda n: (n.arg,),
    ast.And: lambda n: n.args,
    ast.Or: lambda n: n.args,
    ast.Implies: lambda n: (n.left, n.right),
    ast.EffAnd: lambda n: n.effects,
    ast.When: lambda n: (n.condition, n.effect),
    ast.Probabilistic: lambda n: [o.effect for o in n.outcomes],
})
_BINDERS = (ast.Quantified, ast.EffForall)


def quantified_params(node: object) -> list[ast.Param]:
    """Every parameter bound by a quantifier (formula or effect) inside ``node``."""
    found: list[ast.Param] = []
    stack = [node]
    while stack:
        n = stack.pop()
        inner = _INNER.get(type(n))
        if inner is None:
            continue
        if type(n) in _BINDERS:
            found.extend(n.params)
        stack.extend(inner(n))
    return found


