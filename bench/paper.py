"""Reproduce the paper's results table (Shah et al., ATM-MDP) on the PyBullet world.

    python bench/paper.py                       # 10 seeds per class, the paper's timeouts
    python bench/paper.py --quick               # CI: 1 seed per paper class, 120 s limits
    python bench/paper.py --runs 3 --seed-base 100 --classes 'cluttered|domino'
    python bench/paper.py --beyond              # also the classes the paper did not attempt

Every run is a fresh instance from the example's generator (seed = ``--seed-base`` + run
index) refined in its own process by ``bench/paper_worker.py`` (= ``python -m stampc
refine ... --world pybullet -o DIR`` plus work counters). The primary time is the whole
process (interpreter start, compile, ground, scene, refine, export), measured around the
subprocess; the engine's time (``summary.json``) is reported beside it. A run is
**solved** when its coverage is ≥ 0.999 within the timeout and no goal mass was given up
(every leaf is a goal or a dead end proven in the abstract model, when the engine reports
that split; otherwise the table says "split n/a"). Outputs in ``--out``: ``runs.csv``,
``runs.json``, ``table.md`` (printed), ``anytime.png`` and the runs' folders. See
docs/benchmarks.md.
"""

from __future__ import annotations

import argparse
import importlib
import json
import math
import os
import re
import resource
import shlex
import signal
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
for entry in (str(REPO), str(REPO / "bench")):
    if entry not in sys.path:  # examples.<name> generators, and the sibling modules
        sys.path.insert(0, entry)

from paper_classes import CLASSES, ProblemClass  # noqa: E402
from paper_report import executed as _executed, table  # noqa: E402

THRESHOLDS = ("0.5", "0.8", "0.9", "1.0")
SOLVED_COVERAGE = 0.999
QUICK_TIMEOUT = 120.0
EXECUTE_RUNS = 20  # executions of each solved policy in the world (--execute)
#: a solved policy's executions that reach its unrefined part (≤ 0.1 % of the mass) must
#: be at least this likely (binomial tail), else the run is "exec-failed"
PLAUSIBLE = 1e-3


@dataclass(frozen=True)
class Job:
    cls: ProblemClass
    run: int
    seed: int
    timeout_s: float
    out_dir: str
    #: further ``stampc refine`` arguments (``--refine-args``)
    refine_args: tuple[str, ...] = ()
    #: ``stampc execute`` runs of each solved policy (0: none)
    execute_runs: int = EXECUTE_RUNS


@dataclass(frozen=True)
class RunRecord:
    cls: str
    run: int
    seed: int
    #: "solved" | "partial" | "gave-up" | "timeout" | "error" | "exec-failed" (an
    #: execution in the world failed, collided or missed the goal: of a policy refined to
    #: the target, or in the refined part of a partial one)
    status: str
    coverage: float = 0.0
    goal_probability: float = 0.0
    process_s: float = 0.0  # the whole subprocess (primary time)
    cpu_s: float = 0.0  # its user + system CPU time (the machine may be loaded)
    engine_s: float = 0.0  # the engine's wall time (summary.json)
    time_to: dict[str, float | None] = field(default_factory=dict)  # engine time
    #: work done: learned facts, UpdateAbstraction rounds, abstract solves, PRG nodes,
    #: refined nodes, motion-planner calls, collision checks, policy branches (leaves),
    #: ground actions and facts of the abstract model
    work: dict[str, int] = field(default_factory=dict)
    given_up: float | None = None  # goal mass given up (None: the engine has no split)
    instance: str = ""
    detail: str = ""
    #: ``stampc execute`` of the policy (solved, or partial with coverage > 0): runs,
    #: success, failure, collisions, goal_failures, unrefined, seconds (empty: not executed)
    execution: dict[str, float] = field(default_factory=dict)

    @property
    def solved(self) -> bool:
        return self.status == "solved"


def make_problem(cls: ProblemClass, seed: int, out_dir: Path) -> tuple[Path, Path]:
    """(domain, problem): a fresh instance from the example's generator."""
    folder = REPO / "examples" / cls.example
    module = importlib.import_module(f"examples.{cls.example}.scene")
    problem = Path(module.write_problem(out_dir / "problem.stamp", seed=seed,
                                        **dict(cls.kwargs)))
    domain = getattr(module, "domain_path", lambda **_: folder / "domain.stamp")(
        **dict(cls.kwargs))
    return Path(domain), problem


def _child_env() -> dict[str, str]:
    """The environment of a run's subprocess: this checkout first on PYTHONPATH."""
    path = os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))
    return {**os.environ, "PYTHONPATH": path}


def _run_with_deadline(cmd: list[str], deadline_s: float) -> tuple[int, str, bool]:
    """Run ``cmd``; past the deadline send SIGTERM (stampc refine then stops as on
    Ctrl-C and writes the best policy so far; SIGINT would be ignored when the bench runs
    in the background of a script) and kill it 30 s later. Returns (exit code, stderr, killed)."""
    proc = subprocess.Popen(cmd, cwd=REPO, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            text=True, env=_child_env())
    try:
        _, err = proc.communicate(timeout=deadline_s)
        return proc.returncode, err, False
    except subprocess.TimeoutExpired:
        proc.send_signal(signal.SIGTERM)
    try:
        _, err = proc.communicate(timeout=30.0)
        return proc.returncode, err, False
    except subprocess.TimeoutExpired:
        proc.kill()
        _, err = proc.communicate()
        return proc.returncode, err, True


def given_up_mass(summary: dict) -> float | None:
    """Goal mass the engine gave up on (dead ends it did not prove), if it reports it."""
    for key in ("given_up_mass", "unproven_dead_end_mass"):
        if isinstance(summary.get(key), (int, float)):
            return float(summary[key])
    dead, proven = summary.get("dead_end_mass"), summary.get("proven_dead_end_mass")
    if isinstance(dead, (int, float)) and isinstance(proven, (int, float)):
        return max(0.0, float(dead) - float(proven))
    # stampc's engine: coverage = goal_mass + dead_end_mass, where dead_end_mass holds
    # only dead ends proven by the reachability fixpoint; a dead end the solver merely
    # gave up on stays in unrefined_mass, so that is the mass not accounted for
    if all(isinstance(summary.get(k), (int, float))
           for k in ("goal_mass", "dead_end_mass", "unrefined_mass")):
        return float(summary["unrefined_mass"])
    return None


def work_counts(result: Path, stats: dict) -> dict[str, int]:
    summary = json.loads((result / "summary.json").read_text())
    events: list[str] = []
    if (result / "coverage.csv").is_file():
        events = [line.rsplit(",", 1)[-1] for line in
                  (result / "coverage.csv").read_text().splitlines()[1:]]
    learned = branches = 0
    if (result / "policy.json").is_file():
        nodes = json.loads((result / "policy.json").read_text()).get("nodes", [])
        learned = sum(len(n.get("learned", [])) for n in nodes)
        branches = sum(1 for n in nodes if n.get("leaf"))
    return {"learned": learned, "updates": events.count("update"),
            "solves": int(summary.get("abstract_solves", 0)),
            "timeouts": int(summary.get("solver_timeouts", 0)),
            "resamples": int(summary.get("resamples", 0)),
            "prg": int(summary.get("prg_nodes", 0)),
            "refined": int(summary.get("refined_nodes", 0)),
            "planner": int(stats.get("planner_calls", 0)),
            "checks": int(stats.get("collision_checks", 0)), "branches": branches,
            "ground_actions": int(stats.get("ground_actions", 0)),
            "ground_facts": int(stats.get("ground_facts", 0))}


def run_job(job: Job) -> RunRecord:
    """Refine one instance in a subprocess; never raises."""
    out = Path(job.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    base = dict(cls=job.cls.name, run=job.run, seed=job.seed)
    try:
        domain, problem = make_problem(job.cls, job.seed, out)
    except Exception as exc:  # a generator bug must not stop the whole benchmark
        return RunRecord(**base, status="error", detail=f"generator: {type(exc).__name__}: {exc}")
    result, stats_file = out / "result", out / "work.json"
    for stale in (result / "summary.json", stats_file):
        stale.unlink(missing_ok=True)  # never read a previous run's result
    cmd = [sys.executable, str(REPO / "bench" / "paper_worker.py"), str(stats_file),
           "refine", str(domain), str(problem), "--world", "pybullet", "--time-limit",
           str(job.timeout_s), "--target-coverage", str(SOLVED_COVERAGE), "--seed",
           str(job.seed), "--quiet", "-o", str(result), *job.refine_args]
    t0, usage = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
    code, stderr, killed = _run_with_deadline(cmd, job.timeout_s * 1.25 + 60.0)
    process_s = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu_s = (after.ru_utime - usage.ru_utime) + (after.ru_stime - usage.ru_stime)
    (out / "stderr.txt").write_text(stderr)
    if killed or not (result / "summary.json").is_file():
        tail = " | ".join(stderr.strip().splitlines()[-3:])
        return RunRecord(**base, status="timeout" if killed else "error", process_s=process_s,
                         cpu_s=cpu_s,
                         instance=str(problem), detail=f"exit {code}: {tail}"[:300])
    summary = json.loads((result / "summary.json").read_text())
    stats = json.loads(stats_file.read_text()) if stats_file.is_file() else {}
    coverage, engine = float(summary["coverage"]), float(summary["wall_time_s"])
    given_up = given_up_mass(summary)
    if coverage < SOLVED_COVERAGE:
        status = "timeout" if process_s >= job.timeout_s else "partial"
    elif given_up is not None and given_up > 1.0 - SOLVED_COVERAGE + 1e-9:
        status = "gave-up"
    else:
        status = "solved" if process_s <= job.timeout_s else "timeout"
    execution: dict[str, float] = {}
    if job.execute_runs > 0 and (status == "solved" or coverage > 0.0):
        # a partial policy is executed too: what it refined must work in the world (runs
        # that reach its unrefined part are counted apart); a solved policy must be clean
        execution = execute(result / "policy.json", job.execute_runs, job.seed,
                            unrefined_mass=max(0.0, 1.0 - coverage))
        if not execution.get("clean" if status == "solved" else "refined_clean"):
            status = "exec-failed"
    return RunRecord(**base, status=status, coverage=coverage, execution=execution,
                     goal_probability=float(summary["goal_probability"]), process_s=process_s,
                     cpu_s=cpu_s, engine_s=engine,
                     time_to={k: summary.get("time_to_coverage", {}).get(k) for k in THRESHOLDS},
                     work=work_counts(result, stats), given_up=given_up, instance=str(problem),
                     detail=str(summary.get("stop_reason", "")))


def execute(policy: Path, runs: int, seed: int, unrefined_mass: float = 0.0
            ) -> dict[str, float]:
    """Run the policy ``runs`` times in its world (``stampc execute``: outcomes sampled by
    the world, trajectories re-swept at 10x, the goal checked on the concrete state):
    evidence from outside the refinement that a "solved" policy works. It is clean when
    nothing refined failed and the runs that reached the unrefined part are as many as
    its ``unrefined_mass`` (≤ 0.001 for a solved run) makes plausible (binomial tail ≥
    ``PLAUSIBLE``): 1 in 20 at 0.001 is a 2 % event, 2 in 20 one of 0.02 %."""
    cmd = [sys.executable, "-m", "stampc", "execute", str(policy), "--runs", str(runs),
           "--seed", str(seed), "--format", "json"]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True, env=_child_env())
    seconds = round(time.perf_counter() - t0, 2)
    try:
        data = json.loads(proc.stdout)
    except json.JSONDecodeError:
        return {"runs": runs, "error": 1, "clean": 0, "seconds": seconds}
    out = {k: data.get(k, 0) for k in ("runs", "success", "failure", "dead_end", "unrefined",
                                       "collisions", "goal_check_failures")}
    refined_clean = (proc.returncode in (0, 3) and not out["failure"]
                     and not out["collisions"] and not out["goal_check_failures"])
    clean = refined_clean and _plausible(int(out["unrefined"]), int(out["runs"]), unrefined_mass)
    return {**out, "clean": int(clean), "refined_clean": int(refined_clean),
            "seconds": seconds}


def _plausible(k: int, n: int, p: float) -> bool:
    """Whether ``k`` or more of ``n`` runs reaching mass ``p`` has probability ≥ PLAUSIBLE."""
    tail = sum(math.comb(n, i) * p ** i * (1.0 - p) ** (n - i) for i in range(k, n + 1))
    return k == 0 or tail >= PLAUSIBLE


def _anytime(records: list[RunRecord], out: Path, path: Path) -> None:
    """Mean coverage vs engine time per class (from every run's coverage.csv)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.5), dpi=110)
    for name in dict.fromkeys(r.cls for r in records):
        curves = []
        for r in (r for r in records if r.cls == name):
            csv = out / name / f"run{r.run}" / "result" / "coverage.csv"
            if csv.is_file():
                rows = [line.split(",") for line in csv.read_text().splitlines()[1:]]
                curves.append(([float(x[0]) for x in rows], [float(x[1]) for x in rows]))
        curves = [c for c in curves if c[0]]
        if not curves:
            continue
        end = max(c[0][-1] for c in curves)
        grid = [end * i / 200 for i in range(201)]
        mean = [sum(max([v for t, v in zip(*c) if t <= g] or [0.0]) for c in curves) / len(curves)
                for g in grid]
        ax.step(grid, mean, where="post", label=name)
    ax.set(xlabel="engine time (s)", ylabel="mean coverage", ylim=(0, 1.02),
           title="anytime refinement: refined probability mass vs time")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def report(files: list[str], execute_runs: int = 0) -> int:
    """The table of the runs recorded in ``files`` (``runs.json`` of earlier runs). With
    ``execute_runs``, solved runs recorded without an execution are executed now (their
    policies are read from beside the runs.json) and the file is written back."""
    by_key: dict[tuple[str, int], RunRecord] = {}
    for f in files:
        raws = json.loads(Path(f).read_text())
        records = [_executed_late(RunRecord(**raw), Path(f).parent, execute_runs)
                   for raw in raws]
        if execute_runs:
            Path(f).write_text(json.dumps([asdict(r) for r in records], indent=1))
        for rec in records:
            by_key[(rec.cls, rec.seed)] = rec
    records = list(by_key.values())
    names = {r.cls for r in records}
    print(table(records, tuple(c for c in CLASSES if c.name in names)))
    return 0


def _executed_late(rec: RunRecord, out: Path, runs: int) -> RunRecord:
    policy = out / rec.cls / f"run{rec.run}" / "result" / "policy.json"
    if not runs or rec.status != "solved" or rec.execution or not policy.is_file():
        return rec
    execution = execute(policy, runs, rec.seed, unrefined_mass=max(0.0, 1.0 - rec.coverage))
    return replace(rec, execution=execution,
                   status="solved" if execution.get("clean") else "exec-failed")


def _records(jobs: list[Job], args: argparse.Namespace):
    """Each job's record in job order: local processes, or Ray tasks (bench/paper_ray.py)."""
    if args.ray is not None:
        from paper_ray import run_on_ray
        yield from (RunRecord(**raw) for raw in run_on_ray(jobs, args.ray))
        return
    with ProcessPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        yield from pool.map(run_job, jobs)


def _compile_bytecode() -> None:
    """Compile stampc's and the examples' bytecode before the runs, as a regular
    ``pip install`` does: an editable install under ``PYTHONDONTWRITEBYTECODE`` (set on
    the benchmark machine) never writes it, and every run would compile ~180 modules
    again (about 0.25 s of a 2 s domino run), a cost no installed copy pays."""
    import compileall
    for package in ("stampc", "examples"):
        compileall.compile_dir(str(REPO / package), quiet=1)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="reproduce the paper's table on PyBullet")
    ap.add_argument("--runs", type=int, default=10, help="seeds per class (default 10)")
    ap.add_argument("--quick", action="store_true",
                    help=f"CI: 1 seed per paper class, {QUICK_TIMEOUT:.0f} s limits")
    ap.add_argument("--beyond", action="store_true", help="also the beyond-paper classes")
    ap.add_argument("--timeout", type=float, help="override every class's timeout (s)")
    ap.add_argument("--classes", default="", help="regex selecting class names, among every "
                    "class (the beyond-paper ones too, without --beyond)")
    ap.add_argument("--jobs", type=int, default=2, help="parallel runs (default 2)")
    ap.add_argument("--ray", nargs="?", const="", default=None, metavar="ADDRESS",
                    help="run on the Ray cluster at ADDRESS (Ray's default without one) "
                         "instead of the local pool; --jobs is then the cluster's CPUs")
    ap.add_argument("--seed-base", type=int, default=0, help="seed of each class's first run")
    ap.add_argument("--out", default=str(REPO / "bench" / "out" / "paper"))
    ap.add_argument("--report", nargs="+", metavar="RUNS_JSON",
                    help="run nothing: print the table of earlier runs.json files (a later "
                         "file's run of a class and seed replaces an earlier one's)")
    ap.add_argument("--refine-args", default="", metavar="ARGS",
                    help="further stampc refine arguments for every run, e.g. "
                         "'--ban-everywhere-after 3'")
    ap.add_argument("--execute", type=int, default=EXECUTE_RUNS, metavar="N",
                    help="stampc execute runs of each solved or partial policy; a failure, "
                         "collision or missed goal (in a partial policy: in its refined "
                         f"part) makes the run 'exec-failed' (default {EXECUTE_RUNS}; "
                         "0: none)")
    args = ap.parse_args(argv)
    if args.report:  # an explicit --execute N also executes runs recorded without one
        explicit = any(a.startswith("--execute") for a in (argv or sys.argv[1:]))
        return report(args.report, args.execute if explicit else 0)
    classes = tuple(c for c in CLASSES if re.search(args.classes, c.name)
                    and (args.beyond or args.classes or not c.beyond))
    runs = 1 if args.quick else args.runs
    out = Path(args.out).resolve()
    jobs = [Job(cls, i, args.seed_base + i,
                args.timeout or (QUICK_TIMEOUT if args.quick else cls.timeout_s),
                str(out / cls.name / f"run{i}"), tuple(shlex.split(args.refine_args)),
                max(0, args.execute))
            for cls in classes for i in range(runs)]
    _compile_bytecode()
    where = f"{args.jobs} at a time" if args.ray is None else f"on Ray ({args.ray or 'default'})"
    print(f"{len(jobs)} runs of {len(classes)} classes, {where} -> {out}")
    records: list[RunRecord] = []
    for rec in _records(jobs, args):
        records.append(rec)
        print(f"  {rec.cls:16s} seed {rec.seed:3d}: {rec.status:8s} coverage "
              f"{rec.coverage:.4f} process {rec.process_s:7.1f} s (cpu {rec.cpu_s:.1f}) engine "
              f"{rec.engine_s:7.1f} s  {json.dumps(rec.work)}  {rec.detail[:50]}"
              + (f"  executed {_executed([rec])}" if rec.execution else ""), flush=True)
    out.mkdir(parents=True, exist_ok=True)
    (out / "runs.json").write_text(json.dumps([asdict(r) for r in records], indent=1))
    text = table(records, classes)
    (out / "table.md").write_text(text)
    _anytime(records, out, out / "anytime.png")
    print(text)
    print(f"wrote {out / 'runs.json'}, table.md, anytime.png")
    return 0 if all(r.solved for r in records) else 1


if __name__ == "__main__":
    raise SystemExit(main())
