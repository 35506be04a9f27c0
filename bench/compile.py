"""Import + grounding speed over the shared PPDDL benchmarks and a generated domain.

Usage: python bench/compile.py [--only SUBSTRING] [--skip-large] [--sizes N,N,...]
       [--skip-p14]

Then the whole-compile figures of ``bench/compile_ir.py``: sysadmin-slp p14
``stampc compile --target ir`` (wall time, bytes written, peak RSS) and the throughput
(actions/s) per stage of a generated stamp domain at 2k, 20k and 165k actions.

rectangle-tireworld p15 (about 13 million reachable actions) stops with diagnostic G114
(the default ``max_actions`` of ground()); the run continues with the next problem.

Prints one row per benchmark problem (import time, ground time, ground actions, facts)
and the ground time of a programmatically generated lifted model with 2,000 action
schemas chained by reachability (2,000 relaxed-plan layers). Always exits 0.
"""

from __future__ import annotations

import argparse
import sys
import time
from fractions import Fraction
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

import compile_ir  # noqa: E402  (bench/compile_ir.py, beside this file)
from stampc.diagnostics import StampcError  # noqa: E402
from stampc.ir import lifted as L  # noqa: E402
from stampc.ir.ground import ground  # noqa: E402

BENCHMARKS = REPO.parent / "shared" / "benchmarks" / "ppddl"
#: instances known to take far longer than the others (reported, run unless --skip-large)
LARGE = ("sysadmin-slp/p13", "sysadmin-slp/p14", "sysadmin-slp/p15",
         "rectangle-tireworld/p11", "rectangle-tireworld/p12", "rectangle-tireworld/p13",
         "rectangle-tireworld/p14", "rectangle-tireworld/p15")


def generated_model(n_actions: int = 2000, n_locs: int = 6) -> L.Model:
    """``step_k(?r, ?l)``: stage k at a good location -> (0.9) stage k+1; forall effect."""
    r, loc = L.Var("r"), L.Var("l")
    m = L.Var("m")
    preds = [L.Predicate(f"stage{k}", (L.Param("r", "robot"),)) for k in range(n_actions + 1)]
    preds += [L.Predicate("at", (L.Param("r", "robot"), L.Param("l", "loc"))),
              L.Predicate("good", (L.Param("l", "loc"),)),
              L.Predicate("visited", (L.Param("l", "loc"),))]
    actions = []
    for k in range(n_actions):
        pre = L.And((L.Atom(f"stage{k}", (r,)), L.Atom("at", (r, loc)), L.Atom("good", (loc,))))
        eff = L.EffAnd((
            L.Lit(L.Atom("visited", (loc,))),
            L.Probabilistic((L.Outcome(Fraction(9, 10), L.EffAnd((
                L.Lit(L.Atom(f"stage{k + 1}", (r,))),
                L.Lit(L.Atom(f"stage{k}", (r,)), False)))),)),
            L.EffForall((L.Param("m", "loc"),), L.When(
                L.Atom("visited", (m,)), L.CostEffect(L.Num(Fraction(1))))),
        ))
        actions.append(L.Action(f"step{k}", (L.Param("r", "robot"), L.Param("l", "loc")),
                                pre, eff))
    locs = [L.Object(f"l{i}", "loc") for i in range(n_locs)]
    domain = L.Domain("generated", (L.Type("robot"), L.Type("loc")), (), tuple(preds), (),
                      tuple(actions))
    init = (L.Atom("stage0", (L.Const("r0"),)), L.Atom("at", (L.Const("r0"), L.Const("l0"))),
            L.Atom("good", (L.Const("l0"),)), L.Atom("good", (L.Const("l1"),)))
    problem = L.Problem("generated-1", "generated", (L.Object("r0", "robot"), *locs), init,
                        goal=L.Atom(f"stage{n_actions}", (L.Const("r0"),)))
    return L.Model(domain, problem)


def problem_files(only: str, skip_large: bool) -> list[Path]:
    files = []
    for d in sorted(p for p in BENCHMARKS.iterdir() if p.is_dir()):
        for f in sorted(d.glob("*.pddl")):
            rel = f"{d.name}/{f.name}"
            if f.name == "domain.pddl" or only not in rel:
                continue
            if skip_large and any(tag in rel for tag in LARGE):
                continue
            files.append(f)
    return files


def fmt(t: float | None) -> str:
    return "-" if t is None else f"{t:.3f}"


def row(name: str, t_import: float | None, t_ground: float | None, cpu: float | None,
        actions: str, facts: str) -> str:
    return (f"{name:<62} {fmt(t_import):>8} {fmt(t_ground):>8} {fmt(cpu):>8} "
            f"{actions:>9} {facts:>7}")


def timed_ground(model: L.Model):
    """Ground ``model``; returns (model, wall seconds, CPU seconds of this process).

    CPU time is reported too because the machine is shared: wall time includes waiting.
    """
    w0, c0 = time.perf_counter(), time.process_time()
    gm = ground(model)
    return gm, time.perf_counter() - w0, time.process_time() - c0


def bench_ppddl(only: str, skip_large: bool) -> list[float]:
    try:
        from stampc.backends.ppddl.importer import import_ppddl
    except ImportError as exc:
        print(f"PPDDL importer not available ({exc}); skipping benchmarks")
        return []
    if not BENCHMARKS.is_dir():
        print(f"benchmark folder {BENCHMARKS} not found; skipping PPDDL benchmarks")
        return []
    times = []
    for path in problem_files(only, skip_large):
        name = f"{path.parent.name}/{path.name}"
        t0 = time.perf_counter()
        try:
            model = import_ppddl(path)
        except StampcError as exc:
            print(row(name, None, None, None, "import", "error") + f"  {exc}")
            continue
        t1 = time.perf_counter()
        try:
            gm, wall, cpu = timed_ground(model)
        except StampcError as exc:
            print(row(name, t1 - t0, None, None, "ground", "error") + f"  {exc}")
            continue
        times.append(cpu)
        print(row(name, t1 - t0, wall, cpu, str(len(gm.actions)), str(len(gm.facts))),
              flush=True)
    return times


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", default="", help="only benchmarks whose path contains this")
    parser.add_argument("--skip-large", action="store_true",
                        help="skip the instances listed in LARGE (very large ground models)")
    parser.add_argument("--sizes", default="2000,20000,165000",
                        help="stamp domain sizes for the throughput table ('' skips it)")
    parser.add_argument("--skip-p14", action="store_true",
                        help="skip the sysadmin-slp p14 `compile --target ir` measurement")
    args = parser.parse_args(argv)
    print(f"{'problem':<62} {'import s':>8} {'ground s':>8} {'cpu s':>8} "
          f"{'actions':>9} {'facts':>7}")
    times = bench_ppddl(args.only, args.skip_large)
    if times:
        over = sum(1 for t in times if t >= 1.0)
        print(f"\n{len(times)} problems grounded, ground CPU total {sum(times):.2f} s, "
              f"max {max(times):.2f} s, {over} at or above 1 s")
    gm, wall, cpu = timed_ground(generated_model())
    print(row("generated: 2000 action schemas (chain)", None, wall, cpu,
              str(len(gm.actions)), str(len(gm.facts))), flush=True)
    print()
    ir_args = ["--sizes", args.sizes] + (["--skip-p14"] if args.skip_p14 else [])
    return compile_ir.main(ir_args)


if __name__ == "__main__":
    sys.exit(main())
