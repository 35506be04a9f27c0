"""Front-end speed: parse and check a generated domain with 2,000 actions.

Usage: ``python bench/frontend.py [--actions N] [--repeat R] [--shape stress|pick]``.
Prints wall-clock and CPU seconds for building the parser tables (once per process),
parsing alone, and ``check`` (parse + names + types + lints), best of R runs.
Target: parse + check < 1 s. ``stress`` actions (default, ~175 tokens: two
probabilistic blocks, a conditional, quantifiers) are about twice the size of the
stdlib's ``pick``; ``pick`` generates actions shaped like it (~95 tokens).
"""

from __future__ import annotations

import argparse
import gc
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from stampc.semantics.api import check  # noqa: E402
from stampc.syntax.parser import parse_source, tables  # noqa: E402

HEADER = """domain bench
use manipulation

type block < movable
type region
static predicate adjacent(a: region, b: region)
static predicate fragile(o: block)
predicate in_region(o: block, r: region)
predicate broken(o: block)
predicate inspected(o: block)
"""

ACTION = """
action move_{i}(o: block, a: region, b: region, p: pose, g: grasp, q: config, t: traj)
    pre  handempty, at(o, p), in_region(o, a), adjacent(a, b),
         can_grasp(o, p, g, q), motion_to(q, t),
         forall (x: movable) not collision(x, t), not broken(o)
    eff  not in_region(o, a), not inspected(o)
         ? forall (t2: traj) collision(o, t2)
         when fragile(o): probabilistic 1/10 as broken: broken(o)
         probabilistic
             0.9 as moved: in_region(o, b)
             0.1 as slipped: in_region(o, a), cost 2
    cost 1
    executes ".manipulation:pick"
"""


PICK = """
action pick_{i}(o: block, p: pose, g: grasp, q: config, t: traj)
    pre  handempty, at(o, p), can_grasp(o, p, g, q), motion_to(q, t),
         forall (x: movable) not collision(x, t)
    eff  holding(o), not handempty, not at(o, p),
         ? forall (t2: traj) collision(o, t2)
    executes ".manipulation:pick"
"""


def generate(actions: int, shape: str = "stress") -> str:
    template = ACTION if shape == "stress" else PICK
    return HEADER + "".join(template.format(i=i) for i in range(actions))


def best(fn, repeat: int) -> tuple[float, float]:
    walls, cpus = [], []
    for _ in range(repeat):
        gc.collect()
        w, c = time.perf_counter(), time.process_time()
        fn()
        walls.append(time.perf_counter() - w)
        cpus.append(time.process_time() - c)
    return min(walls), min(cpus)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--actions", type=int, default=2000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--shape", choices=("stress", "pick"), default="stress")
    args = ap.parse_args()
    text = generate(args.actions, args.shape)
    w, c = time.perf_counter(), time.process_time()
    tables()
    print(f"parser tables (once per process): {time.perf_counter() - w:.3f} s wall, "
          f"{time.process_time() - c:.3f} s cpu")
    lines = text.count("\n")
    print(f"domain: {args.actions} {args.shape} actions, {lines} lines, {len(text) / 1e3:.0f} kB")
    wall, cpu = best(lambda: parse_source(text, "bench.stamp"), args.repeat)
    print(f"parse:          {wall:.3f} s wall, {cpu:.3f} s cpu")
    diags: list = []
    wall, cpu = best(lambda: diags.append(check(text)), args.repeat)
    errors = [d for d in diags[-1] if d.is_error]
    print(f"parse + check:  {wall:.3f} s wall, {cpu:.3f} s cpu "
          f"({len(diags[-1])} diagnostics, {len(errors)} errors)")
    w, c = time.perf_counter(), time.process_time()
    gc.collect()
    print(f"deferred GC pass over the new objects: {time.perf_counter() - w:.3f} s wall")
    print(f"target: parse + check < 1 s -> wall {'met' if wall < 1.0 else 'NOT met'}, "
          f"cpu {'met' if cpu < 1.0 else 'NOT met'} (best of {args.repeat}; "
          f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
