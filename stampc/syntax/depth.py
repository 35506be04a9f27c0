"""The nesting limit: formulas, effects and numeric expressions at most ``MAX_NESTING``
levels deep.

The parser itself never recurses (an LALR automaton with explicit stacks), but the
passes after it (checker, formatter, lowering, grounding, relaxation, JSON and PPDDL
writers) walk trees recursively. Rather than let deep input reach them and end in a
``RecursionError``, :func:`limit_nesting` measures every declaration right after
parsing, with an explicit stack, and replaces a declaration nested deeper than the
limit by an ``E006`` diagnostic located at the first node past the limit. The limit
leaves every later pass well inside Python's default recursion limit (at most three
frames per level), also in threads with small stacks; hand-written domains nest a few
levels, generated ones a few dozen.
"""

from __future__ import annotations

from types import MappingProxyType

from stampc.diagnostics import Diagnostic, Span, error
from stampc.syntax import ast

MAX_NESTING = 200
TOO_DEEP = "E006"

# children of every node that can nest, by exact type (leaves are absent)
CHILDREN = MappingProxyType({
    ast.Not: lambda n: (n.arg,),
    ast.And: lambda n: n.args,
    ast.Or: lambda n: n.args,
    ast.Implies: lambda n: (n.left, n.right),
    ast.Quantified: lambda n: (n.body,),
    ast.EffAnd: lambda n: n.effects,
    ast.When: lambda n: (n.condition, n.effect),
    ast.EffForall: lambda n: (n.effect,),
    ast.Probabilistic: lambda n: tuple(o.effect for o in n.outcomes),
    ast.CostEffect: lambda n: (n.amount,),
    ast.BinOp: lambda n: (n.left, n.right),
    ast.IndexOp: lambda n: (n.left, n.right),
})


def _roots(decl: ast.Decl) -> tuple:
    if isinstance(decl, ast.ActionDecl):
        return tuple(x for x in (decl.pre, decl.eff, decl.cost) if x is not None)
    if isinstance(decl, ast.GoalDecl):
        return (decl.formula,)
    if isinstance(decl, ast.PredicateDecl) and decl.derived is not None:
        return (decl.derived,)
    if isinstance(decl, ast.InitDecl):  # index expressions of comprehensions
        return tuple(_index_roots(f) for f in decl.facts if isinstance(f, ast.InitForall))
    return ()


def _index_roots(f: ast.InitForall) -> tuple:
    exprs = [e for r in f.ranges for e in (r.first, r.last)]
    exprs += [e for c in f.conditions for e in (c.left, c.right)]
    exprs += [i for a in f.atom.args if isinstance(a, ast.IndexedName) for i in a.indices]
    return max(exprs, key=_index_depth)


def _index_depth(e) -> int:
    depth, stack = 0, [(e, 1)]
    while stack:
        node, level = stack.pop()
        depth = max(depth, level)
        if isinstance(node, ast.IndexOp):
            stack.extend([(node.left, level + 1), (node.right, level + 1)])
    return depth


def too_deep(decl: ast.Decl, limit: int | None = None) -> ast.Formula | ast.Effect | ast.NumExpr | None:
    """The first node (in source order) nested deeper than ``limit`` (default
    :data:`MAX_NESTING`) levels, or None."""
    limit = MAX_NESTING if limit is None else limit
    children = CHILDREN
    stack = [(root, 1) for root in reversed(_roots(decl))]
    while stack:
        node, level = stack.pop()
        inner = children.get(type(node))
        if inner is None:
            continue
        if level > limit:
            return node
        stack.extend((child, level + 1) for child in reversed(inner(node)))
    return None


def limit_nesting(program: ast.Program) -> tuple[ast.Program, list[Diagnostic]]:
    """``program`` without its over-deep declarations, and one ``E006`` for each."""
    kept: list = []
    diags: list[Diagnostic] = []
    for decl in program.decls:
        node = too_deep(decl)
        if node is None:
            kept.append(decl)
            continue
        diags.append(nesting_diagnostic(node.span, decl.span))
    if not diags:
        return program, diags
    return ast.Program(tuple(kept), program.file), diags


def nesting_diagnostic(span: Span, decl_span: Span) -> Diagnostic:
    where = span if span.file != ast.NOWHERE.file else decl_span
    return error(TOO_DEEP, f"nesting deeper than {MAX_NESTING} levels", where,
                 f"stamp accepts formulas, effects and cost expressions up to {MAX_NESTING} levels "
                 "deep; flatten it (`a and b and c` is one level) or name parts with helper predicates")
