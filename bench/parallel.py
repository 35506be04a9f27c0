"""Parallel refinement: speed-up of ``--workers N`` and the serial/parallel time split.

    python bench/parallel.py                          # cluttered-25 and keva-tower-12, 3 seeds
    python bench/parallel.py --runs 5 --workers 2 4 --classes keva-tower-12

For each instance (the paper benchmark's generators, ``bench/paper_classes.py``):

1. **split** — refine it serially *in this process* with the concretizer's two entry
   points timed (``Concretizer.concretize``: generators + ``?`` evaluators;
   ``Concretizer.execute``: executors). Their share ``p`` of the engine's time is what
   ``--workers`` moves to workers; the rest (path selection, abstract re-solves, coverage
   bookkeeping) stays in the engine. Amdahl's bound: ``S(N) = 1 / ((1 - p) + p / N)``.
   The split is a ratio of times measured in one process, so it hardly depends on load.
2. **wall** — ``stampc refine ... --workers N`` as a subprocess for each N (1 first):
   the whole process time and the engine's time (summary.json), coverage, and the
   parallel counters (batches, stale replies discarded, time waiting for workers, the
   batches' critical path: their tasks' summed time over it is the batch parallelism,
   the bound the batch structure sets however idle the cores are).

The load average is printed before and after: the machine may be shared, and the wall
times are only meaningful next to it. A parallel run may follow a different search (the
batches differ from the serial order), so its time reflects both the parallelism and the
search it takes; the split above is the clean measure of the parallelisable share.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
for entry in (str(REPO), str(REPO / "bench")):
    if entry not in sys.path:
        sys.path.insert(0, entry)

from paper import SOLVED_COVERAGE, make_problem  # noqa: E402
from paper_classes import CLASSES  # noqa: E402


def serial_split(domain: Path, problem: Path, seed: int, limit: float) -> dict:
    """Engine time and the time inside the concretizer's entry points (one process)."""
    from stampc import api
    from stampc.refine import RefineOptions
    from stampc.refine.concretize import Concretizer
    from stampc.solvers import SolverOptions

    spent = {"concretize": 0.0, "execute": 0.0}
    originals = {name: getattr(Concretizer, name) for name in spent}

    def timed(name):
        def call(self, *a, **k):  # type: ignore[no-untyped-def]
            t0 = time.perf_counter()
            try:
                return originals[name](self, *a, **k)
            finally:
                spent[name] += time.perf_counter() - t0
        return call

    for name in spent:
        setattr(Concretizer, name, timed(name))
    try:
        options = RefineOptions(seed=seed, time_limit=limit, target_coverage=SOLVED_COVERAGE,
                                solver=SolverOptions(heuristic="hadd", seed=seed))
        result = api.refine_policy([domain, problem], world="pybullet", options=options).result
    finally:
        for name, fn in originals.items():
            setattr(Concretizer, name, fn)
    engine = result.wall_time_s
    p = (spent["concretize"] + spent["execute"]) / engine if engine > 0 else 0.0
    return {"engine_s": engine, "coverage": result.coverage, **spent, "p": p}


def wall_run(domain: Path, problem: Path, seed: int, workers: int, limit: float,
             out: Path) -> dict:
    """``stampc refine --workers N`` in a subprocess: process time, engine time, counters."""
    out.mkdir(parents=True, exist_ok=True)
    (out / "summary.json").unlink(missing_ok=True)
    cmd = [sys.executable, "-m", "stampc", "refine", str(domain), str(problem), "--world",
           "pybullet", "--time-limit", str(limit), "--target-coverage", str(SOLVED_COVERAGE),
           "--seed", str(seed), "--quiet", "--workers", str(workers), "-o", str(out)]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, cwd=REPO, env=env, capture_output=True, text=True)
    process_s = time.perf_counter() - t0
    if not (out / "summary.json").is_file():
        return {"workers": workers, "error": proc.stderr.strip()[-300:], "process_s": process_s}
    summary = json.loads((out / "summary.json").read_text())
    return {"workers": workers, "process_s": process_s, "engine_s": summary["wall_time_s"],
            "coverage": summary["coverage"], "parallel": summary.get("parallel")}


def amdahl(p: float, n: int) -> float:
    return 1.0 / ((1.0 - p) + p / n)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="speed-up of stampc refine --workers N")
    ap.add_argument("--classes", nargs="+", default=["cluttered-25", "keva-tower-12"])
    ap.add_argument("--runs", type=int, default=3, help="seeds per class (default 3)")
    ap.add_argument("--seed-base", type=int, default=0)
    ap.add_argument("--workers", type=int, nargs="+", default=[2])
    ap.add_argument("--time-limit", type=float, default=300.0)
    ap.add_argument("--out", default=str(REPO / "bench" / "out" / "parallel"))
    args = ap.parse_args(argv)
    out = Path(args.out).resolve()
    by_name = {c.name: c for c in CLASSES}
    print(f"load average before: {os.getloadavg()}  ({os.cpu_count()} cores)")
    rows = []
    for name in args.classes:
        for i in range(args.runs):
            seed = args.seed_base + i
            folder = out / name / f"seed{seed}"
            folder.mkdir(parents=True, exist_ok=True)
            domain, problem = make_problem(by_name[name], seed, folder)
            split = serial_split(domain, problem, seed, args.time_limit)
            walls = [wall_run(domain, problem, seed, n, args.time_limit, folder / f"w{n}")
                     for n in [1, *args.workers]]
            rows.append({"class": name, "seed": seed, "split": split, "wall": walls,
                         "load": os.getloadavg()})
            print(f"{name} seed {seed}: serial split p = {split['p']:.3f} (generators "
                  f"{split['concretize']:.2f} s + executors {split['execute']:.2f} s of engine "
                  f"{split['engine_s']:.2f} s); load {rows[-1]['load'][0]:.2f}", flush=True)
            for w in walls:
                print(f"    --workers {w['workers']}: " + (
                    f"process {w['process_s']:.2f} s engine {w['engine_s']:.2f} s coverage "
                    f"{w['coverage']:.4f} {json.dumps(w['parallel']) if w['parallel'] else ''}"
                    if "error" not in w else f"error: {w['error']}"), flush=True)
    print(f"load average after: {os.getloadavg()}")
    _summarise(rows, args.workers)
    (out / "parallel.json").write_text(json.dumps(rows, indent=1))
    print(f"wrote {out / 'parallel.json'}")
    return 0


def _summarise(rows: list[dict], workers: list[int]) -> None:
    for name in dict.fromkeys(r["class"] for r in rows):
        mine = [r for r in rows if r["class"] == name]
        p = statistics.median(r["split"]["p"] for r in mine)
        bounds = "  ".join(f"S({n}) ≤ {amdahl(p, n):.2f}" for n in (2, 4, 8, 16))
        print(f"\n{name}: median parallelisable share p = {p:.3f}; Amdahl: {bounds}; "
              f"S(∞) ≤ {1 / (1 - p) if p < 1 else float('inf'):.2f}")
        for n in workers:
            for key in ("engine_s", "process_s"):
                ratios = [_ratio(r, n, key) for r in mine]
                ratios = [x for x in ratios if x is not None]
                if ratios:
                    print(f"  --workers {n}: median {key} speed-up {statistics.median(ratios):.2f}× "
                          f"(per seed {', '.join(f'{x:.2f}' for x in ratios)})")
            same = [_coverage(r, 1) == _coverage(r, n) for r in mine]
            print(f"  --workers {n}: same coverage as --workers 1 on {sum(same)}/{len(same)} seeds")
            spans = [x for x in (_batch_parallelism(r, n) for r in mine) if x is not None]
            if spans:
                print(f"  --workers {n}: batch parallelism (task time / critical path) median "
                      f"{statistics.median(spans):.2f} (per seed "
                      f"{', '.join(f'{x:.2f}' for x in spans)}): the batches' own bound")


def _ratio(row: dict, n: int, key: str) -> float | None:
    one = next((w for w in row["wall"] if w["workers"] == 1 and key in w), None)
    many = next((w for w in row["wall"] if w["workers"] == n and key in w), None)
    if one is None or many is None or many[key] <= 0:
        return None
    return one[key] / many[key]


def _batch_parallelism(row: dict, n: int) -> float | None:
    """The tasks' summed time over the batches' critical path (summary.json ``parallel``):
    how much the batches could shorten the concretization time, however idle the cores."""
    w = next((w for w in row["wall"] if w["workers"] == n), None)
    stats = (w or {}).get("parallel") or {}
    if not stats.get("critical_s"):
        return None
    return stats["worker_busy_s"] / stats["critical_s"]


def _coverage(row: dict, n: int) -> float | None:
    w = next((w for w in row["wall"] if w["workers"] == n), None)
    return None if w is None else round(w.get("coverage", -1.0), 3)


if __name__ == "__main__":
    raise SystemExit(main())
