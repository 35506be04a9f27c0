"""How closely ``stampc refine --time-limit T`` keeps its limit on hard instances.

Runs ``python -m stampc refine ... --time-limit T -o DIR`` in a subprocess per
(instance, T) and prints the engine's own run time (``summary.json: wall_time_s``, the
clock the limit applies to), its overrun past T, the allowed max(1 s, 2 % of T), and the
process wall time (which adds interpreter start-up, compiling, grounding, opening the
world and writing the outputs).

    python bench/timelimit.py                    # T = 2, 10, 60 on cluttered-25 s2 and keva tower-12
    python bench/timelimit.py --limits 5 --instances cluttered
    python bench/timelimit.py --limits 2 10 --classes   # seed 0 of every bench/paper.py class
    python bench/timelimit.py --classes 'aircraft|keva'  # ... of the classes matching a regex
"""

from __future__ import annotations

import argparse
import re
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def instances(tmp: Path, which: list[str]) -> list[tuple[str, list[Path]]]:
    out = []
    if "cluttered" in which:
        from examples.cluttered_table.scene import write_problem
        p = write_problem(tmp / "c25_s2.stamp", 25, 2, "mid")
        out.append(("cluttered-25 s2", [ROOT / "examples/cluttered_table/domain.stamp", p]))
    if "keva" in which:
        from examples.keva.scene import write_problem as keva
        p = keva(tmp / "tower12.stamp", structure="tower", levels=12, seed=0)
        out.append(("keva tower-12", [ROOT / "examples/keva/domain.stamp", p]))
    return out


def class_instances(tmp: Path, pattern: str = "") -> list[tuple[str, list[Path]]]:
    """Seed 0 of every class of ``bench/paper.py`` (the paper's and the beyond-paper
    ones), made by the same generator call as the benchmark."""
    sys.path.insert(0, str(ROOT / "bench"))
    from paper import make_problem
    from paper_classes import CLASSES

    out = []
    for cls in (c for c in CLASSES if re.search(pattern, c.name)):
        folder = tmp / cls.name
        folder.mkdir(parents=True, exist_ok=True)
        domain, problem = make_problem(cls, 0, folder)
        out.append((cls.name, [domain, problem]))
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--limits", type=float, nargs="*", default=[2.0, 10.0, 60.0])
    parser.add_argument("--instances", nargs="*", default=["cluttered", "keva"])
    parser.add_argument("--classes", nargs="?", const="", default=None, metavar="REGEX",
                        help="instead: seed 0 of every bench/paper.py class (or those matching REGEX)")
    args = parser.parse_args()
    tmp = Path(tempfile.mkdtemp(prefix="timelimit-bench-"))
    cases = (class_instances(tmp, args.classes) if args.classes is not None
             else instances(tmp, args.instances))
    worst = 0.0
    print(f"{'instance':<18} {'T s':>6} {'engine s':>9} {'overrun s':>9} {'allowed s':>9} "
          f"{'process s':>9} {'exit':>4} {'coverage':>8}")
    for name, files in cases:
        for limit in args.limits:
            out = tmp / f"{name.replace(' ', '_')}_{limit:g}"
            start = time.perf_counter()
            proc = subprocess.run([sys.executable, "-m", "stampc", "refine", *map(str, files),
                                   "--world", "pybullet", "--time-limit", str(limit), "--quiet",
                                   "-o", str(out)], capture_output=True, text=True, cwd=ROOT,
                                  timeout=limit + 300)
            wall = time.perf_counter() - start
            summary = json.loads((out / "summary.json").read_text()) if (out / "summary.json").is_file() else {}
            engine = summary.get("wall_time_s", float("nan"))
            worst = max(worst, (engine - limit) / max(1.0, 0.02 * limit))
            print(f"{name:<18} {limit:>6g} {engine:>9.2f} {engine - limit:>9.2f} "
                  f"{max(1.0, 0.02 * limit):>9.2f} {wall:>9.2f} {proc.returncode:>4} "
                  f"{summary.get('coverage', float('nan')):>8.3f}", flush=True)
    print(f"worst overrun: {worst:.2f} of the allowed max(1 s, 2 % of T)"
          f" ({'within' if worst <= 1.0 else 'OVER'} the limit)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
