"""Execution you can trust, per example: refine each example's policy, then run N seeded
executions (truth = the model, PyBullet physics on) and print the table of docs/execute.md:
success rate with its 95 % Wilson interval against coverage × goal probability, runs
that reached an unrefined branch, collisions at 10× resolution, goal-check failures.

    python bench/execute.py --runs 1000          # the issue's N
    python bench/execute.py --runs 100 --only domino shelf2d
    python bench/execute.py --runs 1000 --only keva --policies /tmp/policies  # refine once
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from stampc.cli import main as stampc  # noqa: E402
from stampc.execute.session import execute_file  # noqa: E402

EX = ROOT / "examples"
#: name -> (world, domain, problem)
EXAMPLES = {
    "cluttered_table": ("pybullet", EX / "cluttered_table/domain.stamp",
                        EX / "cluttered_table/problem.stamp"),
    "cluttered_table_fixed": ("pybullet", EX / "cluttered_table/domain_fixed.stamp",
                              EX / "cluttered_table/problem_fixed.stamp"),
    "domino": ("pybullet", EX / "domino/domain.stamp", EX / "domino/problem.stamp"),
    "keva": ("pybullet", EX / "keva/domain.stamp", EX / "keva/problem.stamp"),
    "aircraft_inspection": ("pybullet", EX / "aircraft_inspection/domain.stamp",
                            EX / "aircraft_inspection/problem.stamp"),
    "shelf2d": ("plane2d", EX / "shelf2d/domain.stamp", EX / "shelf2d/problem.stamp"),
    "cluttered_table_2d": ("plane2d", EX / "cluttered_table/domain.stamp",
                           EX / "cluttered_table/problem2d.stamp"),
    "cluttered_table_2d_fixed": ("plane2d", EX / "cluttered_table/domain_fixed.stamp",
                                 EX / "cluttered_table/problem2d_fixed.stamp"),
    "slip2d": ("plane2d", EX / "slip2d/domain.stamp", EX / "slip2d/problem.stamp"),
}


def row(name: str, runs: int, seed: int, out: Path, memo: bool = True) -> str:
    world, domain, problem = EXAMPLES[name]
    policy = out / name
    code = 0
    if not (policy / "policy.json").is_file():  # refined once, reused by later calls
        code = stampc(["refine", str(domain), str(problem), "--world", world, "--seed", "0",
                       "--time-limit", "300", "--quiet", "-o", str(policy)])
    if not (policy / "policy.json").is_file():
        return f"| {name} | refine failed (exit {code}) | | | | | | | | | |"
    memos: list = []
    start = time.perf_counter()
    r = execute_file(policy / "policy.json", runs=runs, seed=seed, memo=memo,
                     on_memo=memos.append)
    elapsed = time.perf_counter() - start
    d = r.to_json()
    lo, hi = d["success_ci95"]
    steps = f"{memos[0].misses} / {memos[0].hits}" if memos else "all / 0"
    return (f"| {name} | {world} | {runs} | {d['success_rate']:.3f} [{lo:.3f}, {hi:.3f}] | "
            f"{d['coverage_x_goal_probability']:.3f} | {d['predicted_success']:.3f} | "
            f"{d['unrefined']} | {d['collisions']} | {d['goal_check_failures']} | "
            f"{steps} | {elapsed:.1f} | {1000 * elapsed / runs:.1f} |")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--runs", type=int, default=200)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--only", nargs="*", choices=sorted(EXAMPLES))
    parser.add_argument("--policies", type=Path, default=None,
                        help="keep the refined policies here (reused when present); "
                             "default: a temporary folder")
    parser.add_argument("--no-memo", action="store_true",
                        help="simulate every step of every run (see stampc/execute/memo.py)")
    args = parser.parse_args()
    print("| example | world | N | success rate [95% Wilson] | coverage × goal prob. | "
          "predicted | unrefined | collisions (10×) | goal-check failures | "
          "steps simulated / replayed | execute s | ms/run |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        out = args.policies or Path(tmp)
        for name in args.only or EXAMPLES:
            print(row(name, args.runs, args.seed, out, not args.no_memo), flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
