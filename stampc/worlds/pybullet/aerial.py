"""A free-flying UAV (an SE(3) box body) planning among boxes with OMPL.

Bindings: ``.aerial:fly`` (generator region → pose, trajectory), ``.aerial:has_battery``
(evaluator), ``.aerial:fly_to``, ``.aerial:charge`` and ``.aerial:inspect`` (executors). The UAV's remaining
battery is part of the concrete state (``WorldState.battery``, in metres of flight).
"""

from __future__ import annotations

import math
import random
import time
from typing import Iterator, Sequence

from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.pybullet._pb import p
from stampc.worlds.pybullet.planning import planner_class
from stampc.worlds.pybullet.values import Pose, Traj, as_traj, quat_from_yaw
from stampc.worlds.pybullet.world import PENETRATION, PyBulletWorld

FLY_RESOLUTION = 0.05  # m between checked poses (OMPL's motion check)
#: the resolution of the execution re-check (``stampc execute``: 10x finer); a planned
#: flight is swept at it before it is offered, so a grazing contact between two poses
#: OMPL checked never reaches a policy
EXEC_RESOLUTION = FLY_RESOLUTION / 10


def _world(ctx: Context) -> PyBulletWorld:
    world = ctx.world
    if not isinstance(world, PyBulletWorld) or world.uav < 0:
        raise StampcError([error("PB030", "aerial functions need a PyBullet world with a "
                                 "'uav'", Span.point("<world>"))])
    return world  # type: ignore[return-value]


def uav_free(world: PyBulletWorld, pose: Sequence[float]) -> bool:
    """Whether the UAV at ``pose`` (x, y, z, qx, qy, qz, qw) touches nothing."""
    cid = world.client
    p.resetBasePositionAndOrientation(world.uav, pose[:3], pose[3:], physicsClientId=cid)
    world.checks += 1
    p.performCollisionDetection(physicsClientId=cid)
    return not any(c[8] < -PENETRATION
                   for c in p.getContactPoints(bodyA=world.uav, physicsClientId=cid))


def _restore_uav(world: PyBulletWorld) -> None:
    pose = world.state.uav
    if pose is not None:
        p.resetBasePositionAndOrientation(world.uav, pose.pos, pose.quat,
                                          physicsClientId=world.client)


def path_length(traj: Traj) -> float:
    """Translational length of a UAV trajectory (metres)."""
    return sum(math.dist(a[:3], b[:3]) for a, b in zip(traj.configs, traj.configs[1:]))


def _sample_goal(world: PyBulletWorld, region: str, rng: random.Random) -> Pose | None:
    box = world.regions[region]
    assert world.spec.uav is not None
    half = [max(0.0, s / 2 - u / 2) for s, u in zip(box.size, world.spec.uav.size)]
    for _ in range(30):
        pos = tuple(c + rng.uniform(-h, h) for c, h in zip(box.position, half))
        pose = Pose.of(pos, quat_from_yaw(rng.uniform(-math.pi, math.pi)))
        if uav_free(world, pose.pos + pose.quat):
            return pose
    return None


def plan_flight(world: PyBulletWorld, start: Pose, goal: Pose, rng: random.Random,
                planner: str = "RRTConnect", max_checks: int = 20000,
                time_limit: float = 5.0) -> list[tuple[float, ...]] | None:
    """An SE(3) path between two poses avoiding every body (level flight not enforced)."""
    spec = world.spec.uav
    assert spec is not None
    counter = {"checks": 0}
    t0 = time.perf_counter()

    def valid(s: object) -> bool:
        counter["checks"] += 1
        r = s.rotation()  # type: ignore[attr-defined]
        return uav_free(world, (s.getX(), s.getY(), s.getZ(), r.x, r.y, r.z, r.w))  # type: ignore[attr-defined]

    level = ou.getLogLevel()
    ou.setLogLevel(ou.LOG_NONE)
    ou.RNG.setSeed(rng.randrange(1, 2**31))
    ou.setLogLevel(ou.LOG_WARN if world.verbose else ou.LOG_ERROR)
    try:
        space = ob.SE3StateSpace()
        bounds = ob.RealVectorBounds(3)
        for i in range(3):
            bounds.setLow(i, spec.low[i])
            bounds.setHigh(i, spec.high[i])
        space.setBounds(bounds)
        ss = og.SimpleSetup(space)
        ss.setStateValidityChecker(valid)
        si = ss.getSpaceInformation()
        si.setStateValidityCheckingResolution(FLY_RESOLUTION / space.getMaximumExtent())
        states = []
        for pose in (start, goal):
            st = space.allocState()
            st.setXYZ(*pose.pos)
            rot = st.rotation()
            rot.x, rot.y, rot.z, rot.w = pose.quat
            states.append(st)
        ss.setStartAndGoalStates(states[0], states[1])
        si.setup()
        if si.checkMotion(states[0], states[1]):
            return [start.pos + start.quat, goal.pos + goal.quat]
        ss.setPlanner(planner_class(planner)(si))
        ss.setup()
        stop = ob.PlannerTerminationCondition(
            lambda: counter["checks"] >= max_checks or time.perf_counter() - t0 > time_limit)
        if not ss.solve(stop) or not ss.haveExactSolutionPath():
            return None
        path = ss.getSolutionPath()
        out = []
        for k in range(path.getStateCount()):
            s = path.getState(k)
            r = s.rotation()
            out.append((s.getX(), s.getY(), s.getZ(), r.x, r.y, r.z, r.w))
        return out
    finally:
        ou.setLogLevel(level)
        _restore_uav(world)


def fly(ctx: Context, region: str) -> Iterator[tuple[Pose, Traj]]:
    """Poses inside ``region`` and collision-free flights from the UAV's current pose."""
    world = _world(ctx)
    if region not in world.regions:
        raise StampcError([error("PB031", f"unknown region {region!r}", Span.point("<world>"),
                                 f"regions: {', '.join(sorted(world.regions))}")])
    start = world.state.uav
    assert start is not None
    budget = int(ctx.options.get("budget", 4))
    for _ in range(budget):
        goal = _sample_goal(world, region, ctx.rng)
        _restore_uav(world)
        if goal is None:
            continue
        path = plan_flight(world, start, goal, ctx.rng,
                           planner=str(ctx.options.get("planner", "RRTConnect")),
                           time_limit=float(ctx.options.get("time_limit", 5.0)))
        if path is None:
            continue
        traj = Traj(tuple(tuple(c) for c in path), target=region)
        if flight_free(world, traj):  # else rejected: the next sample plans anew
            yield goal, traj


def flight_contacts(world: PyBulletWorld, traj: Traj, resolution: float,
                    first: bool = False) -> set[int]:
    """Bodies the UAV penetrates along ``traj`` swept every ``resolution`` m (positions
    interpolated, orientation from the nearer end); ``first``: stop at the first hit."""
    cid, hit = world.client, set()
    try:
        for a, b in zip(traj.configs, traj.configs[1:]):
            n = max(1, math.ceil(math.dist(a[:3], b[:3]) / resolution))
            for i in range(n + 1):
                pos = tuple(x + (y - x) * i / n for x, y in zip(a[:3], b[:3]))
                p.resetBasePositionAndOrientation(world.uav, pos, (a if i < n / 2 else b)[3:],
                                                  physicsClientId=cid)
                world.checks += 1
                p.performCollisionDetection(physicsClientId=cid)
                hit |= {c[2] for c in p.getContactPoints(bodyA=world.uav, physicsClientId=cid)
                        if c[8] < -PENETRATION}
                if hit and first:
                    return hit
        return hit
    finally:
        _restore_uav(world)


def flight_free(world: PyBulletWorld, traj: Traj, resolution: float = EXEC_RESOLUTION) -> bool:
    """Whether ``traj`` touches nothing, swept as the execution re-check sweeps it."""
    return not flight_contacts(world, traj, resolution, first=True)


def has_battery(ctx: Context, t: Traj) -> bool:
    """Whether the remaining battery covers the flight ``t``."""
    return path_length(as_traj(t)) <= _world(ctx).state.battery + 1e-9


def fly_to(ctx: Context, action: ConcreteAction) -> None:
    """Fly along ``t``; drain the battery by its length. If the outcome adds a fact
    naming a *different* region than the one reached (a drift), land at its centre."""
    world = _world(ctx)
    t = action.args.get("t")
    if isinstance(t, dict):
        t = as_traj(t)
    if not isinstance(t, Traj):
        raise StampcError([error("PB032", f"action '{action.name}' needs a flight "
                                 "trajectory argument 't'", Span.point("<world>"))])
    end = Pose.of(t.end[:3], t.end[3:])
    reached = [r for r, box in world.regions.items() if box.contains(end.pos)]
    named = [a for _, args in action.adds for a in args
             if isinstance(a, str) and a in world.regions]
    drift = [r for r in named if r not in reached]
    if drift:
        end = Pose.of(world.regions[drift[0]].position, end.quat)
    world.update(uav=end, battery=max(0.0, world.state.battery - path_length(t)))


def charge(ctx: Context, action: ConcreteAction) -> None:
    """Refill the battery to the scene's capacity."""
    world = _world(ctx)
    assert world.spec.uav is not None
    world.update(battery=world.spec.uav.battery)


def inspect(ctx: Context, action: ConcreteAction) -> None:
    """Inspection changes nothing in the geometry (its outcome is symbolic)."""
    _world(ctx)
