"""Help for E106 (a quantified variable used outside its quantifier): say where the
quantifier's scope ends and what to write instead.

A quantifier binds tighter than `and`/`or`: ``exists (y: b) on(y) and up(y)`` is
``(exists (y: b) on(y)) and up(y)``, so the ``y`` of ``up(y)`` is unbound; the usual fix
is parentheses around the intended body, which the hint spells out. In effects the
block form ``forall (y: b): ...`` covers a whole list. Elsewhere (a variable bound in
the precondition and used in the effect) the fix is an action parameter.
"""

from __future__ import annotations

from typing import Mapping, Sequence

from stampc.syntax import ast
from stampc.syntax.depth import CHILDREN
from stampc.syntax.fmt import effect_lines, fmt_formula, fmt_params
from stampc.syntax.spans import conj, seq

MAX_SUGGESTION = 120  # longer rewrites are described instead of spelled out


def binder_hints(action: ast.ActionDecl, bound: list[ast.Param]) -> dict[str, str]:
    """Default E106 help for each variable (``bound``) some quantifier of ``action`` binds."""
    hints: dict[str, str] = {}
    for p in bound:
        hints.setdefault(p.name.name, (
            f"`{p.name.name}` is bound only inside its quantifier (line {p.span.line}); to use the "
            f"same object here, make it a parameter: `action {action.name.name}"
            f"{fmt_params(action.params + (ast.Param(p.name, p.type),))}`"))
    return hints


def _names(node: object) -> set[str]:
    """Every name an atom, equality or function term inside ``node`` mentions."""
    found: set[str] = set()
    stack = [node]
    while stack:
        n = stack.pop()
        if isinstance(n, (ast.Lit, ast.Unknown)):
            n = n.atom
        if isinstance(n, (ast.Atom, ast.FuncApp)):
            found.update(a.name for a in n.args)
        elif isinstance(n, ast.Eq):
            found.update((n.left.name, n.right.name))
        else:
            inner = CHILDREN.get(type(n))
            stack.extend(inner(n) if inner is not None else ())
    return found


def _using(binder_params: tuple[ast.Param, ...], rest: Sequence) -> list:
    """``rest`` up to its last item that mentions one of the binder's variables."""
    names = {p.name.name for p in binder_params}
    last = max((i for i, x in enumerate(rest) if names & _names(x)), default=len(rest) - 1)
    return list(rest[:last + 1])


def formula_hints(binder: ast.Quantified, rest: Sequence[ast.Formula], joiner: str,
                  hints: Mapping[str, str]) -> dict[str, str]:
    """E106 help for the siblings after ``binder`` in an `and`/`or`/`implies`."""
    rest = _using(binder.params, rest)
    if joiner == "and":
        body: ast.Formula = conj([binder.body, *rest])
    elif joiner == "or":
        body = ast.Or((binder.body, *rest))
    else:
        body = ast.Implies(binder.body, rest[0])
    rewrite = fmt_formula(ast.Quantified(binder.kind, binder.params, body))
    head = f"{binder.kind} {fmt_params(binder.params)}"
    return _with(hints, binder.params, head, fmt_formula(binder.body, 3), rewrite,
                 f"put the quantifier's body and what follows in parentheses: `{head} (... {joiner} ...)`")


def effect_hints(binder: ast.EffForall, rest: Sequence[ast.Effect],
                 hints: Mapping[str, str]) -> dict[str, str]:
    """E106 help for the effects listed after ``forall (..) effect``."""
    rest = _using(binder.params, rest)
    lines = effect_lines(ast.EffForall(binder.params, seq([binder.effect, *rest])))
    rewrite = lines[0] if len(lines) == 1 else ""
    head = f"forall {fmt_params(binder.params)}"
    return _with(hints, binder.params, head, " ".join(effect_lines(binder.effect)), rewrite,
                 f"use the block form `{head}:` followed by every effect it covers")


def _with(hints: Mapping[str, str], params: tuple[ast.Param, ...], head: str, body: str,
          rewrite: str, fallback: str) -> dict[str, str]:
    fix = f"write `{rewrite}`" if rewrite and len(rewrite) <= MAX_SUGGESTION else fallback
    out = dict(hints)
    for p in params:
        out[p.name.name] = f"`{head}` binds `{p.name.name}` only in `{body}`; to cover what follows, {fix}"
    return out
