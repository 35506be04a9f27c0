"""Write a refinement run's outputs: policy.json, coverage.csv/.svg, policy.dot/.svg,
summary.json and prg.json (the PRG's history, ``stampc.refine.history``).

policy.json is deterministic for a given seed (no timings in it), so it can be diffed;
timings live in coverage.csv and summary.json.

Writing stays bounded for large policies: policy.json and policy.dot are linear in the
graph; policy.svg (:mod:`stampc.figures`, a drawing to read, not to search) shows at
most ``SVG_MAX_NODES`` nodes, those nearest the root, and policy.dot at most
``DOT_MAX_NODES``; the rest are collapsed into "+k more" markers and a note says so
(summary.json ``notes``; the command line prints it).
"""

from __future__ import annotations

import csv
import json
from collections import deque
from pathlib import Path
from typing import Any, Mapping

from stampc.ir.grounded import GroundModel, bits
from stampc.figures import DrawnNode, coverage_svg, policy_svg
from stampc.refine.graph import Node, PolicyGraph
from stampc.refine.options import RefineResult
from stampc.refine.outcomes import outcome_labels
from stampc.worlds.base import to_json

POLICY_FORMAT = "stampc-policy"
POLICY_VERSION = 2
#: Most policy nodes shown in policy.svg / policy.dot (breadth-first from the root).
SVG_MAX_NODES = 100
DOT_MAX_NODES = 20_000


def _facts(model: GroundModel, mask: int) -> list[str]:
    return [str(model.facts[b]) for b in bits(mask)]


def _literals(model: GroundModel, mask: int) -> list[dict]:
    return [{"predicate": model.facts[b].predicate, "args": list(model.facts[b].args)}
            for b in bits(mask)]


def policy_json(model: GroundModel, graph: PolicyGraph, result: RefineResult,
                initial_values: Mapping[str, Any], meta: Mapping[str, Any]) -> dict:
    """The refined policy: every reachable node with its abstract state, action and
    arguments, outcomes (probabilities and literal effects), refinement status, learned
    facts, and — for refined nodes — ``sigma``, the concrete values of the symbols the
    node's generators produced. A symbol's value on a path is the nearest ``sigma`` above
    (or at) the node, else ``initial_values``: each concrete value is stored once."""
    nodes = []
    for uid in sorted(graph.reachable()):
        node = graph[uid]
        entry: dict[str, Any] = {
            "id": uid, "depth": node.depth, "state": _facts(model, node.state),
            "leaf": node.leaf, "refined": node.refined,
            **({"proven": node.proven} if node.leaf == "dead_end" else {}),
            "learned": [{"fact": str(model.facts[f]), "value": v} for f, v in node.learned],
        }
        if node.leaf == "goal":
            entry["goal_facts"] = _literals(model, model.goal.pos)
        if node.action is not None:
            action = model.actions[node.action]
            schema = model.lifted.domain.actions[action.schema]
            entry["action"] = action.label
            entry["action_name"] = action.name
            entry["args"] = {p.name: a for p, a in zip(schema.params, action.args)}
            if node.sigma is not None:
                entry["sigma"] = {k: to_json(v) for k, v in sorted(node.sigma.items())}
            names = outcome_labels(action, node.state)
            entry["outcomes"] = [{
                "probability": e.probability, "child": e.child,
                **_outcome_name(names, e.outcome),
                "adds": _literals(model, e.successor.add),
                # only facts true before: a `?` effect deletes collision(o, t2) for every
                # trajectory t2, nearly all already false (a partial cluttered-60 policy
                # was 539 MB, 248 MB of it such deletes)
                "deletes": _literals(model, e.successor.delete & node.state & ~e.successor.add),
            } for e in node.edges]
        nodes.append(entry)
    return {"format": POLICY_FORMAT, "version": POLICY_VERSION, **dict(meta),
            "seed": result.seed, "root": graph.root, "coverage": round(result.coverage, 12),
            "goal_probability": round(result.goal_probability, 12),
            "initial_values": {k: to_json(v) for k, v in sorted(initial_values.items())},
            "nodes": nodes}


def policy_dot(model: GroundModel, graph: PolicyGraph,
               limit: int = DOT_MAX_NODES) -> tuple[str, str | None]:
    """Graphviz DOT of the policy graph (at most ``limit`` nodes, nearest the root first;
    the rest collapsed into "+k more" markers) and a note when it was collapsed."""
    drawn, hidden = bounded_view(graph, limit)
    kept = set(drawn)
    labels: dict[int, str] = {}
    lines = ["digraph policy {", '  node [shape=box, fontname="Helvetica"];']
    for uid in drawn:
        node = graph[uid]
        if node.is_leaf:
            label, style = node.leaf or "leaf", "ellipse"
        else:
            if node.action not in labels:
                labels[node.action] = _escape(model.actions[node.action].label)
            label, style = labels[node.action], "box"
        lines.append(f'  n{uid} [label="{label}", shape={style}, style=filled, '
                     f'fillcolor={_fill(node)}];')
        for e in node.edges:
            if e.child in kept:
                lines.append(f'  n{uid} -> n{e.child} [label="{e.probability:.3g}"];')
        if uid in hidden:
            lines.append(f'  more{uid} [label="+{hidden[uid]} more", shape=plaintext];')
            lines.append(f"  n{uid} -> more{uid} [style=dashed];")
    lines.append("}")
    return "\n".join(lines) + "\n", _collapsed_note("policy.dot", len(drawn), graph)


def _fill(node: Node) -> str:
    """A drawn node's colour: green where the policy is refined (or reached its goal)."""
    return "palegreen" if node.refined or node.leaf == "goal" else "lightgrey"


def _collapsed_note(name: str, drawn: int, graph: PolicyGraph) -> str | None:
    total = len(graph.reachable())
    if total <= drawn:
        return None
    return (f"{name}: shows the {drawn} nodes nearest the root of {total}; the other "
            f"{total - drawn} are collapsed into '+k more' markers (policy.json has them all)")


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


def write_coverage_svg(result: RefineResult, path: Path, title: str = "") -> None:
    events = result.events
    path.write_text(coverage_svg([e.time_s for e in events], [e.coverage for e in events],
                                 [e.goal_probability for e in events], title))


def bounded_view(graph: PolicyGraph, limit: int) -> tuple[list[int], dict[int, int]]:
    """The nodes to draw, breadth-first from the root (at most ``limit``), and for each
    drawn node the number of its children left out."""
    drawn: list[int] = []
    seen = {graph.root}
    queue = deque([graph.root])
    while queue and len(drawn) < limit:
        uid = queue.popleft()
        drawn.append(uid)
        for e in graph[uid].edges:
            if e.child not in seen:
                seen.add(e.child)
                queue.append(e.child)
    kept = set(drawn)
    hidden = {u: n for u in drawn
              if (n := len({e.child for e in graph[u].edges} - kept))}
    return drawn, hidden


def write_policy_svg(model: GroundModel, graph: PolicyGraph, path: Path,
                     limit: int = SVG_MAX_NODES) -> str | None:
    """Draw the policy graph by depth (refined nodes and goals green); above ``limit``
    nodes the drawing is collapsed. Returns a note when it was."""
    drawn, hidden = bounded_view(graph, limit)
    kept = set(drawn)
    nodes: list[DrawnNode] = []
    edges: list[tuple[object, object]] = []
    for uid in drawn:
        node = graph[uid]
        label = (node.leaf or "leaf") if node.is_leaf else model.actions[node.action].name
        nodes.append((uid, node.depth, label, _fill(node)))
        edges += [(uid, e.child) for e in node.edges if e.child in kept]
    for uid, count in hidden.items():
        nodes.append((f"+{uid}", graph[uid].depth + 1, f"+{count} more", "white"))
        edges.append((uid, f"+{uid}"))
    path.write_text(policy_svg(nodes, edges))
    return _collapsed_note(path.name, len(drawn), graph)


def summary_json(result: RefineResult, meta: Mapping[str, Any],
                 notes: list[str] | None = None) -> dict:
    return {**dict(meta), "notes": list(notes or []), "coverage": result.coverage, "goal_probability": result.goal_probability,
            "abstract_goal_probability": result.abstract_goal_probability,
            "wall_time_s": result.wall_time_s, "time_to_coverage": result.time_to_coverage,
            "prg_nodes": result.prg_nodes, "refined_paths": result.refined_paths,
            "refined_nodes": result.refined_nodes, "abstract_solves": result.abstract_solves,
            "goal_mass": result.goal_mass, "dead_end_mass": result.dead_end_mass,
            "unrefined_mass": result.unrefined_mass, "solver_timeouts": result.solver_timeouts,
            "resamples": result.resamples, "recalled_facts": result.recalled_facts,
            "seed": result.seed, "stop_reason": result.stop_reason,
            **({"parallel": result.parallel} if result.parallel is not None else {})}


def _outcome_name(names: tuple[tuple[str, ...], ...], outcome: int) -> dict[str, str]:
    """``{"name": ...}`` for an outcome with ``as NAME`` labels (none past the labelled ones,
    e.g. an edge the engine added itself)."""
    labels = names[outcome] if 0 <= outcome < len(names) else ()
    return {"name": "+".join(labels)} if labels else {}


def write_outputs(out_dir: Path, model: GroundModel, graph: PolicyGraph, result: RefineResult,
                  initial_values: Mapping[str, Any], meta: Mapping[str, Any], *,
                  history: Mapping[str, Any] | None = None) -> list[str]:
    """Write every output; returns notes on what was shortened (also in summary.json)."""
    from stampc.provenance import anchored

    out_dir.mkdir(parents=True, exist_ok=True)
    meta = anchored(meta, out_dir)  # input paths relative to policy.json (issue 13)
    policy = policy_json(model, graph, result, initial_values, meta)
    (out_dir / "policy.json").write_text(json.dumps(policy, indent=1, sort_keys=True))
    dot, dot_note = policy_dot(model, graph)
    (out_dir / "policy.dot").write_text(dot)
    svg_note = write_policy_svg(model, graph, out_dir / "policy.svg")
    notes = [note for note in (dot_note, svg_note) if note]
    write_coverage_csv(result, out_dir / "coverage.csv")
    write_coverage_svg(result, out_dir / "coverage.svg", str(meta.get("problem", "")))
    (out_dir / "summary.json").write_text(json.dumps(summary_json(result, meta, notes), indent=2))
    if history is not None:
        (out_dir / "prg.json").write_text(json.dumps(history, indent=1))
    return notes
