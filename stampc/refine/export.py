"""Write a refinement run's outputs: policy.json, coverage.csv/.png, policy.dot/.svg,
summary.json.

policy.json is deterministic for a given seed (no timings in it), so it can be diffed;
timings live in coverage.csv and summary.json.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any, Mapping

from stampc.ir.grounded import GroundModel, bits
from stampc.refine.graph import PolicyGraph
from stampc.refine.options import RefineResult
from stampc.worlds.base import to_json

POLICY_FORMAT = "stampc-policy"
POLICY_VERSION = 1


def _facts(model: GroundModel, mask: int) -> list[str]:
    return [str(model.facts[b]) for b in bits(mask)]


def _literals(model: GroundModel, mask: int, values: Mapping[str, Any]) -> list[dict]:
    out = []
    for bit in bits(mask):
        atom = model.facts[bit]
        out.append({"predicate": atom.predicate, "args": list(atom.args),
                    "values": [to_json(values[a]) if a in values else a for a in atom.args]})
    return out


def policy_json(model: GroundModel, graph: PolicyGraph, result: RefineResult,
                initial_values: Mapping[str, Any], meta: Mapping[str, Any]) -> dict:
    """The refined policy: every reachable node with state, action, concrete arguments,
    outcomes (probabilities, literal effects with concrete values) and refinement status."""
    nodes = []
    values_on_path = _values_by_node(graph, initial_values)
    for uid in sorted(graph.reachable()):
        node = graph[uid]
        entry: dict[str, Any] = {
            "id": uid, "depth": node.depth, "state": _facts(model, node.state),
            "leaf": node.leaf, "refined": node.refined,
            "learned": [{"fact": str(model.facts[f]), "value": v} for f, v in node.learned],
        }
        if node.leaf == "goal":
            entry["goal_facts"] = [{"predicate": model.facts[f].predicate,
                                    "args": list(model.facts[f].args)}
                                   for f in bits(model.goal.pos)]
        if node.action is not None:
            action = model.actions[node.action]
            schema = model.lifted.domain.actions[action.schema]
            env = {**values_on_path[uid], **(node.sigma or {})}
            entry["action"] = action.label
            entry["action_name"] = action.name
            entry["args"] = {p.name: {"symbol": a, "value": to_json(env[a]) if a in env else None}
                             for p, a in zip(schema.params, action.args)}
            entry["outcomes"] = [{
                "probability": e.probability, "child": e.child,
                "adds": _literals(model, e.successor.add, env),
                "deletes": _literals(model, e.successor.delete & ~e.successor.add, env),
            } for e in node.edges]
        nodes.append(entry)
    return {"format": POLICY_FORMAT, "version": POLICY_VERSION, **dict(meta),
            "seed": result.seed, "root": graph.root, "coverage": round(result.coverage, 12),
            "goal_probability": round(result.goal_probability, 12), "nodes": nodes}


def _values_by_node(graph: PolicyGraph, initial: Mapping[str, Any]) -> dict[int, dict]:
    """Symbol values bound above each node (first path found, breadth-first)."""
    out = {graph.root: dict(initial)}
    queue = [graph.root]
    while queue:
        uid = queue.pop(0)
        node = graph[uid]
        env = {**out[uid], **(node.sigma or {})}
        for e in node.edges:
            if e.child not in out:
                out[e.child] = env
                queue.append(e.child)
    return out


def policy_dot(model: GroundModel, graph: PolicyGraph) -> str:
    lines = ["digraph policy {", '  node [shape=box, fontname="Helvetica"];']
    for uid in graph.reachable():
        node = graph[uid]
        if node.is_leaf:
            label, style = node.leaf or "leaf", "ellipse"
        else:
            label, style = model.actions[node.action].label, "box"
        color = "palegreen" if node.refined or node.leaf in ("goal",) else "lightgrey"
        lines.append(f'  n{uid} [label="{_escape(label)}", shape={style}, style=filled, fillcolor={color}];')
        for e in node.edges:
            lines.append(f'  n{uid} -> n{e.child} [label="{e.probability:.3g}"];')
    lines.append("}")
    return "\n".join(lines) + "\n"


def _escape(text: str) -> str:
    return text.replace("\\", "\\\\").replace('"', '\\"')


def write_coverage_csv(result: RefineResult, path: Path) -> None:
    with path.open("w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["time_s", "coverage", "goal_probability", "refined_nodes",
                         "prg_nodes", "abstract_solves", "event"])
        for e in result.events:
            writer.writerow([f"{e.time_s:.6f}", f"{e.coverage:.9f}", f"{e.goal_probability:.9f}",
                             e.refined_nodes, e.prg_nodes, e.abstract_solves, e.kind])


def write_coverage_png(result: RefineResult, path: Path, title: str = "") -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    times = [e.time_s for e in result.events]
    cov = [e.coverage for e in result.events]
    fig, ax = plt.subplots(figsize=(6, 3.5), dpi=100)
    ax.step(times, cov, where="post", label="refined probability mass")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("coverage")
    ax.set_ylim(0, 1.02)
    ax.grid(alpha=0.3)
    ax.set_title(title or "anytime coverage")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def write_policy_svg(model: GroundModel, graph: PolicyGraph, path: Path) -> None:
    """Draw the policy graph by depth with networkx + matplotlib (no Graphviz needed)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import networkx as nx

    g = nx.DiGraph()
    for uid in graph.reachable():
        node = graph[uid]
        g.add_node(uid, layer=node.depth,
                   label=node.leaf if node.is_leaf else model.actions[node.action].name)
        for e in node.edges:
            g.add_edge(uid, e.child)
    pos = nx.multipartite_layout(g, subset_key="layer", align="horizontal", scale=-1)
    fig, ax = plt.subplots(figsize=(max(6, len(g) * 0.25), 6))
    colors = ["palegreen" if graph[u].refined or graph[u].leaf == "goal" else "lightgrey" for u in g]
    nx.draw_networkx(g, pos, ax=ax, labels=nx.get_node_attributes(g, "label"),
                     node_color=colors, node_size=300, font_size=6, arrows=True)
    ax.set_axis_off()
    fig.tight_layout()
    fig.savefig(path, format="svg")
    plt.close(fig)


def summary_json(result: RefineResult, meta: Mapping[str, Any]) -> dict:
    return {**dict(meta), "coverage": result.coverage, "goal_probability": result.goal_probability,
            "abstract_goal_probability": result.abstract_goal_probability,
            "wall_time_s": result.wall_time_s, "time_to_coverage": result.time_to_coverage,
            "prg_nodes": result.prg_nodes, "refined_paths": result.refined_paths,
            "refined_nodes": result.refined_nodes, "abstract_solves": result.abstract_solves,
            "seed": result.seed, "stop_reason": result.stop_reason}


def write_outputs(out_dir: Path, model: GroundModel, graph: PolicyGraph, result: RefineResult,
                  initial_values: Mapping[str, Any], meta: Mapping[str, Any]) -> None:
    out_dir.mkdir(parents=True, exist_ok=True)
    policy = policy_json(model, graph, result, initial_values, meta)
    (out_dir / "policy.json").write_text(json.dumps(policy, indent=1, sort_keys=True))
    (out_dir / "policy.dot").write_text(policy_dot(model, graph))
    write_policy_svg(model, graph, out_dir / "policy.svg")
    write_coverage_csv(result, out_dir / "coverage.csv")
    write_coverage_png(result, out_dir / "coverage.png", str(meta.get("problem", "")))
    (out_dir / "summary.json").write_text(json.dumps(summary_json(result, meta), indent=2))
