"""Reproduce the paper's results table (Shah et al., ATM-MDP) on the PyBullet world.

    python bench/paper.py                      # 3 seeded runs per class
    python bench/paper.py --runs 10 --jobs 2   # more runs, two at a time
    python bench/paper.py --quick              # CI: 1 run per class, short timeouts
    python bench/paper.py --classes 'domino|aircraft' --out bench/out/paper

Every run is a fresh instance from the example's problem generator
(``examples/<name>/scene.py:write_problem``) refined by ``python -m stampc refine ...
--world pybullet -o DIR`` in its own subprocess with a timeout; ``summary.json`` and
``coverage.csv`` are read back. A run is *solved* when it reaches coverage 1.0 within
the timeout with a policy that reaches the goal with probability > 0. Outputs in ``--out``: ``runs.csv`` (every run), ``table.md`` (the table
printed at the end), ``anytime.png`` (mean coverage vs time per class) and the runs'
folders. See docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import csv
import importlib
import json
import os
import re
import signal
import statistics
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
if str(REPO) not in sys.path:  # the examples' generators are imported as examples.<name>
    sys.path.insert(0, str(REPO))
THRESHOLDS = ("0.5", "0.8", "0.9", "1.0")
SPEEDUP = 50.0  # target: median time <= paper average / 50
EARLY_MASS, EARLY_SHARE = "0.9", 0.15  # target: 90 % of the mass within 15 % of the time


@dataclass(frozen=True)
class ProblemClass:
    """One row of the paper's table: an example folder plus generator arguments."""

    name: str
    example: str
    kwargs: tuple[tuple[str, Any], ...]
    paper_solved: float | None  # fraction solved in the paper (None: not reported)
    paper_time_s: float
    timeout_s: float = 2400.0


def _classes() -> tuple[ProblemClass, ...]:
    out = [ProblemClass(f"cluttered-{n}", "cluttered_table", (("n", n),), solved, t)
           for n, solved, t in ((15, 0.95, 1094.0), (20, 0.79, 1145.0), (25, 0.74, 1393.0))]
    domino = {(10, 2): 99.0, (10, 3): 351.0, (15, 2): 180.0, (15, 3): 632.0,
              (20, 2): 351.0, (20, 3): 591.0}
    out += [ProblemClass(f"domino-n{n}k{k}", "domino", (("n", n), ("k", k)), 1.0, t)
            for (n, k), t in domino.items()]
    # examples/keva/scene.py: write_problem(path, structure=pi|tower|twisted|3towers,
    # levels=, seed=); the seed samples the structure's site. Beyond the paper (no paper
    # figures; its 4,000 s timeout): tower-24 and the photos' 3-towers (3 × 4 levels).
    out += [ProblemClass(name, "keva", (("structure", s), ("levels", levels)), solved, t, 4000.0)
            for name, s, levels, solved, t in (("keva-3pi", "pi", 3, 1.0, 1313.0),
                                               ("keva-tower-12", "tower", 12, 1.0, 1900.0),
                                               ("keva-twisted-12", "twisted", 12, 0.98, 1984.0),
                                               ("keva-tower-24", "tower", 24, None, 4000.0),
                                               ("keva-3towers", "3towers", 4, None, 4000.0))]
    out.append(ProblemClass("aircraft", "aircraft_inspection", (), 1.0, 1457.0))
    return tuple(out)


CLASSES = _classes()


@dataclass(frozen=True)
class Job:
    cls: ProblemClass
    run: int
    seed: int
    timeout_s: float
    out_dir: str


@dataclass(frozen=True)
class RunRecord:
    cls: str
    run: int
    seed: int
    status: str  # "solved" | "partial" | "timeout" | "unsolvable" | "error"
    coverage: float
    goal_probability: float
    wall_time_s: float
    time_to: dict[str, float | None] = field(default_factory=dict)
    process_s: float = 0.0  # the whole subprocess: compile, ground, world, refine, export
    instance: str = ""
    detail: str = ""

    @property
    def solved(self) -> bool:
        return self.status == "solved"


def make_problem(cls: ProblemClass, seed: int, out_dir: Path) -> tuple[Path, Path, str]:
    """(domain, problem, note): a fresh instance from the example's generator, or the
    checked-in problem (with the scene seed overridden) when the generator is missing
    or does not take these arguments."""
    folder = REPO / "examples" / cls.example
    domain, problem = folder / "domain.stamp", out_dir / "problem.stamp"
    try:
        module = importlib.import_module(f"examples.{cls.example}.scene")
        module.write_problem(problem, seed=seed, **dict(cls.kwargs))
        return domain, problem, "generated"
    except (ImportError, AttributeError, TypeError, ValueError) as exc:
        return domain, folder / "problem.stamp", f"checked-in problem ({type(exc).__name__}: {exc})"


def _run_with_deadline(cmd: list[str], env: dict, deadline_s: float) -> tuple[int, str, bool]:
    """Run ``cmd``; past the deadline send SIGINT (stampc then writes the best policy
    so far), and kill it 30 s later. Returns (exit code, stderr, killed)."""
    proc = subprocess.Popen(cmd, cwd=REPO, env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)
    try:
        _, err = proc.communicate(timeout=deadline_s)
        return proc.returncode, err, False
    except subprocess.TimeoutExpired:
        proc.send_signal(signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=30.0)
        return proc.returncode, err, False
    except subprocess.TimeoutExpired:
        proc.kill()
        _, err = proc.communicate()
        return proc.returncode, err, True


def run_job(job: Job) -> RunRecord:
    """Refine one instance in a subprocess (``stampc refine -o``); never raises."""
    out = Path(job.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    base = dict(cls=job.cls.name, run=job.run, seed=job.seed)
    try:
        domain, problem, note = make_problem(job.cls, job.seed, out)
    except Exception as exc:  # a generator bug must not stop the whole benchmark
        return RunRecord(**base, status="error", coverage=0.0, goal_probability=0.0,
                         wall_time_s=0.0, detail=f"generator: {type(exc).__name__}: {exc}")
    cmd = [sys.executable, "-m", "stampc", "refine", str(domain), str(problem),
           "--world", "pybullet", "--time-limit", str(job.timeout_s), "--seed", str(job.seed),
           "--quiet", "-o", str(out / "result")]
    if note != "generated":
        cmd[-2:-2] = ["--scene-arg", f"seed={job.seed}"]
    path = os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))
    env = {**os.environ, "PYTHONPATH": path}
    summary = out / "result" / "summary.json"
    summary.unlink(missing_ok=True)  # never read a previous run's result
    t0 = time.perf_counter()
    returncode, stderr, killed = _run_with_deadline(cmd, env, job.timeout_s * 1.25 + 30.0)
    (out / "stderr.txt").write_text(stderr)
    if killed:
        return RunRecord(**base, status="timeout", coverage=0.0, goal_probability=0.0,
                         wall_time_s=time.perf_counter() - t0, instance=note,
                         detail="killed: no result after the grace period")
    if not summary.is_file():
        tail = stderr.strip().splitlines()[-3:]
        return RunRecord(**base, status="error", coverage=0.0, goal_probability=0.0,
                         wall_time_s=time.perf_counter() - t0, instance=note,
                         detail=f"exit {returncode}: {' | '.join(tail)}")
    data = json.loads(summary.read_text())
    coverage = float(data["coverage"])
    wall = float(data["wall_time_s"])
    # a policy whose every branch is a dead end is "covered" but solves nothing
    unsolvable = data.get("stop_reason") == "abstract goal unreachable"
    solved = (coverage >= 1.0 - 1e-9 and wall <= job.timeout_s and not unsolvable
              and float(data["goal_probability"]) > 0.0)
    status = ("solved" if solved else "unsolvable" if unsolvable
              else "timeout" if wall >= job.timeout_s else "partial")
    return RunRecord(**base, status=status, coverage=coverage,
                     goal_probability=float(data["goal_probability"]), wall_time_s=wall,
                     time_to={k: data["time_to_coverage"].get(k) for k in THRESHOLDS},
                     instance=note, detail=str(data.get("stop_reason", "")),
                     process_s=time.perf_counter() - t0)


def early_mass_ok(r: RunRecord) -> bool:
    t = r.time_to.get(EARLY_MASS)
    return t is not None and t <= EARLY_SHARE * r.wall_time_s + 1e-9


def _median(values: list[float]) -> float | None:
    return statistics.median(values) if values else None


def _fmt(x: float | None, digits: int = 1) -> str:
    return "—" if x is None else f"{x:.{digits}f}"


def table(records: list[RunRecord], classes: tuple[ProblemClass, ...]) -> str:
    head = ("| class | runs | solved | paper solved | median s | mean s | paper avg s | "
            "ratio | t50 | t80 | t90 | t100 | 90 % ≤ 15 % time | targets |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for cls in classes:
        rs = [r for r in records if r.cls == cls.name]
        if not rs:
            continue
        solved = [r for r in rs if r.solved]
        times = [r.wall_time_s for r in solved]
        med = _median(times)
        ratio = cls.paper_time_s / med if med else None
        tt = {k: _median([r.time_to[k] for r in solved if r.time_to.get(k) is not None])
              for k in THRESHOLDS}
        early = sum(early_mass_ok(r) for r in solved)
        ok = (len(solved) == len(rs) and med is not None and med <= cls.paper_time_s / SPEEDUP
              and early >= 0.9 * len(rs))
        paper = "—" if cls.paper_solved is None else f"{100 * cls.paper_solved:.0f} %"
        lines.append(
            f"| {cls.name} | {len(rs)} | {100 * len(solved) / len(rs):.0f} % | {paper} | "
            f"{_fmt(med)} | {_fmt(statistics.fmean(times) if times else None)} | "
            f"{cls.paper_time_s:,.0f} | {_fmt(ratio, 0) + '×' if ratio else '—'} | "
            + " | ".join(_fmt(tt[k], 2) for k in THRESHOLDS)
            + f" | {early}/{len(rs)} | {'met' if ok else 'MISSED'} |")
    return "\n".join(lines) + "\n"


def write_csv(records: list[RunRecord], path: Path) -> None:
    with path.open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["class", "run", "seed", "status", "coverage", "goal_probability",
                    "wall_time_s", *(f"t{k}" for k in THRESHOLDS), "process_s", "instance",
                    "detail"])
        for r in records:
            w.writerow([r.cls, r.run, r.seed, r.status, f"{r.coverage:.9f}",
                        f"{r.goal_probability:.9f}", f"{r.wall_time_s:.3f}",
                        *("" if r.time_to.get(k) is None else f"{r.time_to[k]:.3f}"
                          for k in THRESHOLDS), f"{r.process_s:.3f}", r.instance, r.detail])


def read_curve(path: Path) -> tuple[list[float], list[float]]:
    times, cov = [], []
    if path.is_file():
        with path.open() as fh:
            for row in csv.DictReader(fh):
                times.append(float(row["time_s"]))
                cov.append(float(row["coverage"]))
    return times, cov


def _at(times: list[float], cov: list[float], t: float) -> float:
    value = 0.0
    for ti, ci in zip(times, cov):
        if ti > t:
            break
        value = ci
    return value


def plot_anytime(records: list[RunRecord], out: Path, path: Path) -> None:
    """Mean coverage (step functions of every run's coverage.csv) vs time, per class."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.5), dpi=110)
    for name in dict.fromkeys(r.cls for r in records):
        curves = [read_curve(out / name / f"run{r.run}" / "result" / "coverage.csv")
                  for r in records if r.cls == name]
        curves = [c for c in curves if c[0]]
        if not curves:
            continue
        end = max(c[0][-1] for c in curves)
        grid = [end * i / 200 for i in range(201)]
        mean = [statistics.fmean(_at(t, c, g) for t, c in curves) for g in grid]
        ax.step(grid, mean, where="post", label=name)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("mean coverage")
    ax.set_ylim(0, 1.02)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    ax.set_title("anytime refinement: refined probability mass vs time")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="reproduce the paper's table on PyBullet")
    ap.add_argument("--runs", type=int, default=3, help="instances per class (default 3)")
    ap.add_argument("--quick", action="store_true", help="1 run per class, short timeouts (CI)")
    ap.add_argument("--timeout", type=float, help="override every class's timeout (s)")
    ap.add_argument("--classes", default="", help="regex selecting class names")
    ap.add_argument("--jobs", type=int, default=2, help="parallel runs (default 2)")
    ap.add_argument("--seed", type=int, default=0, help="seed of the first run")
    ap.add_argument("--out", default=str(REPO / "bench" / "out" / "paper"))
    args = ap.parse_args(argv)
    classes = tuple(c for c in CLASSES if re.search(args.classes, c.name))
    runs = 1 if args.quick else args.runs
    out = Path(args.out).resolve()
    jobs = []
    for cls in classes:
        timeout = args.timeout or (60.0 if args.quick else cls.timeout_s)
        jobs += [Job(cls, i, args.seed + i, timeout, str(out / cls.name / f"run{i}"))
                 for i in range(runs)]
    print(f"{len(jobs)} runs of {len(classes)} classes, {args.jobs} at a time -> {out}")
    records: list[RunRecord] = []
    with ProcessPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        for rec in pool.map(run_job, jobs):
            records.append(rec)
            print(f"  {rec.cls:18s} run {rec.run}: {rec.status:8s} coverage {rec.coverage:.4f} "
                  f"{rec.wall_time_s:8.1f} s  {rec.detail[:60]}", flush=True)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(records, out / "runs.csv")
    text = table(records, classes)
    (out / "table.md").write_text(text)
    (out / "runs.json").write_text(json.dumps([asdict(r) for r in records], indent=1))
    plot_anytime(records, out, out / "anytime.png")
    print(text)
    print(f"wrote {out / 'runs.csv'}, table.md, runs.json, anytime.png")
    return 0 if all(r.solved for r in records) else 1


if __name__ == "__main__":
    raise SystemExit(main())
