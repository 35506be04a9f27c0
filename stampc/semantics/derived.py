"""Checks of derived and symmetric predicates (docs/language.md, "Derived predicates").

- a derived predicate's definition is a formula over its parameters (E105 otherwise);
- recursion must be *stratified*: no derived predicate may depend on itself through a
  negation (E312, with the cycle);
- effects never set a derived predicate (E311): its value follows from its definition;
- a ``symmetric`` predicate has two parameters of one type (E313).
"""

from __future__ import annotations

from stampc.diagnostics import Diagnostic, Label
from stampc.semantics.codes import diag
from stampc.semantics.scope import DomainInfo
from stampc.semantics.terms import Ctx, check_formula, check_params
from stampc.syntax import ast


def check_derived(info: DomainInfo, base: Ctx) -> None:
    for decl in info.predicates.values():
        if decl.derived is not None:
            env = check_params(decl.params, base)
            check_formula(decl.derived, env, Ctx(info, base.diags, base.symbols, "E105"))
        if decl.symmetric:
            _check_symmetric(decl, base.diags)
    _check_strata(info, base.diags)


def _check_symmetric(decl: ast.PredicateDecl, diags: list[Diagnostic]) -> None:
    types = [p.type.name for p in decl.params]
    if len(types) != 2 or types[0] != types[1]:
        diags.append(diag("E313", f"symmetric predicate `{decl.name.name}` must have two parameters "
                          f"of one type, not ({', '.join(types)})", decl.name.span,
                          "declare it as `symmetric predicate NAME(a, b: TYPE)`"))


def dependencies(f: ast.Formula | None, positive: bool = True) -> list[tuple[ast.Atom, bool]]:
    """Atoms ``f`` reads, with their polarity (False under an odd number of negations;
    ``implies`` negates its left side)."""
    out: list[tuple[ast.Atom, bool]] = []
    stack: list[tuple[ast.Formula, bool]] = [(f, positive)] if f is not None else []
    while stack:
        node, pol = stack.pop()
        if isinstance(node, ast.Atom):
            out.append((node, pol))
        elif isinstance(node, ast.Not):
            stack.append((node.arg, not pol))
        elif isinstance(node, (ast.And, ast.Or)):
            stack.extend((a, pol) for a in node.args)
        elif isinstance(node, ast.Implies):
            stack.extend([(node.left, not pol), (node.right, pol)])
        elif isinstance(node, ast.Quantified):
            stack.append((node.body, pol))
    return out


def _check_strata(info: DomainInfo, diags: list[Diagnostic]) -> None:
    """E312 for a derived predicate on a cycle that passes through a negation."""
    derived = {n: d for n, d in info.predicates.items() if d.derived is not None}
    edges: dict[str, list[tuple[str, bool, ast.Atom]]] = {
        n: [(a.predicate.name, pol, a) for a, pol in dependencies(d.derived)
            if a.predicate.name in derived] for n, d in derived.items()}
    reported: set[str] = set()
    for start, decl in derived.items():
        if start in reported:
            continue
        cycle = _negative_cycle(start, edges)
        if cycle is None:
            continue
        reported.update(target for target, _, _ in cycle)
        names = " -> ".join([start] + [target for target, _, _ in cycle])
        negated = next(atom for _, pol, atom in cycle if not pol)
        diags.append(diag("E312", f"derived predicate `{start}` depends on itself through a negation "
                          f"({names})", decl.name.span,
                          "recursion must be stratified: a predicate may use `not` only on predicates "
                          "that do not depend on it", (Label(negated.span, "negated here"),)))


def _negative_cycle(start: str, edges) -> list[tuple[str, bool, ast.Atom]] | None:
    """Edges of a path start -> ... -> start with at least one negative edge."""
    frontier: list[tuple[str, bool, list]] = [(start, False, [])]
    visited: set[tuple[str, bool]] = set()
    while frontier:
        node, negative, path = frontier.pop()
        for edge in edges.get(node, ()):
            target, pol, _atom = edge
            neg = negative or not pol
            if target == start and neg:
                return path + [edge]
            if (target, neg) not in visited:
                visited.add((target, neg))
                frontier.append((target, neg, path + [edge]))
    return None


def effect_on_derived(decl: ast.PredicateDecl, atom: ast.Atom, what: str) -> Diagnostic:
    return diag("E311", f"{what} derived predicate `{decl.name.name}`", atom.predicate.span,
                "a derived predicate follows from its definition; change the facts it is "
                "defined from instead", (Label(decl.name.span, "defined here"),))
