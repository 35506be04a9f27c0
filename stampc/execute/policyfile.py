"""Read a refined policy (policy.json from ``stampc refine -o``) with located diagnostics.

``I003`` covers every file that is not one: invalid or truncated JSON (at the parser's
line and column), JSON of another kind (an abstract policy from ``stampc solve``, a
summary.json, an IR file) and a refined policy missing the parts execution needs.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from stampc.diagnostics import Span, StampcError, error

HINT = "pass the policy.json written by `stampc refine ... -o DIR`"
#: what execution reads from a refined policy, and the JSON type each must have
REQUIRED = {"files": list, "world": str, "scene": dict, "root": int, "nodes": list}


@dataclass(frozen=True)
class PolicyFile:
    path: Path
    text: str
    data: Mapping[str, Any]


def load_policy(path: Path) -> PolicyFile:
    from stampc.inputs import display_name, json_problem, read_input_text

    shown = display_name(path)
    text = read_input_text(path, shown)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise _not_a_policy(f"{json_problem(exc, text)}: {exc.msg}",
                            Span.point(shown, exc.lineno, exc.colno))
    _check_kind(data, shown)
    return PolicyFile(path, text, data)


def _check_kind(data: Any, shown: str) -> None:
    if not isinstance(data, dict):
        raise _not_a_policy(f"not a stampc policy file: a JSON {type(data).__name__}, not "
                            "an object", Span.point(shown))
    if data.get("format") == "stampc-policy" and "policy" in data and "nodes" not in data:
        raise _not_a_policy("this is an abstract policy (written by `stampc solve`): it has "
                            "no concrete values to execute", Span.point(shown),
                            "refine it first: `stampc refine DOMAIN PROBLEM --world W -o DIR`, "
                            "then execute DIR/policy.json")
    if data.get("format") != "stampc-policy":
        kind = ("an IR file" if "ir_version" in data or "format" in data and
                "ir" in str(data.get("format")) else
                "a refinement summary (summary.json)" if "stop_reason" in data else
                f"format {data.get('format')!r}" if "format" in data else "no `format` key")
        raise _not_a_policy(f"not a stampc policy file ({kind})", Span.point(shown))
    wrong = [f"`{k}` ({'missing' if k not in data else 'not a ' + t.__name__})"
             for k, t in REQUIRED.items() if not isinstance(data.get(k), t)
             or isinstance(data.get(k), bool)]
    if not wrong and not all(isinstance(f, str) for f in data["files"]):
        wrong = ["`files` (not a list of paths)"]
    if not wrong:
        wrong = _node_problems(data)
    if wrong:
        raise _not_a_policy("not a complete refined policy: " + ", ".join(wrong),
                            Span.point(shown))


def _node_problems(data: Mapping[str, Any]) -> list[str]:
    ids = set()
    for i, node in enumerate(data["nodes"]):
        if not isinstance(node, dict) or not isinstance(node.get("id"), int) \
                or "leaf" not in node or "refined" not in node:
            return [f"`nodes[{i}]` (needs id, leaf, refined)"]
        ids.add(node["id"])
        if node["leaf"] is None and node["refined"] and not isinstance(node.get("outcomes"), list):
            return [f"`nodes[{i}]` (a refined action node without outcomes)"]
    if data["root"] not in ids:
        return ["`root` (names no node)"]
    for node in data["nodes"]:
        for o in node.get("outcomes") or []:
            if not isinstance(o, dict) or o.get("child") not in ids:
                return [f"`nodes` (node {node['id']} has an outcome leading to no node)"]
    return []


def _not_a_policy(message: str, span: Span, hint: str = HINT) -> StampcError:
    return StampcError([error("I003", message, span, hint=hint)])
