"""Benchmark of the plane2d world: collision checks per second and generator call times.

Run from the repository root:  python bench/plane2d.py [--objects N] [--repeat K]
Prints figures only (no pass/fail thresholds).
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
from stampc.worlds.plane2d import Traj2, open_world  # noqa: E402
from stampc.worlds.plane2d import manipulation as m  # noqa: E402
from stampc.worlds.plane2d.scenes import cluttered  # noqa: E402


def _rate(fn, seconds: float = 0.5) -> tuple[float, int]:
    n, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        fn()
        n += 1
    return n / (time.perf_counter() - start), n


def _times(make_call, repeat: int) -> str:
    samples = []
    for k in range(repeat):
        start = time.perf_counter()
        make_call(k)
        samples.append((time.perf_counter() - start) * 1e3)
    return (f"median {statistics.median(samples):7.2f} ms   max {max(samples):7.2f} ms   "
            f"(n={repeat})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=12)
    parser.add_argument("--repeat", type=int, default=20)
    args = parser.parse_args()

    world = open_world(cluttered(args.objects, 0, blockers=2), seed=0)
    shelf = open_world(cluttered(args.objects, 0, blockers=2, shelf=True), seed=0)
    rng = random.Random(0)
    ctx = Context(world, rng)
    _, q = next(m.grasp(ctx, "can0", world.pose("can0")))
    checker = world.checker(exclude=("can0",))
    a, b = world.gripper, q.xy
    print(f"plane2d bench: {args.objects} cans on the table")

    free_end = (0.2, 0.2)
    assert checker.segment_free(a, free_end) and not checker.segment_free(a, b)
    rate, _ = _rate(lambda: checker.segment_free(a, free_end))
    print(f"  {f'free segment checks (vs all {args.objects - 1} objects)':<46}{rate:10.0f} /s")
    rate, _ = _rate(lambda: checker.segment_free(a, b))
    print(f"  {'blocked segment checks (early exit)':<46}{rate:10.0f} /s")
    rng_pts = random.Random(1)
    polylines = [tuple(checker.sample(rng_pts) for _ in range(6)) for _ in range(64)]
    i = iter(range(10**9))
    rate, _ = _rate(lambda: checker.blockers(polylines[next(i) % 64]))
    print(f"  {'polyline blocking sets (numpy, 5 segments)':<46}{rate:10.0f} /s")
    j = iter(range(10**9))
    # fresh cache each time: measures the evaluator itself, not the memo
    rate, _ = _rate(lambda: m.collision(Context(world, rng), "can1",
                                        Traj2(polylines[next(j) % 64], None, None)))
    print(f"  {'collision evaluator calls (uncached)':<46}{rate:10.0f} /s")

    def first(gen):
        return next(iter(gen), None)

    print("  grasp (all candidates):      " + _times(
        lambda k: list(m.grasp(Context(world, random.Random(k)), "can0", world.pose("can0"))),
        args.repeat))
    print("  placement (first, tray):     " + _times(
        lambda k: first(m.placement(Context(world, random.Random(k)), "can3", "tray")),
        args.repeat))
    free_q = m.Config2(*free_end, None)
    print("  motion, straight line:       " + _times(
        lambda k: first(m.motion(Context(world, random.Random(k)), free_q)), args.repeat))
    print("  motion, RRT-Connect detour:  " + _times(
        lambda k: first(m.motion(Context(world, random.Random(k)), q)), args.repeat))
    _, q_shelf = next(m.grasp(Context(shelf, rng), "can0", shelf.pose("can0")))
    print("  motion, blocked -> fallback: " + _times(
        lambda k: first(m.motion(Context(shelf, random.Random(k), options={"budget": 2}),
                                 q_shelf)), args.repeat)
          + "  (2 failed RRTs x 400 iterations)")


if __name__ == "__main__":
    main()
