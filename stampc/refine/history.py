"""The plan refinement graph's history as JSON (prg.json beside policy.json).

Each PRG node is a policy; each PRG edge one revision of it: an UpdateAbstraction (true
facts written at a policy node, the policy replanned below it) or a re-sample of an
ancestor's generator values. ``stampc view`` shows this as the "PRG history": which
updates happened, at which policy node, and when. An update's ``facts`` were learned
at its node; its ``recalled`` facts (when any) were learned elsewhere and re-evaluated
there (stampc/refine/recall.py). The time of a revision is that of the
first progress event that counted its PRG node (events carry the PRG size).
"""

from __future__ import annotations

from typing import Any, Sequence

import networkx as nx

from stampc.refine.options import ProgressEvent

HISTORY_FORMAT = "stampc-prg"
HISTORY_VERSION = 1


def prg_history(prg: nx.DiGraph, events: Sequence[ProgressEvent], best: int) -> dict[str, Any]:
    """``prg.json``: PRG nodes (parent, failed), revisions (edges, in creation order, with
    the policy node they touched and the facts learned) and every progress event."""
    created = _creation_times(events)
    revisions = []
    for u, v, data in sorted(prg.edges(data=True), key=lambda e: e[1]):
        revisions.append({
            "from": u, "to": v, "kind": data.get("kind", "update"), "node": data.get("node"),
            "facts": list(data.get("failed_preconditions", [])),
            **({"recalled": list(data["recalled"])} if data.get("recalled") else {}),
            "concretization": list(data.get("concretization", [])),
            **({"failed_node": data["failed_node"]} if "failed_node" in data else {}),
            "failed": bool(prg.nodes[v].get("failed")), "time_s": created.get(v)})
    return {
        "format": HISTORY_FORMAT, "version": HISTORY_VERSION, "best": best,
        "nodes": [{"id": v, "parent": prg.nodes[v].get("parent"),
                   "failed": bool(prg.nodes[v].get("failed"))} for v in sorted(prg.nodes)],
        "revisions": revisions,
        "events": [{"time_s": round(e.time_s, 6), "kind": e.kind, "detail": e.detail,
                    "coverage": e.coverage, "goal_probability": e.goal_probability,
                    "dead_end_mass": e.dead_end_mass, "prg_nodes": e.prg_nodes}
                   for e in events],
    }


def _creation_times(events: Sequence[ProgressEvent]) -> dict[int, float]:
    """PRG node id -> time of the first event whose PRG size included it."""
    times: dict[int, float] = {}
    for e in events:
        for v in range(len(times), e.prg_nodes):
            times[v] = round(e.time_s, 6)
    return times
