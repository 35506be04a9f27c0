"""Joint-space motion planning with OMPL, and trajectory sweeps.

A trajectory has three stretches (see :class:`~.values.Traj`): a straight back-off from
the last contact, the planned middle, and a straight approach to the goal. Contacts that
are part of the task (the held object resting on its support, the fingers around the
target or the just-released object) are tolerated in the first and last stretch only.

Planning is deterministic for a given ``rng``: OMPL's global seed is set from it and the
search is bounded by a number of validity checks (a wall-clock limit is only a guard).
"""

from __future__ import annotations

import random
import time
from dataclasses import dataclass
from typing import Callable, Sequence

from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.pybullet.values import Config, Traj, interpolate
from stampc.worlds.pybullet.world import CLEARANCE, PyBulletWorld

PLAN_RESOLUTION = 0.05  # rad: OMPL's longest valid segment
#: rad: the final check of a trajectory, the ``collision`` evaluator's sweeps and
#: ``stampc execute``'s re-check (10× the planning resolution, as in every world): a
#: graze thinner than a coarser final check passed refinement and failed execution
#: (0.13 mm, cluttered-15 seed 3); a refined trajectory is now clear at every
#: configuration execution tests.
CHECK_RESOLUTION = PLAN_RESOLUTION / 10
#: OMPL geometric planners selectable with the ``planner`` option
PLANNERS = ("RRTConnect", "RRT", "KPIECE1", "BKPIECE1", "LBKPIECE1", "PRM", "RRTstar",
            "BITstar")


def planner_class(name: str) -> Callable:
    if name not in PLANNERS or not hasattr(og, name):
        raise StampcError([error("PB020", f"unknown OMPL planner {name!r}",
                                 Span.point("<options>"),
                                 f"choose one of: {', '.join(PLANNERS)}")])
    return getattr(og, name)


@dataclass(frozen=True)
class PlanSettings:
    planner: str = "RRTConnect"
    max_checks: int = 20000
    time_limit: float = 5.0
    static_only: bool = False
    #: try the straight segment before searching (off for alternative paths)
    straight: bool = True
    #: greedily drop waypoints whose neighbours see each other
    shortcut: bool = True


@dataclass
class PlanStats:
    """Accumulated figures for benchmarks."""

    queries: int = 0
    solved: int = 0
    plan_time: float = 0.0
    check_time: float = 0.0
    checks: int = 0


# ------------------------------------------------------------------ per-config checks
def bad_bodies(world: PyBulletWorld, q: Sequence[float], stretch: str,
               held: str | None, target: str | None, released: str | None,
               clearance: float = CLEARANCE) -> frozenset[int]:
    """Bodies hit at ``q`` that count as collisions in the given stretch
    (``"retreat"``, ``"middle"`` or ``"approach"``); planning keeps ``clearance`` from
    movable objects, execution's re-check passes 0."""
    robot_hits, held_hits = world.hits(q, stretch, clearance)
    if stretch == "retreat":
        robot_hits = robot_hits - _ids(world, released)
        held_hits = held_hits - world.static_ids
    elif stretch == "approach":
        robot_hits = robot_hits - _ids(world, target)
        if held is not None:
            held_hits = held_hits - world.static_ids
    return robot_hits | held_hits


def _ids(world: PyBulletWorld, name: str | None) -> frozenset[int]:
    return frozenset() if name is None or name not in world.body else frozenset({world.body[name]})


def counts(world: PyBulletWorld, bodies: frozenset[int], static_only: bool) -> bool:
    """Whether ``bodies`` contains a collision for the chosen obstacle set."""
    return bool(bodies - world.movable_ids) if static_only else bool(bodies)


def stretches(traj: Traj) -> list[tuple[str, tuple[float, ...], tuple[float, ...]]]:
    """Consecutive waypoint pairs labelled with their stretch."""
    out = []
    for i, (a, b) in enumerate(zip(traj.configs, traj.configs[1:])):
        if i < traj.retreat_end:
            kind = "retreat"
        elif i >= traj.approach_start:
            kind = "approach"
        else:
            kind = "middle"
        out.append((kind, a, b))
    return out


def sweep(world: PyBulletWorld, traj: Traj, resolution: float = CHECK_RESOLUTION,
          stop_on_hit: bool = False, static_only: bool = False) -> frozenset[int]:
    """All bodies the trajectory hits, checked every ``resolution`` radians."""
    hit: set[int] = set()
    for kind, a, b in stretches(traj) or [("middle", traj.start, traj.start)]:
        for q in interpolate(a, b, resolution):
            bodies = bad_bodies(world, q, kind, traj.held, traj.target, traj.released)
            if stop_on_hit and counts(world, bodies, static_only):
                return frozenset(bodies)
            hit |= bodies
    return frozenset(hit)


# ------------------------------------------------------------------ OMPL
def plan_path(world: PyBulletWorld, start: Sequence[float], goal: Sequence[float],
              rng: random.Random, settings: PlanSettings,
              stats: PlanStats | None = None) -> list[tuple[float, ...]] | None:
    """A collision-free joint path from ``start`` to ``goal`` (middle stretch rules)."""
    held = world.state.held
    dim = len(start)
    budget = {"checks": 0, "time": 0.0}

    def is_free(q: Sequence[float]) -> bool:
        t0 = time.perf_counter()
        budget["checks"] += 1
        bodies = bad_bodies(world, q, "middle", held, None, None)
        budget["time"] += time.perf_counter() - t0
        return not counts(world, bodies, settings.static_only)

    t_start = time.perf_counter()
    path = _ompl_solve(world, start, goal, dim, is_free, rng, settings, budget, t_start)
    if stats is not None:
        stats.queries += 1
        stats.solved += path is not None
        stats.plan_time += time.perf_counter() - t_start
        stats.check_time += budget["time"]
        stats.checks += budget["checks"]
    return path


def _ompl_solve(world: PyBulletWorld, start: Sequence[float], goal: Sequence[float], dim: int,
                is_free: Callable[[Sequence[float]], bool], rng: random.Random,
                settings: PlanSettings, budget: dict, t_start: float
                ) -> list[tuple[float, ...]] | None:
    if not (is_free(start) and is_free(goal)):
        return None
    level = ou.getLogLevel()
    ou.setLogLevel(ou.LOG_NONE)  # re-seeding after the first RNG warns; it still works
    ou.RNG.setSeed(rng.randrange(1, 2**31))
    ou.setLogLevel(ou.LOG_WARN if world.verbose else ou.LOG_ERROR)
    try:
        space = ob.RealVectorStateSpace(dim)
        bounds = ob.RealVectorBounds(dim)
        for i, (lo, hi) in enumerate(zip(world.lower, world.upper)):
            bounds.setLow(i, lo)
            bounds.setHigh(i, hi)
        space.setBounds(bounds)
        ss = og.SimpleSetup(space)
        ss.setStateValidityChecker(lambda s: is_free([s[i] for i in range(dim)]))
        si = ss.getSpaceInformation()
        si.setStateValidityCheckingResolution(PLAN_RESOLUTION / space.getMaximumExtent())
        a, b = space.allocState(), space.allocState()
        for i in range(dim):
            a[i], b[i] = start[i], goal[i]
        ss.setStartAndGoalStates(a, b)
        si.setup()
        if settings.straight and si.checkMotion(a, b):  # usually free on a tabletop
            return [tuple(start), tuple(goal)]
        ss.setPlanner(planner_class(settings.planner)(si))
        ss.setup()

        def stop() -> bool:
            return (budget["checks"] >= settings.max_checks
                    or time.perf_counter() - t_start > settings.time_limit)

        solved = ss.solve(ob.PlannerTerminationCondition(stop))
        if not solved or not ss.haveExactSolutionPath():
            return None
        path = ss.getSolutionPath()
        waypoints = [tuple(path.getState(k)[i] for i in range(dim))
                     for k in range(path.getStateCount())]
        return shortcut(waypoints, is_free) if settings.shortcut else waypoints
    finally:
        ou.setLogLevel(level)


def shortcut(path: list[tuple[float, ...]], is_free: Callable[[Sequence[float]], bool],
             resolution: float = PLAN_RESOLUTION) -> list[tuple[float, ...]]:
    """Greedy shortcutting: from each kept waypoint jump to the farthest one reachable
    in a straight line (cheaper than OMPL's simplifier, which costs more than planning)."""
    out = [path[0]]
    i = 0
    while i < len(path) - 1:
        j = len(path) - 1
        while j > i + 1 and not all(is_free(q) for q in interpolate(path[i], path[j],
                                                                     resolution)[1:-1]):
            j -= 1
        out.append(path[j])
        i = j
    return out


# ------------------------------------------------------------------ whole trajectories
def plan_trajectory(world: PyBulletWorld, goal: Config, rng: random.Random,
                    settings: PlanSettings, stats: PlanStats | None = None) -> Traj | None:
    """Back off, plan, approach: a trajectory from the current state to ``goal``.

    Returns ``None`` if a straight stretch collides or the planner fails; the result is
    rechecked at :data:`CHECK_RESOLUTION` (OMPL's 0.05 rad checks occasionally miss).
    """
    planned = plan_swept(world, goal, rng, settings, stats)
    return None if planned is None else planned[0]


def plan_swept(world: PyBulletWorld, goal: Config, rng: random.Random,
               settings: PlanSettings, stats: PlanStats | None = None
               ) -> tuple[Traj, frozenset[int]] | None:
    """:func:`plan_trajectory`, with every body the returned trajectory hits (what
    ``sweep(world, traj)`` gives in this state: empty unless ``settings.static_only``).

    Every configuration is checked once at :data:`CHECK_RESOLUTION`: the straight
    stretches before planning, the planned middle after it. A static-only path's
    sweep does not stop at a movable object, so the bodies met are all of them — the
    ``collision`` evaluator takes them as they are rather than sweeping the path again
    (it did, at 13 % of a cluttered-25 run)."""
    state = world.state
    head = [state.q] + ([state.retreat] if state.retreat is not None else [])
    tail = ([goal.pre] if goal.pre is not None else []) + [goal.q]
    target = goal.obj if goal.obj != state.held else None
    skeleton = Traj(tuple(head + tail), state.held, target, state.released,
                    retreat_end=len(head) - 1, approach_start=len(head))
    hit: set[int] = set()
    for kind, a, b in stretches(skeleton):
        if kind == "middle":
            continue
        bodies = sweep(world, Traj((a, b), state.held, target, state.released, **_marks(kind)),
                       stop_on_hit=True, static_only=settings.static_only)
        if counts(world, bodies, settings.static_only):
            return None
        hit |= bodies
    middle = plan_path(world, head[-1], tail[0], rng, settings, stats)
    if middle is None:
        return None
    configs = tuple(head + middle[1:-1] + tail)
    arm = world.active_arm
    traj = Traj(configs, state.held, target, state.released, retreat_end=len(head) - 1,
                approach_start=len(configs) - len(tail), static_only=settings.static_only,
                robot=arm.name if arm else None, base=world.base_pose())
    planned = Traj(configs[traj.retreat_end:traj.approach_start + 1], state.held, target,
                   state.released)  # the middle stretch alone: the rest was swept above
    bodies = sweep(world, planned, stop_on_hit=True, static_only=settings.static_only)
    world.set_arm(state.q)
    if counts(world, bodies, settings.static_only):
        return None
    return traj, frozenset(hit | bodies)


def _marks(kind: str) -> dict:
    return {"retreat_end": 1, "approach_start": 2} if kind == "retreat" else \
        {"retreat_end": 0, "approach_start": 0}
