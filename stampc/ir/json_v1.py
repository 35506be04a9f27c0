"""Reading IR 1.0 documents: rewrite them as 2.0 documents, then load those.

A lifted 1.0 document differs from 2.0 only by its version (it has no ``subtrees``). A
grounded 1.0 document nests conditions and effects inline in every action; they become
nodes of the 2.0 table here, walked with an explicit stack like everything else.
"""

from __future__ import annotations

from typing import Any

from stampc.ir.json_lifted import J
from stampc.ir.json_model import compact
from stampc.ir.json_tree import fold

V1 = "1.0"


def upgrade(data: J, version: str) -> J:
    """The 2.0 form of a 1.0 document (``data`` is left unchanged)."""
    out = {**data, "ir_version": version}
    if data.get("kind") != "grounded":
        return out
    nodes = _NodeTable()
    out["actions"] = [{**{k: v for k, v in a.items() if k not in ("pre", "effect", "index")},
                       "pre": nodes.condition(a["pre"]), "effect": nodes.effect(a["effect"])}
                      for a in _list(data["actions"])]
    out["goal"] = nodes.condition(data["goal"])
    out["nodes"] = nodes.entries
    return out  # an embedded lifted 1.0 document is upgraded when it is read


def _list(x: Any) -> list:
    if not isinstance(x, list):
        raise TypeError(f"expected a list, got {x!r}")
    return x


# A 1.0 sub-structure to convert: (kind, json). Kinds: "f" formula, "c" condition,
# "e" effect, "w" when pair, "b" block.
Item = tuple[str, Any]


def _children(item: Item) -> list[Item]:
    kind, x = item
    if kind == "f":
        if "and" in x or "or" in x:
            return [("f", a) for a in _list(x["and"] if "and" in x else x["or"])]
        return []
    if kind == "c":
        return [("f", f) for f in _list(x.get("rest", []))]
    if kind == "w":
        cond, effect = x
        return [("c", cond), ("e", effect)]
    if kind == "b":
        return [("e", effect) for _, effect in _list(x)]
    return [("w", w) for w in _list(x.get("whens", []))] + \
        [("b", b) for b in _list(x.get("blocks", []))]


class _NodeTable:
    def __init__(self) -> None:
        self.entries: list[J] = []
        self._ids: dict[str, int] = {}

    def condition(self, x: Any) -> int:
        return fold(("c", x), _children, self._combine)

    def effect(self, x: Any) -> int:
        return fold(("e", x), _children, self._combine)

    def _add(self, node: J) -> int:
        text = compact(node)
        ref = self._ids.get(text)
        if ref is None:
            ref = self._ids[text] = len(self.entries)
            self.entries.append(node)
        return ref

    def _combine(self, item: Item, kids: list[int]) -> int:
        kind, x = item
        if kind == "f":
            if "lit" in x or "not" in x:
                return self._add({"t": "lit" if "lit" in x else "not",
                                  "fact": x["lit"] if "lit" in x else x["not"]})
            return self._add({"t": "and" if "and" in x else "or", "args": kids})
        if kind == "w":
            return self._add({"t": "when", "cond": kids[0], "effect": kids[1]})
        if kind == "b":
            return self._add({"t": "prob", "outcomes": [[p, k] for (p, _), k in zip(x, kids)]})
        node: J = {"t": "cond" if kind == "c" else "effect"}
        keys = ("pos", "neg", "never") if kind == "c" else ("add", "del", "unknown", "cost")
        node.update((k, x[k]) for k in keys if k in x)
        if kind == "c":
            if kids:
                node["rest"] = kids
            return self._add(node)
        n_whens = len(x.get("whens", []))
        if n_whens:
            node["whens"] = kids[:n_whens]
        if kids[n_whens:]:
            node["blocks"] = kids[n_whens:]
        return self._add(node)
