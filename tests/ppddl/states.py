"""Reachable state spaces of grounded models, by fact names (to compare two groundings
whose fact numbering differs, e.g. a domain with derived predicates and its compiled form)."""

from __future__ import annotations

from stampc.ir.grounded import GroundModel


def reachable_fact_sets(gm: GroundModel, keep: set[str]) -> set[frozenset[str]]:
    """Every state reachable from ``gm.init`` (goal states expanded too), as the set of
    its facts whose predicate is in ``keep``."""
    return {frozenset(str(f) for f in gm.state_facts(s) if f.predicate in keep)
            for s in reachable_states(gm)}


def reachable_states(gm: GroundModel) -> set[int]:
    """Every state reachable from ``gm.init`` through ``GroundAction.outcomes``."""
    seen, stack = {gm.init}, [gm.init]
    while stack:
        s = stack.pop()
        for a in gm.actions:
            if a.precondition.holds(s):
                for o in a.outcomes(s):
                    n = o.apply(s)
                    if n not in seen:
                        seen.add(n)
                        stack.append(n)
    return seen
