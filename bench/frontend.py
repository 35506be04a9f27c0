"""Front-end speed: parse and check generated domains; throughput at several sizes.

Usage: ``python bench/frontend.py [--sizes 2000,20000,165000] [--shape small|pick|stress]``
(one child process per size, so each peak RSS is its own), or ``--actions N`` for one
size in this process with ``--repeat R`` (best of R).

Per size it prints parse and parse + check wall and CPU seconds, throughput (actions/s
and MB/s of source) and the peak resident memory of the process: a cost that grows
faster than the input shows up as falling throughput. Issue 10's target: the 10 MB,
165,000-action ``small`` file parsed and checked in <= 60 s and <= 1 GB.
Shapes: ``small`` (~62 bytes/action: one precondition, two effects; 165,000 actions make
10 MB), ``pick`` (shaped like the stdlib's pick, ~95 tokens), ``stress`` (~175 tokens:
two probabilistic blocks, a conditional, quantifiers).
"""

from __future__ import annotations

import argparse
import gc
import os
import resource
import subprocess
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


SMALL_HEADER = """domain bench
type block
predicate p(o: block)
predicate q(o: block)
"""

SMALL = """action a_{i}(o: block)
    pre  p(o)
    eff  not p(o), q(o)
"""

SHAPES = {"small": (SMALL_HEADER, SMALL), "pick": (HEADER, PICK), "stress": (HEADER, ACTION)}


def generate(actions: int, shape: str = "stress") -> str:
    header, template = SHAPES[shape]
    return header + "".join(template.format(i=i) for i in range(actions))


def best(fn, repeat: int) -> tuple[float, float]:
    walls, cpus = [], []
    for _ in range(repeat):
        gc.collect()
        w, c = time.perf_counter(), time.process_time()
        fn()
        walls.append(time.perf_counter() - w)
        cpus.append(time.process_time() - c)
    return min(walls), min(cpus)


def peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB on Linux


def rates(actions: int, megabytes: float, wall: float, cpu: float) -> str:
    """Throughput by wall time and by CPU time (on a loaded machine only the latter is
    comparable between sizes)."""
    return (f"{actions / wall:7.0f} actions/s {megabytes / wall:5.2f} MB/s wall, "
            f"{actions / cpu:7.0f} actions/s {megabytes / cpu:5.2f} MB/s cpu")


def measure(actions: int, shape: str, repeat: int) -> int:
    """One size in this process: parse, then parse + check; prints one block."""
    text = generate(actions, shape)
    megabytes = len(text.encode("utf-8")) / 1e6
    tables()
    print(f"{actions} {shape} actions, {text.count(chr(10))} lines, {megabytes:.1f} MB")
    wall, cpu = best(lambda: parse_source(text, "bench.stamp"), repeat)
    print(f"  parse:         {wall:7.2f} s wall {cpu:7.2f} s cpu  {rates(actions, megabytes, wall, cpu)}")
    diags: list = []
    wall, cpu = best(lambda: diags.append(check(text)), repeat)
    errors = [d for d in diags[-1] if d.is_error]
    print(f"  parse + check: {wall:7.2f} s wall {cpu:7.2f} s cpu  {rates(actions, megabytes, wall, cpu)}  "
          f"peak RSS {peak_rss_mb():.0f} MB "
          f"({len(diags[-1])} diagnostics, {len(errors)} errors)")
    return 1 if errors else 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="2000,20000,165000",
                    help="comma-separated action counts, one child process each")
    ap.add_argument("--actions", type=int, help="one size, measured in this process")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--shape", choices=tuple(SHAPES), default="small")
    args = ap.parse_args()
    if args.actions is not None:
        return measure(args.actions, args.shape, args.repeat)
    w, c = time.perf_counter(), time.process_time()
    tables()
    print(f"parser tables (once per process): {time.perf_counter() - w:.3f} s wall, "
          f"{time.process_time() - c:.3f} s cpu")
    status = 0
    for size in args.sizes.split(","):
        cmd = [sys.executable, __file__, "--actions", size, "--shape", args.shape,
               "--repeat", str(args.repeat)]
        status |= subprocess.run(cmd, check=False).returncode
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores (wall times grow "
          "with load; cpu times less so)")
    return status


if __name__ == "__main__":
    sys.exit(main())
