"""Incremental vs from-scratch abstract re-solves after UpdateAbstraction.

Runs the engine on instances, records every re-solve that followed learned facts (the
state, the learned facts and the previous solution the engine warm-started from), then
times each one twice more: from scratch (fresh successor cache, heuristic and tables)
and incrementally (the engine's way: the previous tables, with values carried across the
learned facts). Prints per-update figures and the median speed-up.

    python bench/resolve.py                        # cluttered-25 (PyBullet) + Keva
    python bench/resolve.py --cluttered-seeds 0 1 2 --keva --cap 60
    python bench/resolve.py --plane2d              # quick: the 2-D cluttered table
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import stampc  # noqa: E402
from stampc.refine import Engine, RefineOptions  # noqa: E402
from stampc.solvers import solve  # noqa: E402
from stampc.worlds.bindings import resolve_model  # noqa: E402
from stampc.worlds.loading import load_scene, open_world  # noqa: E402


def updates_of(files: list[Path], world_name: str, seed: int, time_limit: float) -> tuple:
    """Run the engine; return (ground model, [(state, learned, warm solution, solution)])."""
    model = stampc.load_model(files)
    gm = stampc.ground(model)
    world = open_world(world_name, load_scene(model.problem, files[-1].parent), seed=seed)
    try:
        engine = Engine(gm, world, resolve_model(model, world.package),
                        RefineOptions(seed=seed, time_limit=time_limit))
        engine.planner.log = []
        for _ in engine.run():
            pass
    finally:
        world.close()
    log = [entry for entry in engine.planner.log if entry[1] is not None and entry[2] is not None]
    return engine.planner.solve_model, log, engine.result()


def setup_time(model, options) -> float:
    """What a from-scratch solve spends before searching: the successor cache and the
    relaxed model of its heuristic (model-level, reported apart so that the speed-up is
    not just this one-off cost)."""
    from stampc.solvers.heuristics import make_heuristic
    from stampc.solvers.successors import SuccessorCache
    t0 = time.perf_counter()
    SuccessorCache(model, options.unit_cost)
    make_heuristic(options.heuristic, model, options.unit_cost, options.weight)
    return time.perf_counter() - t0


def compare(model, entry, cap: float) -> dict:
    """Time one logged re-solve from scratch and incrementally (same options, cap)."""
    state, learned, warm, logged = entry
    opts = replace(logged.options, time_limit=cap)
    t0 = time.perf_counter()
    scratch = solve(model, opts, init=state)
    t1 = time.perf_counter()
    incremental = solve(model, opts, init=state, warm=warm, learned=learned)
    t2 = time.perf_counter()
    return {"scratch_s": t1 - t0, "scratch_converged": scratch.converged,
            "scratch_expanded": scratch.states_expanded, "scratch_goal": scratch.goal_probability,
            "inc_s": t2 - t1, "inc_converged": incremental.converged,
            "inc_expanded": incremental.states_expanded, "inc_goal": incremental.goal_probability}


def _median_big(rows: list[dict]) -> str:
    big = [r["scratch_s"] / max(r["inc_s"], 1e-6) for r in rows if r["scratch_s"] >= 0.5]
    return f"{statistics.median(big):.1f}x ({len(big)} re-solves)" if big else "n/a"


def instances(args) -> list[tuple[str, list[Path], str, int]]:
    out = []
    tmp = Path(tempfile.mkdtemp(prefix="resolve-bench-"))
    if args.plane2d:
        ex = ROOT / "examples" / "cluttered_table"
        for seed in args.cluttered_seeds:
            from examples.cluttered_table.scene import write_problem
            p = write_problem(tmp / f"c{args.n}_2d_{seed}.stamp", args.n, seed, "mid", world="plane2d")
            out.append((f"cluttered2d-{args.n} s{seed}", [ex / "domain.stamp", p], "plane2d", seed))
        return out
    ex = ROOT / "examples" / "cluttered_table"
    from examples.cluttered_table.scene import write_problem
    # --fixed: the fixed-base scene with its arranged blockers (domain_fixed.stamp), where
    # obstructions are learned on every seed; default: the paper's random scene
    world, domain = (("pybullet-fixed", "domain_fixed.stamp") if args.fixed
                     else ("pybullet", "domain.stamp"))
    for seed in args.cluttered_seeds:
        p = write_problem(tmp / f"c{args.n}_{seed}.stamp", args.n, seed, "mid", world=world)
        out.append((f"cluttered-{args.n} s{seed}", [ex / domain, p], "pybullet", seed))
    if args.keva:
        from examples.keva.scene import write_problem as keva_problem
        for structure, levels in args.keva_structures:
            p = keva_problem(tmp / f"keva_{structure}{levels}.stamp", structure=structure,
                             levels=levels, seed=0)
            out.append((f"keva-{structure}-{levels}", [ROOT / "examples" / "keva" / "domain.stamp", p],
                        "pybullet", 0))
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n", type=int, default=25)
    parser.add_argument("--cluttered-seeds", type=int, nargs="*", default=[0, 1, 2, 3, 4, 5])
    parser.add_argument("--keva", action=argparse.BooleanOptionalAction, default=True)
    parser.add_argument("--plane2d", action="store_true")
    parser.add_argument("--fixed", action="store_true",
                        help="the cluttered table's fixed-base scene with arranged blockers")
    parser.add_argument("--keva-structures", type=lambda v: (v.split(":")[0], int(v.split(":")[1])),
                        nargs="*", default=[("pi", 3), ("tower", 12)], metavar="STRUCTURE:LEVELS",
                        help="Keva instances (seed 0), e.g. pi:3 twisted:12 3towers:4")
    parser.add_argument("--time-limit", type=float, default=300.0, help="per engine run")
    parser.add_argument("--cap", type=float, default=60.0, help="per timed re-solve")
    args = parser.parse_args()
    rows = []
    print(f"{'instance':<22} {'#':>3} {'scratch s':>9} {'exp':>6} {'conv':>4} "
          f"{'incr. s':>8} {'exp':>6} {'conv':>4} {'speed-up':>8} {'w/o set-up':>10}")
    for name, files, world, seed in instances(args):
        model, log, result = updates_of(files, world, seed, args.time_limit)
        setup = setup_time(model, log[0][3].options) if log else 0.0
        for k, entry in enumerate(log):
            row = compare(model, entry, args.cap)
            row["name"] = name
            row["net_s"] = max(row["scratch_s"] - setup, 0.0)
            rows.append(row)
            speedup = row["scratch_s"] / max(row["inc_s"], 1e-6)
            net = row["net_s"] / max(row["inc_s"], 1e-6)
            print(f"{name:<22} {k:>3} {row['scratch_s']:>9.3f} {row['scratch_expanded']:>6} "
                  f"{'y' if row['scratch_converged'] else 'n':>4} {row['inc_s']:>8.3f} "
                  f"{row['inc_expanded']:>6} {'y' if row['inc_converged'] else 'n':>4} "
                  f"{speedup:>8.1f} {net:>10.1f}", flush=True)
        print(f"  {name}: engine coverage {result.coverage:.3f} in {result.wall_time_s:.1f} s, "
              f"{len(log)} learned-fact re-solves; scratch set-up {setup:.3f} s", flush=True)
    if rows:
        speedups = [r["scratch_s"] / max(r["inc_s"], 1e-6) for r in rows]
        nets = [r["net_s"] / max(r["inc_s"], 1e-6) for r in rows]
        print(f"\n{len(rows)} learned-fact re-solves: median scratch "
              f"{statistics.median(r['scratch_s'] for r in rows):.3f} s, median incremental "
              f"{statistics.median(r['inc_s'] for r in rows):.3f} s, median speed-up "
              f"{statistics.median(speedups):.1f}x (min {min(speedups):.1f}x, max "
              f"{max(speedups):.1f}x); scratch timed out {sum(not r['scratch_converged'] for r in rows)}, "
              f"incremental timed out {sum(not r['inc_converged'] for r in rows)}")
        print(f"without the scratch solves' model-level set-up: median speed-up "
              f"{statistics.median(nets):.1f}x; over the re-solves where scratch needs "
              f">= 0.5 s: median {_median_big(rows):s}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
