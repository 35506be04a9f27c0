"""Start-up time of the command line: whole processes, as a user sees them.

Runs each command N times as a subprocess and prints the median wall time and the
median CPU time (user + system of the child; on a loaded machine the CPU time is the
fairer figure, the wall time includes waiting for a core). One untimed warm-up run per
command first writes the bytecode and the grammar cache, as any first use does;
``--cold-cache`` gives every run an empty grammar cache instead.

    python bench/startup.py                 # python -m stampc from this checkout
    python bench/startup.py --runs 20
    python bench/startup.py --script stampc # an installed console script
    python bench/startup.py --cold-cache

Target (issue 10): --help, check and solve on a tiny instance in <= 0.3 s each.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
TIRE = REPO.parent / "shared" / "benchmarks" / "ppddl" / "ippc2006-tireworld" / "p01.pddl"
COMMANDS = {
    "python -c pass (floor)": None,
    "stampc --help": ["--help"],
    "stampc check domino": ["check", "examples/domino/domain.stamp", "examples/domino/problem.stamp"],
    "stampc fmt domino": ["fmt", "examples/domino/domain.stamp"],
    "stampc solve tireworld p01": ["solve", str(TIRE), "--unit-cost"],
}
TARGET_S = 0.3


def child_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_once(argv: list[str], env: dict[str, str]) -> tuple[float, float]:
    cpu0, wall0 = child_cpu(), time.perf_counter()
    done = subprocess.run(argv, cwd=REPO, env=env, stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True)
    wall, cpu = time.perf_counter() - wall0, child_cpu() - cpu0
    if done.returncode not in (0, 1):  # 1: the domain has warnings/errors, still a run
        raise SystemExit(f"{' '.join(argv)} exited {done.returncode}: {done.stderr[-400:]}")
    return wall, cpu


def measure(base: list[str], args: list[str] | None, runs: int, env: dict[str, str],
            cold: bool) -> tuple[float, float]:
    argv = [sys.executable, "-c", "pass"] if args is None else base + args
    run_once(argv, env)  # warm-up: bytecode, grammar cache
    walls, cpus = [], []
    for _ in range(runs):
        run_env = env
        scratch = None
        if cold:
            scratch = tempfile.mkdtemp(prefix="stampc-cache-")
            run_env = {**env, "STAMPC_CACHE_DIR": scratch}
        try:
            wall, cpu = run_once(argv, run_env)
        finally:
            if scratch:
                shutil.rmtree(scratch, ignore_errors=True)
        walls.append(wall)
        cpus.append(cpu)
    return statistics.median(walls), statistics.median(cpus)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=9)
    parser.add_argument("--script", help="console script to time instead of python -m stampc")
    parser.add_argument("--cold-cache", action="store_true",
                        help="an empty grammar cache for every run (first use)")
    args = parser.parse_args()
    if args.runs < 1:
        parser.error("--runs must be at least 1")
    base = [shutil.which(args.script) or args.script] if args.script else [sys.executable, "-m", "stampc"]
    # A user's installed package has its bytecode; this machine's default may not write it.
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"{' '.join(base)}: median of {args.runs} runs, "
          f"{'cold' if args.cold_cache else 'warm'} grammar cache, load average {load:.1f} "
          f"on {os.cpu_count()} cores")
    print(f"{'command':<30} {'wall s':>8} {'cpu s':>8}  target {TARGET_S} s")
    for name, cmd in COMMANDS.items():
        if cmd and "solve" in cmd and not TIRE.is_file():
            print(f"{name:<30} {'(benchmark folder missing)':>18}")
            continue
        wall, cpu = measure(base, cmd, args.runs, env, args.cold_cache)
        verdict = ("" if cmd is None else "ok" if wall <= TARGET_S
                   else "cpu ok, wall over (waiting for a core)" if cpu <= TARGET_S else "over")
        print(f"{name:<30} {wall:8.3f} {cpu:8.3f}  {verdict}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
