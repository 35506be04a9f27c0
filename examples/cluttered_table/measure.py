"""Refine time to coverage 1.0 on the PyBullet cluttered table, n cans × seeds.

    python -m examples.cluttered_table.measure --n 15 20 25 --seeds 0 1 2 --variant mid

Each instance runs in its own process (``stampc refine --quiet``; one PyBullet client
each) with a wall-clock limit; prints a Markdown table and writes ``results.json``.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from examples.cluttered_table.scene import VARIANTS, write_problem

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]


def run_one(n: int, seed: int, variant: str, time_limit: float, out: Path) -> dict:
    problem = write_problem(out / f"problem_n{n}_s{seed}_{variant}.stamp", n, seed, variant)
    result_dir = out / f"n{n}_s{seed}_{variant}"
    cmd = [sys.executable, "-m", "stampc", "refine", str(HERE / "domain.stamp"), str(problem),
           "--world", "pybullet", "--quiet", "--seed", str(seed),
           "--time-limit", str(time_limit), "-o", str(result_dir)]
    start = time.perf_counter()
    row: dict = {"n": n, "seed": seed, "variant": variant}
    try:
        proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True,
                              timeout=time_limit + 120)
    except subprocess.TimeoutExpired:  # the run ignored its --time-limit (killed)
        row.update(process_s=round(time.perf_counter() - start, 2), exit=None,
                   error=f"killed after {time_limit + 120:.0f} s")
        return row
    row.update(process_s=round(time.perf_counter() - start, 2), exit=proc.returncode)
    summary = result_dir / "summary.json"
    if summary.is_file():
        data = json.loads(summary.read_text(encoding="utf-8"))
        res = data.get("result", data)
        row.update(coverage=res.get("coverage"), goal_probability=res.get("goal_probability"),
                   refine_s=res.get("wall_time_s"),
                   to_full=(res.get("time_to_coverage") or {}).get("1.0"),
                   prg_nodes=res.get("prg_nodes"), refined_nodes=res.get("refined_nodes"))
    else:
        row["error"] = (proc.stderr or proc.stdout)[-400:]
    return row


def table(rows: list[dict]) -> str:
    head = ("| n | seed | variant | coverage | goal prob. | time to 1.0 (s) | refined nodes "
            "| PRG nodes | process (s) |\n|---|---|---|---|---|---|---|---|---|")

    def fmt(v: object, digits: int = 3) -> str:
        return "–" if v is None else f"{v:.{digits}f}" if isinstance(v, float) else str(v)

    lines = [head] + [
        f"| {r['n']} | {r['seed']} | {r['variant']} | {fmt(r.get('coverage'))} | "
        f"{fmt(r.get('goal_probability'))} | {fmt(r.get('to_full'), 2)} | "
        f"{fmt(r.get('refined_nodes'))} | {fmt(r.get('prg_nodes'))} | {fmt(r['process_s'], 1)} |"
        for r in rows]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, nargs="+", default=[15, 20, 25])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--variant", choices=sorted(VARIANTS), default="mid")
    parser.add_argument("--time-limit", type=float, default=300.0)
    parser.add_argument("-o", "--out", default=None, help="output folder (default: a temp dir)")
    args = parser.parse_args(argv)
    out = Path(args.out or tempfile.mkdtemp(prefix="cluttered_measure_"))
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for n in args.n:
        for seed in args.seeds:
            rows.append(run_one(n, seed, args.variant, args.time_limit, out))
            print(json.dumps(rows[-1]), flush=True)
    (out / "results.json").write_text(json.dumps(rows, indent=2), encoding="utf-8")
    print(table(rows))
    print(f"outputs in {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
