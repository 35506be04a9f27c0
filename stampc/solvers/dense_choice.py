"""When ``solve_bounded`` picks the dense solver over LAO* (numpy-free: the check runs on
every certified solve, and ``stampc solve`` does not otherwise load numpy)."""

from __future__ import annotations

from stampc.ir.grounded import GEffect, GroundModel
from stampc.solvers.solution import SolverOptions

#: Automatic selection: some action has at least this many independent probabilistic
#: blocks, i.e. up to 2^blocks joint outcomes for every expansion of a search.
AUTO_MIN_BLOCKS = 10


def effect_blocks(effect: GEffect) -> int:
    """Probabilistic blocks in ``effect``, nested ones included."""
    return (len(effect.blocks) + sum(effect_blocks(s) for _, s in effect.whens)
            + sum(effect_blocks(s) for b in effect.blocks for _, s in b.outcomes))


def explosive_blocks(model: GroundModel) -> int:
    """The largest number of probabilistic blocks in one action."""
    return max((effect_blocks(a.effect) for a in model.actions), default=0)


def auto_dense(model: GroundModel, options: SolverOptions) -> bool:
    """Should a certified LAO* solve try the dense solver (``dense_api.py``) first?"""
    return (options.algorithm == "lao" and options.horizon is None and model.horizon is None
            and not options.forbidden and explosive_blocks(model) >= AUTO_MIN_BLOCKS)
