"""The report's data: a compact JSON of the policy graph for the page's script.

Facts are interned (each node lists indices into one table) and concrete values are
summarised (a trajectory becomes its waypoint count, ends and length), so a policy of
thousands of nodes stays a few MB. The page lays the graph out with vis-network's
hierarchical layout, one level per policy depth.
"""

from __future__ import annotations

import json
import math
from typing import Any, Mapping



class FactTable:
    """Interned fact strings: the index of each distinct fact, in first-seen order."""

    def __init__(self) -> None:
        self.index: dict[str, int] = {}

    def ids(self, facts) -> list[int]:
        return [self.index.setdefault(f, len(self.index)) for f in facts]

    def literal_ids(self, literals) -> list[int]:
        return self.ids(f"{lit['predicate']}({', '.join(lit['args'])})" for lit in literals)

    @property
    def table(self) -> list[str]:
        return list(self.index)


def status(node: Mapping[str, Any]) -> str:
    """goal | dead-end-proven | dead-end | horizon | refined | unrefined."""
    leaf = node.get("leaf")
    if leaf == "dead_end":
        return "dead-end-proven" if node.get("proven") else "dead-end"
    if leaf:
        return str(leaf)
    return "refined" if node.get("refined") else "unrefined"


def page_data(policy: Mapping[str, Any]) -> dict[str, Any]:
    """Nodes (with positions, status, state, values, outcomes) and the fact table."""
    facts = FactTable()
    nodes = []
    for node in policy["nodes"]:
        entry = {
            "id": node["id"], "depth": node.get("depth", 0), "status": status(node),
            "label": node.get("action_name") or node.get("leaf") or "?",
            "action": node.get("action"),
            "state": facts.ids(node.get("state", [])),
            "learned": [{"fact": f.get("fact"), "value": f.get("value")}
                        for f in node.get("learned", [])],
            "values": {k: summarise(v) for k, v in (node.get("sigma") or {}).items()},
            "outcomes": [{"p": o.get("probability"), "child": o.get("child"),
                          "name": o.get("name", ""), "adds": facts.literal_ids(o.get("adds", [])),
                          "deletes": facts.literal_ids(o.get("deletes", []))}
                         for o in node.get("outcomes", [])],
        }
        if "goal_facts" in node:
            entry["goal"] = facts.literal_ids(node["goal_facts"])
        nodes.append(entry)
    return {"root": policy["root"], "nodes": nodes, "facts": facts.table}


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
