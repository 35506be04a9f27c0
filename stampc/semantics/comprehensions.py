"""Expanding problem comprehensions: ``object cell(0..4, 0..3)`` and
``init forall (i: 0..3, j: 0..4) when ...: p(cell(i, j), ...)`` (docs/language.md,
"Comprehensions"). Ranges are inclusive; every generated name must be a declared
object or constant (E110), every index value a whole number >= 0 (E008)."""

from __future__ import annotations

from typing import Callable, Iterator

from stampc.diagnostics import Diagnostic, Span
from stampc.semantics.codes import diag
from stampc.syntax import ast
from stampc.syntax.fmt_index import arg_text
from stampc.syntax.indexed import evaluate, indexed_name

MAX_EXPANSION = 1_000_000  # facts or objects one comprehension may produce
COMPARE: dict[str, Callable[[int, int], bool]] = {
    "=": int.__eq__, "!=": int.__ne__, "<": int.__lt__, "<=": int.__le__,
    ">": int.__gt__, ">=": int.__ge__}


def expand_grid(g: ast.ObjectGrid, diags: list[Diagnostic]) -> list[ast.Ident]:
    """``cell(0..1, 0..2)`` → cell_0_0, cell_0_1, …, cell_1_2 (last index fastest)."""
    size = 1
    for lo, hi in g.bounds:
        if lo > hi:
            diags.append(diag("E005", f"invalid object range {lo}..{hi} in `{g.base}(...)`", g.span,
                              "a range is FIRST..LAST with FIRST <= LAST"))
            return []
        size *= hi - lo + 1
    if size > MAX_EXPANSION:
        diags.append(_too_large(g.span, size))
        return []
    names: list[list[int]] = [[]]
    for lo, hi in g.bounds:
        names = [prefix + [i] for prefix in names for i in range(lo, hi + 1)]
    return [ast.Ident(indexed_name(g.base, tuple(n)), g.span) for n in names]


def _too_large(span: Span, size: int | None = None) -> Diagnostic:
    what = f" ({size} items)" if size is not None else ""
    return diag("E008", f"comprehension too large{what}: at most {MAX_EXPANSION}", span)


def expand_forall(f: ast.InitForall, known: Callable[[str], bool],
                  diags: list[Diagnostic]) -> list[ast.Atom]:
    """The atoms of ``f``; reports the first undeclared name (E110) or bad index (E008)
    and leaves out the atoms that hold one."""
    for r in f.ranges:
        if _literal(r.first) and _literal(r.last) and evaluate(r.first, {}) > evaluate(r.last, {}):
            diags.append(diag("E008", f"empty range {evaluate(r.first, {})}..{evaluate(r.last, {})} "
                              f"for `{r.var}`", r.span, "a range is FIRST..LAST with FIRST <= LAST"))
            return []
    if all(_literal(r.first) and _literal(r.last) for r in f.ranges):
        size = 1
        for r in f.ranges:
            size *= evaluate(r.last, {}) - evaluate(r.first, {}) + 1
        if size > MAX_EXPANSION:
            diags.append(_too_large(f.span, size))
            return []
    atoms: list[ast.Atom] = []
    bad = 0
    first_bad: Diagnostic | None = None
    for count, env in enumerate(_assignments(f.ranges, f.conditions), 1):
        if count > MAX_EXPANSION:
            diags.append(_too_large(f.span))
            return []
        args: list[ast.Ident] = []
        for arg in f.atom.args:
            if isinstance(arg, ast.IndexedName):
                problem, name = _resolve(arg, env, known)
                if problem is not None:
                    bad += 1
                    first_bad = first_bad or problem
                    break
                args.append(ast.Ident(name, arg.span))
            else:
                args.append(arg)
        else:
            atoms.append(ast.Atom(f.atom.predicate, tuple(args), f.atom.span))
    if first_bad is not None:
        more = f" (and {bad - 1} more)" if bad > 1 else ""
        diags.append(diag(first_bad.code, first_bad.message + more, first_bad.span, first_bad.hint))
    return atoms


def _literal(e: ast.IndexExpr) -> bool:
    return isinstance(e, ast.IndexNum)


def _assignments(ranges: tuple[ast.IndexRange, ...],
                 conds: tuple[ast.IndexCond, ...]) -> Iterator[dict[str, int]]:
    """Every assignment of the range variables (in order, the last fastest) that passes
    the filter; a range may use the variables before it."""
    def walk(i: int, env: dict[str, int]) -> Iterator[dict[str, int]]:
        if i == len(ranges):
            if all(COMPARE[c.op](evaluate(c.left, env), evaluate(c.right, env)) for c in conds):
                yield dict(env)
            return
        r = ranges[i]
        for v in range(evaluate(r.first, env), evaluate(r.last, env) + 1):
            env[r.var] = v
            yield from walk(i + 1, env)
        env.pop(r.var, None)
    return walk(0, {})


def _resolve(arg: ast.IndexedName, env: dict[str, int],
             known: Callable[[str], bool]) -> tuple[Diagnostic | None, str]:
    values = tuple(evaluate(i, env) for i in arg.indices)
    at = ", ".join(f"{k} = {v}" for k, v in env.items())
    shown = _show(arg)
    if any(v < 0 for v in values):
        return diag("E008", f"`{shown}` has a negative index for {at}", arg.span,
                    "restrict the ranges or add a `when` filter so that indices stay >= 0"), ""
    name = indexed_name(arg.base, values)
    if not known(name):
        return diag("E110", f"`{shown}` names `{name}` for {at}, which is not declared", arg.span,
                    "restrict the ranges, add a `when` filter (e.g. `when i < 4:`), or declare "
                    f"the object (e.g. `object {arg.base}(0..N, ...): TYPE`)"), ""
    return None, name


def _show(arg: ast.IndexedName) -> str:
    return arg_text(arg)
