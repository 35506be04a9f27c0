"""Whole-compile figures: sysadmin-slp p14 ``--target ir``, and stamp throughput by size.

Usage: ``python bench/compile_ir.py [--runs R] [--sizes 2000,20000,165000] [--skip-p14]``
(also run by ``python bench/compile.py``).

- p14: ``python -m stampc compile domain.pddl p14 --target ir -o DIR`` in a child
  process, R times; prints median wall time, bytes written and peak RSS (``wait4``
  rusage of that child) against the targets (10 s, 50 MB, 1 GB).
- stamp: a domain of N actions from ``bench/frontend.py``'s generator plus a small
  problem, each size in its own child process; prints seconds and actions/s per stage
  (parse + check, lower, ground, JSON) so a cost growing faster than N shows as falling
  throughput, and the process's peak RSS at the end of each stage (the checked program
  is dropped after lowering, as ``stampc compile`` does). The generator's ``? forall (t2: traj) collision(o, t2)`` effect is
  narrowed to the action's own trajectory: over all trajectories it is quadratic by
  definition (every ground action has its own Skolem trajectory, and each would mark
  all N of them unknown).
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BENCH = Path(__file__).resolve().parent
REPO = BENCH.parent
SYSADMIN = REPO.parent / "shared" / "benchmarks" / "ppddl" / "ippc2008-sysadmin-slp"
P14 = "p14-n960-l480-s14.pddl"
TARGETS = {"wall s": 10.0, "written MB": 50.0, "peak RSS MB": 1024.0}

NARROW = ("? forall (t2: traj) collision(o, t2)", "? collision(o, t)")
PROBLEM = """
problem bench_p for bench

object b0: block
object r0, r1: region
object pose0: pose

init handempty
     at(b0, pose0)
     in_region(b0, r0)
     adjacent(r0, r1)

goal in_region(b0, r1)
"""


def timed_child(cmd: list[str]) -> tuple[float, int, float, str, float]:
    """Run ``cmd`` from the repository root: (wall s, exit code, the child's own peak RSS
    in MB from ``os.wait4``, its output, its CPU s)."""
    with tempfile.TemporaryFile("w+") as out:
        start = time.perf_counter()
        proc = subprocess.Popen(cmd, cwd=REPO, stdout=out, stderr=subprocess.STDOUT, text=True)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        cpu = usage.ru_utime + usage.ru_stime
        return wall, proc.returncode, usage.ru_maxrss / 1024, out.read(), cpu


def bench_p14(runs: int) -> None:
    domain, problem = SYSADMIN / "domain.pddl", SYSADMIN / P14
    if not problem.is_file():
        print(f"sysadmin-slp p14 not found under {SYSADMIN}; skipped")
        return
    rows = []
    for _ in range(runs):
        with tempfile.TemporaryDirectory() as tmp:
            wall, code, rss, text, cpu = timed_child(
                [sys.executable, "-m", "stampc", "compile", str(domain), str(problem),
                 "--target", "ir", "-o", tmp])
            if code != 0:
                print(f"p14 compile failed (exit {code}):\n{text}")
                return
            written = sum(f.stat().st_size for f in Path(tmp).iterdir())
            grounded = (Path(tmp) / "grounded.json").stat().st_size
        rows.append((wall, written / 1e6, rss, grounded / 1e6, cpu))
    med = [statistics.median(r[i] for r in rows) for i in range(5)]
    print(f"sysadmin-slp p14 `stampc compile --target ir` ({runs} runs, median; "
          f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")
    for (name, target), value in zip(TARGETS.items(), med):
        print(f"  {name:<12} {value:9.2f}   target <= {target:g}: "
              f"{'met' if value <= target else 'NOT met'}")
    print(f"  cpu s        {med[4]:9.2f}   (user + system of the process: the wall time on a "
          f"loaded machine includes waiting)")
    print(f"  (grounded.json {med[3]:.2f} MB; walls {', '.join(f'{r[0]:.2f}' for r in rows)})")


# ----------------------------------------------------------- stamp by size
def replicate_actions(loaded, n: int):
    """``loaded`` with its generated actions copied, renamed, up to ``n`` actions: the
    checked program a generated N-action file gives, without parsing N actions."""
    from dataclasses import replace

    info = loaded.domain
    generated = [a for a in info.actions if a.name.name.startswith("move_")]
    actions = list(info.actions)
    productions = dict(loaded.productions)
    for i in range(len(generated), len(generated) + n - len(actions)):
        source = generated[i % len(generated)]
        name = f"move_{i}"
        actions.append(replace(source, name=replace(source.name, name=name)))
        productions[name] = loaded.productions[source.name.name]
    return replace(loaded, domain=replace(info, actions=tuple(actions)),
                   productions=productions)


def stamp_child(n: int, replicate_from: int) -> None:
    """In a child process: compile a generated N-action domain, print stage timings."""
    sys.path.insert(0, str(BENCH))
    sys.path.insert(0, str(REPO))
    from frontend import generate

    from stampc.ir.ground import ground
    from stampc.ir.json_io import write_grounded_json, write_lifted_json
    from stampc.ir.lower import lower
    from stampc.semantics.api import load_together

    base = min(n, replicate_from) if replicate_from else n
    text = generate(base)
    narrowed = text.replace(*NARROW)
    with tempfile.TemporaryDirectory() as tmp:
        d, p = Path(tmp) / "domain.stamp", Path(tmp) / "problem.stamp"
        d.write_text(narrowed)
        p.write_text(PROBLEM)
        stages: list[tuple[str, float, float]] = []
        clock = time.process_time

        def done(name: str, start: float) -> None:
            peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB on Linux
            stages.append((name, clock() - start, peak))

        t = clock()
        loaded = load_together([d, p])
        done("parse+check" if base == n else f"check@{base}", t)
        if base < n:
            loaded = replicate_actions(loaded, n)
        t = clock()
        model = lower(loaded)
        del loaded  # stampc compile keeps only the lifted model
        done("lower", t)
        t = clock()
        gm = ground(model)
        done("ground", t)
        t = clock()
        with open(Path(tmp) / "lifted.json", "w", encoding="utf-8") as f:
            write_lifted_json(model, f)
        with open(Path(tmp) / "grounded.json", "w", encoding="utf-8") as f:
            write_grounded_json(gm, f)
        done("json", t)
        size = sum(f.stat().st_size for f in Path(tmp).glob("*.json"))
    print(f"STAGES {len(model.domain.actions)} {len(gm.actions)} {size} "
          + " ".join(f"{name}={sec:.4f}:{peak:.0f}" for name, sec, peak in stages)
          + f" narrowed={text != narrowed}")


def bench_stamp(sizes: list[int], replicate_from: int) -> None:
    print(f"\ngenerated stamp domain (bench/frontend.py 'stress' actions; CPU s of the "
          f"child, actions/s = schemas / CPU s; peak RSS of the child at the end of each "
          f"stage; load average {os.getloadavg()[0]:.1f})")
    print(f"{'actions':>8} {'ground':>7} {'stage':<12} {'cpu s':>8} {'actions/s':>10}"
          f" {'peak RSS MB':>11} {'JSON MB':>8}")
    for n in sizes:
        wall, code, rss, out, _ = timed_child([sys.executable, str(Path(__file__)), "--child",
                                               str(n), "--replicate-from", str(replicate_from)])
        line = next((ln for ln in out.splitlines() if ln.startswith("STAGES")), None)
        if code != 0 or line is None:
            print(f"{n:>8} failed (exit {code}, peak RSS {rss:.0f} MB): {out[-2000:]}")
            continue
        _, schemas, ground_n, size, *stages = line.split()
        rows = [(name, *value.split(":")) for name, value in
                (s.split("=") for s in stages if not s.startswith("narrowed"))]
        if "narrowed=False" in stages:
            print(f"  note: the generator no longer has {NARROW[0]!r}; measured as generated")
        for i, (name, sec, peak) in enumerate(rows):
            done = int(name[6:]) if name.startswith("check@") else int(schemas)
            rate = done / max(float(sec), 1e-9)
            extra = f" {int(size) / 1e6:8.1f}" if name == "json" else ""
            print(f"{n if i == 0 else '':>8} {ground_n if i == 0 else '':>7} {name:<12} "
                  f"{float(sec):8.2f} {rate:10.0f} {float(peak):11.0f}{extra}")
        total = sum(float(sec) for _, sec, _ in rows[1:])
        print(f"{'':>8} {'':>7} {'after AST':<12} {total:8.2f} "
              f"{int(schemas) / max(total, 1e-9):10.0f} {rss:11.0f}   (lower + ground + json; "
              f"wall {wall:.1f} s)")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=3, help="p14 runs (median reported)")
    ap.add_argument("--sizes", default="2000,20000,165000",
                    help="comma-separated stamp domain sizes (actions)")
    ap.add_argument("--skip-p14", action="store_true")
    ap.add_argument("--replicate-from", type=int, default=0, metavar="M",
                    help="parse + check only an M-action file and copy its checked actions "
                         "up to each size (isolates lower/ground/JSON from the front end)")
    ap.add_argument("--child", type=int, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        stamp_child(args.child, args.replicate_from)
        return 0
    if not args.skip_p14:
        bench_p14(args.runs)
    sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    if sizes:
        bench_stamp(sizes, args.replicate_from)
    return 0


if __name__ == "__main__":
    sys.exit(main())
