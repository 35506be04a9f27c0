"""LM-cut vs h_max: states expanded and time of certified LAO* on IPPC instances.

    python bench/lmcut.py [instance ...]     # relative paths under ../shared/benchmarks/ppddl

Each instance is solved in-process with the reference conventions (unit costs, dead-end
cost 500, certified relative gap 1e-4) under both heuristics; prints expansions, times,
bounds, and the expansion ratio LM-cut / h_max.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

BENCH = (Path(__file__).resolve().parents[2] / "shared" / "benchmarks" / "ppddl").resolve()
DEFAULT = ("ippc2006-tireworld/p03.pddl", "ippc2008-blocksworld/p02.pddl",
           "ippc2006-elevators/p01.pddl", "mdplib-triangle-tireworld-60/p03.pddl",
           "ippc2006-blocksworld/p04.pddl", "ippc2006-pitchcatch/p05.pddl",
           "ippc2008-zenotravel/p01.pddl", "mdplib-ex-blocksworld-fixed/p03.pddl")
TIME_LIMIT = 60.0


def main(argv: list[str]) -> int:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from stampc import api
    from stampc.solvers import SolverOptions
    from stampc.solvers.bounds import solve_bounded

    print(f"{'instance':42} {'h':6} {'expanded':>9} {'solve s':>8} {'lower':>11} "
          f"{'upper':>11} {'cert':>5}")
    for instance in argv or DEFAULT:
        model = api.ground(api.load_model([str(BENCH / instance)]))
        counts = {}
        for h in ("hmax", "lmcut"):
            options = SolverOptions(heuristic=h, unit_cost=True, time_limit=TIME_LIMIT)
            start = time.perf_counter()
            sol, b = solve_bounded(model, options)
            counts[h] = sol.states_expanded
            print(f"{instance[:42]:42} {h:6} {sol.states_expanded:9d} "
                  f"{time.perf_counter() - start:8.2f} {b.lower:11.6f} {b.upper:11.6f} "
                  f"{str(b.certified):>5}", flush=True)
        print(f"{'':42} lmcut/hmax expansions: {counts['lmcut'] / max(1, counts['hmax']):.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
