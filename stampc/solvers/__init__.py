"""SSP solvers over the grounded IR: LAO*, LRTDP, VI; heuristics; policy trees.

See docs/solvers.md for the algorithms, options and cost conventions. Names are
resolved lazily (module ``__getattr__``) so that listing ``ALGORITHMS`` for the command
line does not import the solvers and the grounded IR.
"""

from __future__ import annotations

from stampc.lazy import lazy_exports

_LAZY = {name: f"stampc.solvers.{module}" for name, module in {
    "ADMISSIBLE": "names", "ALGORITHMS": "names", "HEURISTICS": "names",
    "check_options": "api", "solve": "api", "make_heuristic": "heuristic_choice",
    "SimulationResult": "simulation", "simulate": "simulation",
    "Solution": "solution", "SolverOptions": "solution", "SuccessorCache": "successors",
    "TreeEdge": "tree", "TreeNode": "tree", "count_leaves": "tree", "iter_paths": "tree",
    "policy_tree": "tree",
}.items()}

__all__ = sorted(_LAZY)
__getattr__, __dir__ = lazy_exports(globals(), _LAZY)
