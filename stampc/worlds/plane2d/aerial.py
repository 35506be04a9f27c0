"""Bound functions of aerial (UAV inspection) domains on the plane2d world.

The UAV is a disc of radius ``uav.radius`` flying over the workspace; static obstacle
boxes (and any object on the table) are no-fly zones. Its battery drains by the length
of every path flown.

- generator :func:`fly` (region → pose, path), evaluator :func:`has_battery`
- executors :func:`fly_to`, :func:`charge`, :func:`inspect`, :func:`drive` (outcome-aware)
"""

from __future__ import annotations

import math
from typing import Any, Iterator

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.base import ConcreteAction, Context, Outcome
from stampc.worlds.plane2d.geometry import EPS
from stampc.worlds.plane2d.planning import Checker, rrt_connect
from stampc.worlds.plane2d.support import arg, int_option, world_of
from stampc.worlds.plane2d.values import Pose2, Traj2, as_traj
from stampc.worlds.plane2d.world import Plane2DWorld


def _require_uav(world: Plane2DWorld):
    if world.scene.uav is None or world.uav is None:
        raise StampcError([error("S275", "plane2d: this scene has no UAV",
                                 Span.point("<scene>"),
                                 hint='add "uav": {"start": region, "battery": B, "radius": r}')])
    return world.scene.uav


def uav_checker(world: Plane2DWorld) -> Checker:
    """Obstacles for the UAV disc; no reach limit (it is not arm-mounted)."""
    spec = _require_uav(world)
    return world.checker(footprints=(((0.0, 0.0), spec.radius),), reach=math.inf)


def fly(ctx: Context, r: str) -> Iterator[tuple[Pose2, Traj2]]:
    """Poses inside region ``r`` (UAV disc fully inside, clear of obstacles) with a path
    from the UAV's position: straight if free, else seeded RRT-Connect."""
    world = world_of(ctx)
    spec = _require_uav(world)
    rect = world.region(r)
    budget = int_option(ctx, "budget", 4)
    tries = int_option(ctx, "tries", 50)
    iterations = int_option(ctx, "iterations", 400)
    checker = uav_checker(world)
    start = world.uav
    x0, x1 = rect.x0 + spec.radius, rect.x1 - spec.radius
    y0, y1 = rect.y0 + spec.radius, rect.y1 - spec.radius
    if x0 > x1 or y0 > y1:
        return
    found = 0
    for _ in range(tries * budget):
        goal = (ctx.rng.uniform(x0, x1), ctx.rng.uniform(y0, y1))
        if not checker.point_free(goal):
            continue
        path = rrt_connect(start, goal, checker, ctx.rng, iterations=iterations)
        if path is None:
            continue
        yield Pose2(goal[0], goal[1], 0.0), Traj2(tuple(path), None, r)
        found += 1
        if found >= budget:
            return


def has_battery(ctx: Context, t: Any) -> bool:
    """The path of ``t`` is no longer than the battery left in the current state."""
    world = world_of(ctx)
    _require_uav(world)
    return as_traj(t).length <= world.battery + EPS


def _planned_region(world: Plane2DWorld, action: ConcreteAction, t: Traj2) -> str | None:
    for key in ("r", "to"):
        value = action.args.get(key)
        if isinstance(value, str) and world.scene.region(value) is not None:
            return value
    return t.target


def fly_to(ctx: Context, action: ConcreteAction) -> None:
    """Fly along ``t`` (draining the battery by its length). If the outcome puts the UAV
    in another region than planned (drift), it ends at that region's centre."""
    world = world_of(ctx)
    _require_uav(world)
    t = arg(action, "t", as_traj)
    planned = _planned_region(world, action, t)
    end = t.end
    added = [a for _, args in action.adds for a in args
             if isinstance(a, str) and world.scene.region(a) is not None]
    if added and planned not in added:
        end = world.region(added[0]).centre
    world.set_uav(end, world.battery - t.length, trace=t.points + (end,))


def drive(ctx: Context, action: ConcreteAction, outcome: Outcome) -> None:
    """Outcome-aware move of the mobile robot (the ``uav`` disc) along ``t``: it drives
    (the battery drains by the path length) only if the sampled outcome moves it, i.e.
    adds a fact about the planned region; any other outcome (a slip) leaves it in place.
    """
    world = world_of(ctx)
    _require_uav(world)
    t = arg(action, "t", as_traj)
    planned = _planned_region(world, action, t)
    if not any(planned in args for _, args in outcome.adds):
        return  # slipped: the concrete state stays as it was
    world.set_uav(t.end, world.battery - t.length, trace=t.points)


def charge(ctx: Context, action: ConcreteAction) -> None:
    """Refill the battery to its capacity."""
    world = world_of(ctx)
    spec = _require_uav(world)
    world.set_uav(world.uav, spec.battery)


def inspect(ctx: Context, action: ConcreteAction) -> None:
    """Inspection changes nothing in the geometry (its outcome is symbolic)."""
    world_of(ctx)
