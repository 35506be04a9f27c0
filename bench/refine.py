"""Anytime behaviour of the refinement engine on 2-D shelf problems of growing size.

For each size (cans, blockers) and seed, refines examples/shelf2d's domain in the plane2d
world to coverage 1.0 and prints the coverage reached at 10/25/50/100 % of the run's
wall time, plus the run's figures. Usage: ``python bench/refine.py [--seeds 3] [--quick]``.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import stampc  # noqa: E402
from stampc.refine import RefineOptions  # noqa: E402

DOMAIN = ROOT / "examples" / "shelf2d" / "domain.stamp"
SIZES = [(5, 2), (10, 2), (20, 3), (30, 3)]


def problem_text(n: int, blockers: int, seed: int) -> str:
    lines = [f"problem shelf{n}_{seed} for shelf",
             f"object can0..can{n - 1}: can",
             "object table, tray: surface",
             f"object pose_can0..pose_can{n - 1}: pose",
             "init handempty", "     is_tray(tray)"]
    lines += [f"     at(can{i}, pose_can{i})" for i in range(n)]
    lines += ["goal holding(can0)",
              f'scene builder "stampc.worlds.plane2d.scenes:cluttered"'
              f"(n={n}, seed={seed}, blockers={blockers}, shelf=true)"]
    return "\n".join(lines) + "\n"


def coverage_at(events, t: float) -> float:
    reached = [e.coverage for e in events if e.time_s <= t + 1e-12]
    return max(reached) if reached else 0.0


def run_one(n: int, blockers: int, seed: int, time_limit: float) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        problem = Path(tmp) / "problem.stamp"
        problem.write_text(problem_text(n, blockers, seed))
        run = stampc.refine_policy([DOMAIN, problem], world="plane2d",
                                   options=RefineOptions(seed=seed, time_limit=time_limit))
    r = run.result
    total = r.wall_time_s
    return {"n": n, "blockers": blockers, "seed": seed, "coverage": r.coverage,
            "time": total, "solves": r.abstract_solves, "prg": r.prg_nodes,
            "refined": r.refined_nodes,
            "at": [coverage_at(r.events, f * total) for f in (0.10, 0.25, 0.50, 1.0)]}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--time-limit", type=float, default=120.0)
    parser.add_argument("--quick", action="store_true", help="smallest two sizes, one seed")
    args = parser.parse_args()
    sizes = SIZES[:2] if args.quick else SIZES
    seeds = 1 if args.quick else args.seeds
    print(f"{'cans':>4} {'blk':>3} {'seed':>4} {'cov':>6} {'time s':>8} {'solves':>6} "
          f"{'PRG':>4} {'refined':>7}   coverage at 10% / 25% / 50% / 100% of run time")
    rows = []
    for n, blockers in sizes:
        for seed in range(seeds):
            row = run_one(n, blockers, seed, args.time_limit)
            rows.append(row)
            at = " / ".join(f"{c:.3f}" for c in row["at"])
            print(f"{n:>4} {blockers:>3} {seed:>4} {row['coverage']:>6.3f} {row['time']:>8.3f} "
                  f"{row['solves']:>6} {row['prg']:>4} {row['refined']:>7}   {at}", flush=True)
    for n, blockers in sizes:
        sel = [r for r in rows if r["n"] == n]
        med = statistics.median(r["time"] for r in sel)
        mean_at = [statistics.mean(r["at"][i] for r in sel) for i in range(4)]
        print(f"summary n={n}: median time {med:.3f}s, mean coverage at 10/25/50/100 %: "
              + " / ".join(f"{c:.3f}" for c in mean_at))
    return 0


if __name__ == "__main__":
    sys.exit(main())
