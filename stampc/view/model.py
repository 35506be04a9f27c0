"""The report's data: a compact JSON of the policy graph for the page's script.

Facts, effect lists and ground actions are interned, states are stored as differences
from a parent's, and concrete values are summarised (a trajectory becomes its waypoint
count, ends and length), so a policy of twenty thousand nodes stays a few MB. Node
positions come from igraph's tree layout, computed here once.
"""

from __future__ import annotations

import json
import math
from collections import deque
from typing import Any, Mapping

#: px between neighbours and between layers of the tree layout
NODE_GAP, LAYER_GAP = 80, 130


class Interner:
    """Distinct values in first-seen order: each stored once, referred to by index."""

    def __init__(self) -> None:
        self.index: dict[Any, int] = {}

    def id(self, value: Any) -> int:
        return self.index.setdefault(value, len(self.index))

    @property
    def table(self) -> list:
        return [list(v) if isinstance(v, tuple) else v for v in self.index]


def _literal(lit: Mapping[str, Any]) -> str:
    return f"{lit['predicate']}({', '.join(lit['args'])})"


def status(node: Mapping[str, Any]) -> str:
    """goal | dead-end-proven | dead-end | horizon | refined | unrefined."""
    leaf = node.get("leaf")
    if leaf == "dead_end":
        return "dead-end-proven" if node.get("proven") else "dead-end"
    if leaf:
        return str(leaf)
    return "refined" if node.get("refined") else "unrefined"


def page_data(policy: Mapping[str, Any]) -> dict[str, Any]:
    """The policy for the page, compactly: short keys, empty fields left out, facts,
    effect lists and ground actions interned, and each state stored as its difference
    from the state of the node's breadth-first parent (``sb``: parent, ``sa``/``sd``:
    facts added/removed; ``st``: the whole state, at the root). report.js expands it."""
    facts, effects, actions = Interner(), Interner(), Interner()

    def literal_list(literals) -> int:
        return effects.id(tuple(facts.id(_literal(x)) for x in literals))

    nodes = policy["nodes"]
    states = {n["id"]: {facts.id(f) for f in n.get("state", [])} for n in nodes}
    parent = _tree_parents(policy)
    positions = layout(policy)
    out = []
    for node in nodes:
        uid = node["id"]
        x, y = positions[uid]
        entry: dict[str, Any] = {"id": uid, "d": node.get("depth", 0), "s": status(node),
                                 "x": x, "y": y}
        if node.get("action") is not None:
            entry["a"] = actions.id((node["action"], node.get("action_name") or "?"))
        up = parent.get(uid)
        if up is None:
            entry["st"] = sorted(states[uid])
        else:
            entry["sb"] = up
            entry["sa"] = sorted(states[uid] - states[up])
            entry["sd"] = sorted(states[up] - states[uid])
        if node.get("learned"):
            entry["l"] = [[f.get("fact"), f.get("value")] for f in node["learned"]]
        if node.get("sigma"):
            entry["v"] = {k: summarise(v) for k, v in node["sigma"].items()}
        if node.get("outcomes"):
            entry["o"] = [[_rounded_p(o.get("probability")), o.get("child"), o.get("name", ""),
                           literal_list(o.get("adds", [])), literal_list(o.get("deletes", []))]
                          for o in node["outcomes"]]
        if "goal_facts" in node:
            entry["g"] = literal_list(node["goal_facts"])
        out.append(entry)
    return {"root": policy["root"], "nodes": out, "facts": facts.table,
            "effects": effects.table, "actions": actions.table}


def layout(policy: Mapping[str, Any]) -> dict[int, tuple[int, int]]:
    """Pixel positions from igraph's Reingold-Tilford tree layout (a spanning tree by
    breadth-first search where nodes are shared): a tidy tree, root on top, computed
    once here so that the browser only draws (vis-network's own hierarchical layout
    took over 3 s for 23,000 nodes)."""
    import igraph

    ids = [n["id"] for n in policy["nodes"]]
    index = {uid: i for i, uid in enumerate(ids)}
    edges = [(index[n["id"]], index[o["child"]]) for n in policy["nodes"]
             for o in n.get("outcomes", []) if o.get("child") in index]
    graph = igraph.Graph(n=len(ids), edges=edges, directed=True)
    coords = graph.layout_reingold_tilford(mode="out", root=[index[policy["root"]]]).coords
    return {uid: (round(x * NODE_GAP), round(y * LAYER_GAP)) for uid, (x, y) in zip(ids, coords)}


def _rounded_p(p: Any) -> Any:
    """Six significant digits (the page shows four): 0.2777777777777778 costs 18 bytes
    in each of thousands of outcomes."""
    return float(f"{p:.6g}") if isinstance(p, float) else p


def _tree_parents(policy: Mapping[str, Any]) -> dict[int, int]:
    """Each node's parent in the breadth-first tree from the root (acyclic, so the
    page can rebuild states by walking up; nodes not reached keep whole states)."""
    children = {n["id"]: [o.get("child") for o in n.get("outcomes", [])] for n in policy["nodes"]}
    parent: dict[int, int] = {}
    seen, queue = {policy["root"]}, deque([policy["root"]])
    while queue:
        uid = queue.popleft()
        for child in children.get(uid, []):
            if child in children and child not in seen:
                seen.add(child)
                parent[child] = uid
                queue.append(child)
    return parent


def summarise(value: Any) -> str:
    """A concrete value in a line: trajectories by waypoints, ends and length; poses by
    rounded position and orientation; anything else as short JSON."""
    if isinstance(value, dict):
        path = value.get("configs") or value.get("points")
        if isinstance(path, list) and path and all(isinstance(q, list) for q in path):
            rest = {k: v for k, v in value.items() if k in ("target", "held", "released")
                    and v is not None}
            return (f"trajectory: {len(path)} waypoints, length {_length(path):.3f}, from "
                    f"{_short(path[0])} to {_short(path[-1])}"
                    + (f" ({_short(rest)})" if rest else ""))
    return _short(value)


def _length(path: list[list[float]]) -> float:
    return sum(math.dist(a, b) for a, b in zip(path, path[1:]) if len(a) == len(b))


def _short(value: Any, limit: int = 400) -> str:
    text = json.dumps(_rounded(value), separators=(", ", ": "))
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _rounded(value: Any) -> Any:
    if isinstance(value, float):
        return round(value, 3)
    if isinstance(value, list):
        return [_rounded(v) for v in value]
    if isinstance(value, dict):
        return {k: _rounded(v) for k, v in value.items()}
    return value
