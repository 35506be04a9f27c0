"""The solver and heuristic names (a leaf module: the CLI lists them without importing
the solvers)."""

ALGORITHMS = ("lao", "lrtdp", "vi", "tvi", "dense")
HEURISTICS = ("zero", "hmax", "lmcut", "hadd", "hff")
#: Whether each heuristic never overestimates the optimal cost (LAO*/LRTDP optimality).
ADMISSIBLE = {"zero": True, "hmax": True, "lmcut": True, "hadd": False, "hff": False}
