"""One benchmark run, in its own process: ``stampc refine ...`` plus work counters.

    python bench/paper_worker.py STATS.json refine DOMAIN PROBLEM --world pybullet ...

Runs the ``stampc`` command line in this process (compile, ground, build the scene,
refine, export: exactly what ``python -m stampc refine`` does) and writes the world's
work counters, which the command line does not report, to ``STATS.json``: collision
checks, motion-planner calls (arm joint-space queries and UAV flights) and the size of
the ground abstract model (actions, facts: the grounding's work, which grows with the
objects even where the refinement's does not). The counters are read by wrapping the
world's and the grounder's functions here, in the benchmark, not in the library.
"""

from __future__ import annotations

import json
import sys
import time

START = time.perf_counter()  # before stampc is imported: imports count as process time


def main(argv: list[str]) -> int:
    stats_path, args = argv[0], argv[1:]
    from stampc.ir import ground as grounding
    from stampc.worlds.pybullet import aerial, planning
    from stampc.worlds.pybullet import world as pbworld

    stats = {"collision_checks": 0, "planner_calls": 0, "worlds": 0, "ground_actions": 0,
             "ground_facts": 0}
    ground = grounding.ground
    close, plan_path, plan_flight = (pbworld.PyBulletWorld.close, planning.plan_path,
                                     aerial.plan_flight)

    def counted_close(self: pbworld.PyBulletWorld) -> None:
        if self.client >= 0:
            stats["collision_checks"] += self.checks
            stats["worlds"] += 1
        close(self)

    def counted_plan_path(*a, **k):  # type: ignore[no-untyped-def]
        stats["planner_calls"] += 1
        return plan_path(*a, **k)

    def counted_plan_flight(*a, **k):  # type: ignore[no-untyped-def]
        stats["planner_calls"] += 1
        return plan_flight(*a, **k)

    def counted_ground(*a, **k):  # type: ignore[no-untyped-def]
        model = ground(*a, **k)
        stats["ground_actions"] = max(stats["ground_actions"], len(model.actions))
        stats["ground_facts"] = max(stats["ground_facts"], len(model.facts))
        return model

    grounding.ground = counted_ground
    pbworld.PyBulletWorld.close = counted_close  # type: ignore[method-assign]
    planning.plan_path = counted_plan_path
    aerial.plan_flight = counted_plan_flight
    from stampc.cli import main as cli

    code = 2
    try:
        code = cli(args)
    finally:
        stats["in_process_s"] = time.perf_counter() - START
        stats["exit"] = code
        with open(stats_path, "w", encoding="utf-8") as fh:
            json.dump(stats, fh)
    return code


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
