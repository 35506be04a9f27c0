"""Policy export: JSON (state -> action label over the policy graph) and Graphviz DOT."""

from __future__ import annotations

import json
from dataclasses import asdict

from stampc.ir.grounded import GroundModel
from stampc.solvers.solution import Solution

POLICY_FORMAT = "stampc-policy"
POLICY_VERSION = 1


def _facts(model: GroundModel, state: int) -> list[str]:
    return [str(f) for f in model.state_facts(state)]


def _status(model: GroundModel, solution: Solution, state: int, t: int,
            action: int | None) -> str:
    if model.is_goal(state):
        return "goal"
    if solution.horizon is not None and t >= solution.horizon:
        return "horizon"
    return "dead_end" if action is None else "act"


def policy_entries(model: GroundModel, solution: Solution) -> list[dict]:
    """One entry per (state, t) of the policy graph reachable from ``solution.init``."""
    entries = []
    for state, t in solution.policy_nodes():
        action = solution.action(state, t)
        entry = {"state": _facts(model, state),
                 "action": None if action is None else model.actions[action].label,
                 "status": _status(model, solution, state, t, action),
                 "value": solution.value(state, t)}
        if solution.horizon is not None:
            entry["t"] = t
        entries.append(entry)
    return entries


def _relevance_reduced(solution: Solution) -> int | None:
    if solution.search is None or solution.table is not None:
        return None
    relevance = solution.search.space.cache.relevance
    return None if relevance is None else relevance.reduced


def summary(solution: Solution) -> dict:
    return {"expected_cost": solution.expected_cost,
            "goal_probability": solution.goal_probability,
            "states_expanded": solution.states_expanded,
            "states_generated": solution.states_generated,
            "solve_time_s": solution.solve_time_s,
            "converged": solution.converged,
            "horizon": solution.horizon,
            # the solver that ran: "dense" when solve_bounded chose it over LAO*
            "method": "dense" if solution.table is not None else solution.options.algorithm,
            # interchangeable objects were found and states merged per orbit (symmetry.py)
            "orbits": bool(solution.search is not None and solution.table is None
                           and solution.search.space.cache.canonical is not None),
            # next states that lost irrelevant facts (relevance.py), None when off
            "relevance_reduced": _relevance_reduced(solution),
            "options": {k: v for k, v in asdict(solution.options).items() if k != "forbidden"}}


def policy_json(model: GroundModel, solution: Solution) -> dict:
    return {"format": POLICY_FORMAT, "version": POLICY_VERSION, **summary(solution),
            "init": _facts(model, solution.init),
            "policy": policy_entries(model, solution)}


def write_policy_json(path: str, model: GroundModel, solution: Solution) -> None:
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(policy_json(model, solution), fh, indent=1)
        fh.write("\n")


def _escape(text: str) -> str:
    return text.replace("\\", "\\\\").replace('"', '\\"')


def _quote(text: str) -> str:
    return '"' + _escape(text) + '"'


#: Most (state, t) nodes written to a policy DOT file (in depth-first order from the
#: initial state, so what is shown stays connected); the rest are counted in a note.
DOT_MAX_NODES = 20_000


def policy_dot(model: GroundModel, solution: Solution, max_facts: int = 12,
               limit: int = DOT_MAX_NODES) -> str:
    """The policy graph: one node per (state, t), edges labelled with action and outcome
    probability; goal nodes double-circled, dead ends / horizon nodes boxed. Above
    ``limit`` nodes the rest is left out and a ``more`` node says how many."""
    nodes = solution.policy_nodes()
    ids = {key: f"n{i}" for i, key in enumerate(nodes[:limit])}
    lines = ["digraph policy {", "  rankdir=LR;", '  node [fontsize=10, shape=ellipse];']
    for (state, t), nid in ids.items():
        action = solution.action(state, t)
        status = _status(model, solution, state, t, action)
        facts = _facts(model, state)
        shown = facts[:max_facts] + (["..."] if len(facts) > max_facts else [])
        shown.append(f"V={solution.value(state, t):.4g}"
                     + (f" t={t}" if solution.horizon is not None else ""))
        label = "\\n".join(_escape(line) for line in shown)  # DOT line breaks
        shape = {"goal": "doublecircle", "dead_end": "box", "horizon": "box"}.get(status)
        attrs = f'label="{label}"' + (f", shape={shape}" if shape else "")
        lines.append(f"  {nid} [{attrs}];")
        if status != "act":
            continue
        probs: dict[tuple[int, int], float] = {}
        for o in model.actions[action].outcomes(state):
            key = (o.apply(state), t + 1 if solution.horizon is not None else 0)
            probs[key] = probs.get(key, 0.0) + float(o.probability)
        for key, p in probs.items():
            target = ids.get(key)
            if target is None:
                continue  # only when the solve stopped early (time limit)
            text = f"{model.actions[action].label} p={p:.3g}"
            lines.append(f"  {nid} -> {target} [label={_quote(text)}];")
    if len(nodes) > limit:
        lines.append(f'  more [label="+{len(nodes) - limit} more states not shown", shape=plaintext];')
    lines.append("}")
    return "\n".join(lines) + "\n"


def write_policy_dot(path: str, model: GroundModel, solution: Solution,
                     limit: int = DOT_MAX_NODES) -> str | None:
    """Write the policy DOT; returns a note when the graph was cut at ``limit`` nodes."""
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(policy_dot(model, solution, limit=limit))
    total = len(solution.policy_nodes())
    if total <= limit:
        return None
    return (f"{path}: shows the first {limit} of {total} policy states (depth-first from "
            f"the initial state); the rest are left out to keep writing bounded")
