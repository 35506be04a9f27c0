"""``make_heuristic`` over every heuristic name, LM-cut included (``lmcut.py`` builds on
``heuristics.py``, so the dispatch lives above both)."""

from __future__ import annotations

from stampc.ir.grounded import GroundModel
from stampc.solvers import heuristics
from stampc.solvers.heuristics import Heuristic
from stampc.solvers.lmcut import make_lmcut


def make_heuristic(name: str, model: GroundModel, unit_cost: bool,
                   weight: float = 1.0) -> Heuristic:
    """A cached state -> cost-to-go estimate (``inf`` marks a recognised dead end)."""
    if name == "lmcut":
        return make_lmcut(model, unit_cost, weight)
    return heuristics.make_heuristic(name, model, unit_cost, weight)
