"""Iterative JSON codec for the lifted IR's trees (formulas, effects, numeric expressions).

Nothing here recurses on the input, so 10,000-deep formulas round-trip. The JSON text stays
shallow too (``json.dumps``/``json.loads`` recurse in C and stop near 1,000 levels): a
sub-tree reaching :data:`SPILL_HEIGHT` nodes is moved into the document's ``"subtrees"``
table and replaced by ``{"t": "ref", "id": k}``. An entry may only refer to entries before
it, so the table cannot hold cycles. Ordinary models never reach the height and read as
plain nested trees (format: docs/ir.md).
"""

from __future__ import annotations

from itertools import repeat
from typing import Any, Callable, Sequence, TypeVar

from stampc.ir import lifted as L
from stampc.ir.json_lifted import (
    J, atom_from, atom_to, frac_from, frac_to, params_from, params_to, term_from, term_to)

N = TypeVar("N")
R = TypeVar("R")

#: Tree height (in nodes) at which a sub-tree moves to the ``"subtrees"`` table.
SPILL_HEIGHT = 32


def fold(root: N, children: Callable[[N], Sequence[N]], combine: Callable[[N, list[R]], R]) -> R:
    """Post-order evaluation of a tree with an explicit stack (no recursion).

    ``combine(node, results_of_children_in_order)`` gives a node's result.
    """
    results: list[R] = []
    stack: list[tuple[N, Sequence[N] | None]] = [(root, None)]
    while stack:
        node, kids = stack.pop()
        if kids is None:
            kids = children(node)
            stack.append((node, kids))
            stack.extend(zip(reversed(kids), repeat(None)))
            continue
        cut = len(results) - len(kids)
        args = results[cut:]
        del results[cut:]
        results.append(combine(node, args))
    return results[0]


# ------------------------------------------------------------------ encoding
# Dispatch on the exact node class: one dict lookup per node instead of isinstance
# chains (the lifted writer handles millions of nodes for 165k-action domains).
_NO_KIDS: tuple = ()
_CHILDREN: dict[type, Callable[[Any], Sequence[Any]]] = {
    L.And: lambda n: n.args, L.Or: lambda n: n.args, L.Not: lambda n: (n.arg,),
    L.Imply: lambda n: (n.left, n.right), L.BinOp: lambda n: (n.left, n.right),
    L.Forall: lambda n: (n.body,), L.Exists: lambda n: (n.body,),
    L.EffAnd: lambda n: n.effects, L.When: lambda n: (n.condition, n.effect),
    L.EffForall: lambda n: (n.effect,),
    L.Probabilistic: lambda n: tuple(o.effect for o in n.outcomes),
    L.CostEffect: lambda n: (n.amount,),
}
_LEAVES = (L.Atom, L.Equals, L.Truth, L.Lit, L.Unknown, L.Num, L.FuncTerm)


def _children(n: Any) -> Sequence[Any]:
    kids = _CHILDREN.get(type(n))
    if kids is not None:
        return kids(n)
    if type(n) in _LEAVES:
        return _NO_KIDS
    raise TypeError(f"not a formula, effect or numeric expression: {n!r}")


def _prob_to(n: L.Probabilistic, kids: list[Any]) -> J:
    return {"t": "prob", "outcomes": [{"p": frac_to(o.probability), "effect": k,
                                       "label": o.label} for o, k in zip(n.outcomes, kids)]}


#: node class -> JSON of the node given its children's JSON (``kids``)
_NODE_TO: dict[type, Callable[[Any, list[Any]], J]] = {
    L.Atom: lambda n, kids: {"t": "atom", **atom_to(n)},
    L.Equals: lambda n, kids: {"t": "eq", "args": [term_to(n.left), term_to(n.right)]},
    L.Not: lambda n, kids: {"t": "not", "arg": kids[0]},
    L.And: lambda n, kids: {"t": "and", "args": kids},
    L.Or: lambda n, kids: {"t": "or", "args": kids},
    L.Imply: lambda n, kids: {"t": "imply", "args": kids},
    L.Forall: lambda n, kids: {"t": "forall", "params": params_to(n.params), "body": kids[0]},
    L.Exists: lambda n, kids: {"t": "exists", "params": params_to(n.params), "body": kids[0]},
    L.Truth: lambda n, kids: {"t": "truth", "value": n.value},
    L.Lit: lambda n, kids: {"t": "lit", "atom": atom_to(n.atom), "positive": n.positive},
    L.Unknown: lambda n, kids: {"t": "unknown", "atom": atom_to(n.atom)},
    L.EffAnd: lambda n, kids: {"t": "and", "effects": kids},
    L.When: lambda n, kids: {"t": "when", "cond": kids[0], "effect": kids[1]},
    L.EffForall: lambda n, kids: {"t": "forall", "params": params_to(n.params),
                                  "effect": kids[0]},
    L.Probabilistic: _prob_to,
    L.CostEffect: lambda n, kids: {"t": "cost", "amount": kids[0]},
    L.Num: lambda n, kids: {"t": "num", "value": frac_to(n.value)},
    L.FuncTerm: lambda n, kids: {"t": "func", "name": n.function,
                                 "args": [term_to(a) for a in n.args]},
    L.BinOp: lambda n, kids: {"t": "binop", "op": n.op, "left": kids[0], "right": kids[1]},
}


class TreeEncoder:
    """Encodes trees of one document; ``subtrees`` collects the spilled sub-trees."""

    def __init__(self) -> None:
        self.subtrees: list[J] = []

    def encode(self, root: Any) -> J:
        return fold(root, _children, self._combine)[0]

    def _combine(self, n: Any, kids: list[tuple[J, int]]) -> tuple[J, int]:
        if not kids:
            return _NODE_TO[type(n)](n, []), 1
        height = 1 + max([h for _, h in kids])
        out = _NODE_TO[type(n)](n, [j for j, _ in kids])
        if height < SPILL_HEIGHT:
            return out, height
        self.subtrees.append(out)
        return {"t": "ref", "id": len(self.subtrees) - 1}, 1


# ------------------------------------------------------------------ decoding
# An item is (kind, json, bound): kind "f" formula, "e" effect, "n" numeric expression;
# refs inside it must point below ``bound``.
Item = tuple[str, Any, int]

_FORMULA_KIDS: dict[str, Callable[[J], list[tuple[str, Any]]]] = {
    "not": lambda x: [("f", x["arg"])],
    "and": lambda x: [("f", a) for a in _list(x["args"])],
    "or": lambda x: [("f", a) for a in _list(x["args"])],
    "imply": lambda x: [("f", a) for a in _pair(x["args"])],
    "forall": lambda x: [("f", x["body"])],
    "exists": lambda x: [("f", x["body"])],
}
_EFFECT_KIDS: dict[str, Callable[[J], list[tuple[str, Any]]]] = {
    "and": lambda x: [("e", a) for a in _list(x["effects"])],
    "when": lambda x: [("f", x["cond"]), ("e", x["effect"])],
    "forall": lambda x: [("e", x["effect"])],
    "prob": lambda x: [("e", o["effect"]) for o in _list(x["outcomes"])],
    "cost": lambda x: [("n", x["amount"])],
}
_NUM_KIDS: dict[str, Callable[[J], list[tuple[str, Any]]]] = {
    "binop": lambda x: [("n", x["left"]), ("n", x["right"])],
}
_KIDS = {"f": _FORMULA_KIDS, "e": _EFFECT_KIDS, "n": _NUM_KIDS}


def _list(x: Any) -> list:
    if not isinstance(x, list):
        raise TypeError(f"expected a list, got {x!r}")
    return x


def _pair(x: Any) -> list:
    if len(_list(x)) != 2:
        raise ValueError(f"expected two arguments, got {len(x)}")
    return x


def _formula_from(x: J, kids: list[Any]) -> L.Formula:
    tag = x["t"]
    if tag == "atom":
        return atom_from(x)
    if tag == "eq":
        left, right = _pair(x["args"])
        return L.Equals(term_from(left), term_from(right))
    if tag == "not":
        return L.Not(kids[0])
    if tag in ("and", "or"):
        return L.And(tuple(kids)) if tag == "and" else L.Or(tuple(kids))
    if tag == "imply":
        return L.Imply(kids[0], kids[1])
    if tag in ("forall", "exists"):
        return (L.Forall if tag == "forall" else L.Exists)(params_from(x["params"]), kids[0])
    if tag == "truth":
        return L.Truth(bool(x["value"]))
    raise ValueError(f"unknown formula tag {tag!r}")


def _effect_from(x: J, kids: list[Any]) -> L.Effect:
    tag = x["t"]
    if tag == "lit":
        return L.Lit(atom_from(x["atom"]), bool(x["positive"]))
    if tag == "unknown":
        return L.Unknown(atom_from(x["atom"]))
    if tag == "and":
        return L.EffAnd(tuple(kids))
    if tag == "when":
        return L.When(kids[0], kids[1])
    if tag == "forall":
        return L.EffForall(params_from(x["params"]), kids[0])
    if tag == "prob":
        return L.Probabilistic(tuple(L.Outcome(frac_from(o["p"]), k, o.get("label"))
                                     for o, k in zip(x["outcomes"], kids)))
    if tag == "cost":
        return L.CostEffect(kids[0])
    raise ValueError(f"unknown effect tag {tag!r}")


def _num_from(x: J, kids: list[Any]) -> L.NumExpr:
    tag = x["t"]
    if tag == "num":
        return L.Num(frac_from(x["value"]))
    if tag == "func":
        return L.FuncTerm(str(x["name"]), tuple(term_from(a) for a in _list(x["args"])))
    if tag == "binop":
        return L.BinOp(str(x["op"]), kids[0], kids[1])
    raise ValueError(f"unknown numeric expression tag {tag!r}")


_BUILD = {"f": _formula_from, "e": _effect_from, "n": _num_from}


class TreeDecoder:
    """Decodes the trees of one document against its ``"subtrees"`` table."""

    def __init__(self, subtrees: list[Any]) -> None:
        self.table = _list(subtrees)
        self._done: dict[tuple[str, int], Any] = {}  # a shared entry is decoded once

    def formula(self, x: Any) -> L.Formula:
        return self._decode(("f", x, len(self.table)))

    def effect(self, x: Any) -> L.Effect:
        return self._decode(("e", x, len(self.table)))

    def num(self, x: Any) -> L.NumExpr:
        return self._decode(("n", x, len(self.table)))

    def _decode(self, root: Item) -> Any:
        return fold(root, self._children, self._combine)

    def _children(self, item: Item) -> list[Item]:
        kind, x, bound = item
        if not isinstance(x, dict):
            raise TypeError(f"expected a JSON object, got {x!r}")
        tag = x["t"]
        if tag == "ref":
            k = self._ref(x, bound)
            if (kind, k) in self._done:
                return []
            return [(kind, self.table[k], k)]
        expand = _KIDS[kind].get(tag)
        return [] if expand is None else [(k, j, bound) for k, j in expand(x)]

    def _combine(self, item: Item, kids: list[Any]) -> Any:
        kind, x, bound = item
        if x["t"] != "ref":
            return _BUILD[kind](x, kids)
        key = (kind, self._ref(x, bound))
        if kids:
            self._done[key] = kids[0]
        return self._done[key]

    @staticmethod
    def _ref(x: J, bound: int) -> int:
        k = x["id"]
        if isinstance(k, bool) or not isinstance(k, int) or not 0 <= k < bound:
            raise ValueError(f"invalid subtree reference {k!r}")
        return k
