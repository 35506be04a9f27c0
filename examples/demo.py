"""The flagship demo: a mobile Panda picks a target can off a cluttered table (PyBullet +
OMPL): the paper's scene, cans at random, the robot choosing among base poses around it.

    python examples/demo.py                 # 15 cans, seed 0, outputs in ./out/demo
    python examples/demo.py --n 20 --seed 3 --variant high --out /tmp/demo

Outputs go to ``--out`` (default ``out/demo``) relative to the current directory, wherever
the demo is run from; it prints that folder first and every output at the end.

The steps, each a `stampc` command (run with the repository root as working directory,
so the stamp files read as in the README):
1. compile the domain and problem to the JSON IR and PPDDL (`stampc compile`);
2. refine the abstract policy with concrete grasps and motions, anytime, showing a live
   coverage bar on a terminal (`stampc refine --world pybullet`);
3. replay the refined policy 20 times with sampled outcomes (crushed cans included) and
   render the first run to PNG frames and a GIF (`stampc execute --render`);
4. a crushed can discarded into the tray: the paper's scene rarely puts a can in the
   target's way (the default one never does, so nothing is ever discarded there), so the
   fixed-base scene (`domain_fixed.stamp`, `problem_fixed.stamp`: a delicate can in front
   of the target, a tray beside the table) is refined and the first seed (from 1) whose
   run crushes and discards a can is rendered — the demo says which seed it took.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "cluttered_table"


def _step(title: str, args: list[str]) -> int:
    print(f"\n== {title}\n$ stampc {' '.join(args)}", flush=True)
    start = time.perf_counter()
    code = subprocess.call([sys.executable, "-m", "stampc", *args], cwd=ROOT)
    print(f"-- {time.perf_counter() - start:.1f} s, exit {code}", flush=True)
    return code


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="stampc flagship demo: the cluttered table")
    parser.add_argument("--n", type=int, default=15, help="number of cans (default 15)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--variant", choices=("low", "mid", "high"), default="mid",
                        help="crush probability of delicate cans: 0.1 / 0.5 / 0.9")
    parser.add_argument("--time-limit", type=float, default=180.0)
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--out", default="out/demo",
                        help="output folder, relative to the current directory (default out/demo)")
    args = parser.parse_args(argv)

    sys.path.insert(0, str(ROOT))
    from examples.cluttered_table.scene import write_problem

    out = Path(args.out).resolve()  # before the steps run with the repository as cwd
    print(f"outputs go to {out}", flush=True)
    default = (args.n, args.seed, args.variant) == (15, 0, "mid")
    problem = (EXAMPLE / "problem.stamp" if default else
               write_problem(out / f"problem_n{args.n}_s{args.seed}_{args.variant}.stamp",
                             args.n, args.seed, args.variant))
    domain = EXAMPLE / "domain.stamp"
    files = [str(domain.relative_to(ROOT)), str(problem)]
    policy_dir, render_dir = out / "policy", out / "render"

    if _step("1. compile (IR + PPDDL)", ["compile", *files, "-o", str(out / "ir")]) != 0:
        return 1
    _step("1b. compile to PPDDL", ["compile", *files, "--target", "ppddl", "-o", str(out / "ppddl")])
    code = _step("2. refine on PyBullet + OMPL (anytime; live coverage bar)",
                 ["refine", *files, "--world", "pybullet", "--seed", str(args.seed),
                  "--time-limit", str(args.time_limit), "-o", str(policy_dir)])
    if not (policy_dir / "policy.json").is_file():
        print("refinement produced no policy", file=sys.stderr)
        return 1
    if code != 0:
        print("(coverage below 1.0: replaying the partial policy anyway)")
    code = _step("3. execute the refined policy, rendering the first run",
                 ["execute", str(policy_dir / "policy.json"), "--runs", str(args.runs),
                  "--seed", "1", "--render", str(render_dir)])
    discard = _discard_run(out / "tray", args.time_limit)
    print(f"""
outputs:
  problem       {problem}
  IR / PPDDL    {out / 'ir'}, {out / 'ppddl'}
  policy        {policy_dir / 'policy.json'} (+ policy.svg, coverage.svg, summary.json)
  animation     {render_dir / 'run.gif'} (frames: {render_dir}/frame_*.png)
  discard       {discard}""")
    return code


def _discard_run(out: Path, time_limit: float, seeds: range = range(1, 41)) -> str:
    """Step 4: refine the fixed-base scene with its tray, find the first seed whose run
    crushes a can and discards it (one run per seed, the world sampling outcomes), and
    render that run. Returns where the animation is (or why there is none)."""
    files = [str(EXAMPLE.relative_to(ROOT) / n) for n in ("domain_fixed.stamp",
                                                           "problem_fixed.stamp")]
    policy = out / "policy" / "policy.json"
    _step("4. a crushed can discarded into the tray: refine the fixed-base scene",
          ["refine", *files, "--world", "pybullet", "--seed", "0", "--quiet",
           "--time-limit", str(time_limit), "-o", str(policy.parent)])
    if not policy.is_file():
        return "none (the fixed-base scene was not refined)"
    for seed in seeds:
        report = subprocess.run([sys.executable, "-m", "stampc", "execute", str(policy),
                                 "--runs", "1", "--seed", str(seed), "--format", "json"],
                                cwd=ROOT, capture_output=True, text=True)
        if report.stdout and "discard" in json.loads(report.stdout).get("outcomes", {}):
            break
    else:
        return f"none (no run with seeds {seeds.start}..{seeds.stop - 1} crushed a can)"
    print(f"\nseed {seed} is the first seed from {seeds.start} whose run crushes a can and "
          "discards it into the tray; rendering that run", flush=True)
    _step("4b. execute that run, rendering it",
          ["execute", str(policy), "--runs", "1", "--seed", str(seed),
           "--render", str(out / "render")])
    return f"{out / 'render' / 'run.gif'} (seed {seed}: a crushed can lands in the tray)"


if __name__ == "__main__":
    raise SystemExit(main())
