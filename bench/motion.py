"""Speed figures of the PyBullet + OMPL world (issue #6).

Prints: collision checks per second, OMPL planning median time and success rate among
15 and 25 cans, IK success rate on tabletop grasps, the share of planning time spent in
collision checks, snapshot/restore vs PyBullet's saveState, and the average time per
generator call. Run: ``python bench/motion.py [--queries N] [--seeds K]``.
"""

from __future__ import annotations

import argparse
import random
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from stampc.worlds.base import Context  # noqa: E402
from stampc.worlds.pybullet import manipulation as manip  # noqa: E402
from stampc.worlds.pybullet import open_world  # noqa: E402
from stampc.worlds.pybullet._pb import p  # noqa: E402
from stampc.worlds.pybullet.kinematics import grasp_candidates, solve_ik  # noqa: E402
from stampc.worlds.pybullet.planning import PlanSettings, PlanStats, plan_path  # noqa: E402
from stampc.worlds.pybullet.scenes import cluttered_table  # noqa: E402


def collision_rate(world, n: int = 20000) -> float:
    rng = random.Random(0)
    qs = [tuple(rng.uniform(lo, hi) for lo, hi in zip(world.lower, world.upper))
          for _ in range(n)]
    t0 = time.perf_counter()
    for q in qs:
        world.hits(q)
    rate = n / (time.perf_counter() - t0)
    world.set_arm(world.state.q)
    return rate


def ik_success(world, rng: random.Random) -> tuple[int, int, float]:
    ok = total = 0
    times = []
    for name, pose in world.state.poses:
        for g in grasp_candidates(world.geometry[name], rng, "top"):
            total += 1
            t0 = time.perf_counter()
            ok += solve_ik(world, pose.multiply(g.hand), rng) is not None
            times.append(time.perf_counter() - t0)
    world.set_arm(world.state.q)
    return ok, total, statistics.median(times)


def grasp_configs(world, rng: random.Random) -> list:
    configs = []
    for name, pose in world.state.poses:
        ctx = Context(world=world, rng=rng, options={"budget": 1, "grasps": "top"})
        configs += [q for _, q in manip.grasp(ctx, name, pose)]
    return configs


def planning(world, configs: list, queries: int, rng: random.Random, straight: bool):
    """grasp→grasp queries between pre-grasp configs, movable objects as obstacles.

    Pre-grasp configs are only checked against static obstacles by the grasp generator;
    pairs whose ends touch a can are skipped (no planner could solve them)."""
    stats = PlanStats()
    times = []
    valid = [c for c in configs if not any(world.hits(c.pre))]
    for _ in range(queries):
        a, b = rng.sample(valid, 2)
        t0 = time.perf_counter()
        plan_path(world, a.pre, b.pre, rng, PlanSettings(straight=straight), stats)
        times.append(time.perf_counter() - t0)
    world.set_arm(world.state.q)
    return stats, times


def generator_calls(world, rng: random.Random, n: int) -> dict[str, float]:
    out: dict[str, list[float]] = {"grasp (first)": [], "grasp (all)": [],
                                   "placement (first)": [], "motion (first)": []}
    names = [name for name, _ in world.state.poses]
    for _ in range(n):
        name = rng.choice(names)
        pose = world.object_pose(name)
        ctx = Context(world=world, rng=random.Random(rng.random()))
        t0 = time.perf_counter()
        gen = manip.grasp(ctx, name, pose)
        first = next(gen, None)
        out["grasp (first)"].append(time.perf_counter() - t0)
        list(gen)
        out["grasp (all)"].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        next(manip.placement(Context(world=world, rng=ctx.rng), name, "table"), None)
        out["placement (first)"].append(time.perf_counter() - t0)
        if first is not None:
            t0 = time.perf_counter()
            next(manip.motion(Context(world=world, rng=ctx.rng), first[1]), None)
            out["motion (first)"].append(time.perf_counter() - t0)
    return {k: statistics.mean(v) for k, v in out.items() if v}


def snapshot_cost(world, n: int = 2000) -> tuple[float, float]:
    """Mean cost of snapshot + restore between two states differing in the arm and one
    object's pose, against PyBullet's saveState/restoreState doing the same."""
    s0 = world.snapshot()
    name = world.state.poses[0][0]
    pose = world.object_pose(name)
    world.update(q=tuple(v + 0.2 for v in s0.q),
                 poses=world.with_object_pose(name, type(pose).of(
                     (pose.pos[0], pose.pos[1] + 0.01, pose.pos[2]))))
    s1 = world.snapshot()
    t0 = time.perf_counter()
    for i in range(n):
        world.snapshot()
        world.restore(s0 if i % 2 else s1)
    ours = (time.perf_counter() - t0) / n
    world.restore(s0)
    ids = [p.saveState(physicsClientId=world.client)]
    world.restore(s1)
    ids.append(p.saveState(physicsClientId=world.client))
    t0 = time.perf_counter()
    for i in range(n):
        p.restoreState(stateId=ids[i % 2], physicsClientId=world.client)
    restore = (time.perf_counter() - t0) / n
    t0 = time.perf_counter()
    extra = [p.saveState(physicsClientId=world.client) for _ in range(200)]
    save = (time.perf_counter() - t0) / 200
    for sid in ids + extra:
        p.removeState(sid, physicsClientId=world.client)
    world.restore(s0)
    return ours, save + restore


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--queries", type=int, default=20, help="planning queries per scene")
    parser.add_argument("--seeds", type=int, default=3, help="scenes per can count")
    args = parser.parse_args()
    for n_cans in (15, 25):
        ik_ok = ik_total = 0
        ik_times, solved, total, med_times, med_straight = [], 0, 0, [], []
        share_checks = share_time = 0.0
        check_count = 0
        rates, gens = [], []
        snap = (0.0, 0.0)
        for seed in range(args.seeds):
            world = open_world(cluttered_table(n_cans, seed), seed=seed)
            rng = random.Random(seed)
            rates.append(collision_rate(world, 5000))
            ok, tot, med = ik_success(world, rng)
            ik_ok, ik_total = ik_ok + ok, ik_total + tot
            ik_times.append(med)
            configs = grasp_configs(world, rng)
            stats, times = planning(world, configs, args.queries, rng, straight=False)
            solved, total = solved + stats.solved, total + stats.queries
            med_times += times
            share_checks += stats.check_time
            share_time += stats.plan_time
            check_count += stats.checks
            _, times_s = planning(world, configs, args.queries, rng, straight=True)
            med_straight += times_s
            gens.append(generator_calls(world, rng, 5))
            if seed == 0:
                snap = snapshot_cost(world)
            world.close()
        print(f"== {n_cans} cans ({args.seeds} scenes) ==")
        print(f"collision checks/s        : {statistics.mean(rates):,.0f} (random configs,"
              f" many self-contacts); inside the planner: "
              f"{check_count / max(share_checks, 1e-9):,.0f}")
        print(f"IK success (top grasps)   : {ik_ok}/{ik_total} = {ik_ok / ik_total:.1%}"
              f"  (median {statistics.median(ik_times) * 1e3:.2f} ms per solve)")
        print(f"RRTConnect grasp->grasp   : solved {solved}/{total} = {solved / total:.1%},"
              f" median {statistics.median(med_times) * 1e3:.1f} ms"
              f" (straight-line shortcut on: median {statistics.median(med_straight) * 1e3:.1f} ms)")
        print(f"planning time in checks   : {share_checks / max(share_time, 1e-9):.1%}")
        print(f"snapshot+restore          : {snap[0] * 1e6:.0f} us"
              f" (PyBullet saveState+restoreState: {snap[1] * 1e6:.0f} us)")
        for key in gens[0]:
            mean = statistics.mean(g[key] for g in gens if key in g)
            print(f"{'avg ' + key:<26}: {mean * 1e3:.1f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
