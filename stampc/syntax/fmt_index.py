"""Canonical text of indexed names and problem comprehensions (used by fmt.py)."""

from __future__ import annotations

from stampc.syntax import ast

_PREC = {"+": 1, "-": 1, "*": 2}


def index_text(e: ast.IndexExpr, prec: int = 0) -> str:
    """``i + 1``, ``(i + 1) * 2``, ``i - (j - 1)``: parentheses only where needed
    (``-`` is left-associative, so a right operand of the same level keeps them)."""
    if isinstance(e, ast.IndexNum):
        return str(e.value)
    if isinstance(e, ast.IndexVar):
        return e.name
    own = _PREC[e.op]
    text = f"{index_text(e.left, own)} {e.op} {index_text(e.right, own + 1)}"
    return f"({text})" if own < prec else text


def arg_text(arg: object) -> str:
    if isinstance(arg, ast.IndexedName):
        return f"{arg.base}({', '.join(index_text(i) for i in arg.indices)})"
    return arg.name  # type: ignore[attr-defined]


def init_forall_text(f: ast.InitForall) -> str:
    ranges = ", ".join(f"{r.var}: {index_text(r.first)}..{index_text(r.last)}" for r in f.ranges)
    conds = " and ".join(f"{index_text(c.left)} {c.op} {index_text(c.right)}" for c in f.conditions)
    atom = f.atom
    body = atom.predicate.name  # type: ignore[attr-defined]
    if atom.args:
        body += f"({', '.join(arg_text(a) for a in atom.args)})"
    return f"forall ({ranges}) " + (f"when {conds}: " if conds else "") + body


def object_item_text(item: object) -> str:
    if isinstance(item, ast.ObjectGrid):
        return f"{item.base}({', '.join(f'{lo}..{hi}' for lo, hi in item.bounds)})"
    if isinstance(item, ast.ObjectRange):
        return f"{item.first.name}..{item.last.name}"
    return item.name  # type: ignore[attr-defined]
