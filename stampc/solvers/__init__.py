"""SSP solvers over the grounded IR: LAO*, LRTDP, VI; heuristics; policy trees.

See docs/solvers.md for the algorithms, options and cost conventions. Names are
resolved lazily (module ``__getattr__``) so that listing ``ALGORITHMS`` for the command
line does not import the solvers and the grounded IR.
"""

from __future__ import annotations

from importlib import import_module

_LAZY = {
    "ADMISSIBLE": "names", "ALGORITHMS": "names", "HEURISTICS": "names",
    "check_options": "api", "solve": "api", "make_heuristic": "heuristics",
    "SimulationResult": "simulation", "simulate": "simulation",
    "Solution": "solution", "SolverOptions": "solution", "SuccessorCache": "successors",
    "TreeEdge": "tree", "TreeNode": "tree", "count_leaves": "tree", "iter_paths": "tree",
    "policy_tree": "tree",
}

__all__ = sorted(_LAZY)


def __getattr__(name: str):
    if name in _LAZY:
        value = getattr(import_module(f"stampc.solvers.{_LAZY[name]}"), name)
        globals()[name] = value  # resolved once
        return value
    raise AttributeError(f"module 'stampc.solvers' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
