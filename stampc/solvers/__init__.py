"""SSP solvers over the grounded IR: LAO*, LRTDP, VI; heuristics; policy trees.

See docs/solvers.md for the algorithms, options and cost conventions.
"""

from stampc.solvers.api import check_options, solve
from stampc.solvers.heuristics import ADMISSIBLE, HEURISTICS, make_heuristic
from stampc.solvers.simulate import SimulationResult, simulate
from stampc.solvers.solution import ALGORITHMS, Solution, SolverOptions
from stampc.solvers.successors import SuccessorCache
from stampc.solvers.tree import TreeEdge, TreeNode, count_leaves, iter_paths, policy_tree

__all__ = [
    "ADMISSIBLE", "ALGORITHMS", "HEURISTICS", "SimulationResult", "Solution", "SolverOptions",
    "SuccessorCache", "TreeEdge", "TreeNode", "check_options", "count_leaves", "iter_paths",
    "make_heuristic", "policy_tree", "simulate", "solve",
]
