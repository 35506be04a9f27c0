"""Bound generators, evaluators and executors for arm manipulation.

Bindings (relative to the world package): ``.manipulation:grasp``, ``:placement``,
``:motion``, ``:collision``, ``:reachable``, ``:pick``, ``:place``, ``:discard``. Every function leaves
the bodies at the world's current concrete state when it returns or yields.
"""

from __future__ import annotations

import math
import random
from dataclasses import replace
from typing import Iterator

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.base import ConcreteAction, Context, missing_parameter_hint
from stampc.worlds.pybullet.kinematics import (IkSettings, arm_meets, grasp_candidates, solve_ik,
                                               top_grasp)
from stampc.worlds.pybullet.planning import PlanSettings, PlanStats, counts, plan_swept, sweep
from stampc.worlds.pybullet.values import (Config, Grasp, Pose, Traj, as_config, as_pose,
                                           as_traj, interpolate, quat_from_yaw, yaw_of)
from stampc.worlds.pybullet.world import CLEARANCE, PyBulletWorld

PLACE_CLEARANCE = 0.002  # m above the surface, so a placed object does not penetrate it
PLACE_SPACING = 0.01  # m between footprints of placed and present objects
PLACE_MARGIN = 0.02  # m between a footprint and the surface edge
LIFT_HEIGHT = 0.05  # m the hand rises after closing on an object it took from the side


def _world(ctx: Context, robot: str | None = None) -> PyBulletWorld:
    """The context's world with robot ``robot`` (default: the first) selected."""
    world = ctx.world
    if not isinstance(world, PyBulletWorld) or not world.arms:
        raise StampcError([error("PB010", "manipulation functions need a PyBullet world "
                                 "with a robot arm", Span.point("<world>"))])
    world.select(robot)
    return world


def _owner(world: PyBulletWorld) -> tuple[str, Pose]:
    """The active robot's name and current base pose (recorded in generated values)."""
    assert world.active_arm is not None
    return world.active_arm.name, world.base_pose()


def _check_base(world: PyBulletWorld, value: Config | Traj, what: str) -> None:
    """A config or trajectory recorded for another base pose cannot be executed here."""
    if value.base is not None and value.base != world.base_pose():
        raise StampcError([error("PB016", f"{what} belongs to robot {value.robot!r} at base "
                                 f"{value.base.pos}, but the robot stands at "
                                 f"{world.base_pose().pos}", Span.point("<world>"),
                                 "tie configs to base poses in the model (e.g. a base "
                                 "argument of the grasp generator)")])


def _check_object(world: PyBulletWorld, name: str) -> None:
    if name not in world.geometry:
        raise StampcError([error("PB011", f"unknown object {name!r}", Span.point("<world>"),
                                 f"scene objects: {', '.join(sorted(world.geometry))}")])


def _budget(ctx: Context) -> int:
    value = ctx.options.get("budget")
    return int(value) if isinstance(value, (int, float)) and value > 0 else 1_000_000


def _static_free(world: PyBulletWorld, configs: list[tuple[float, ...]],
                 ignore_held_support: bool = False) -> bool:
    """Robot (and held object) clear of surfaces and of itself along ``configs``."""
    for q in configs:
        robot_hits, held_hits = world.hits(q)
        if ignore_held_support:
            held_hits = held_hits - world.static_ids
        if (robot_hits | held_hits) - world.movable_ids:
            return False
    return True


def _approach_ok(world: PyBulletWorld, pre: tuple[float, ...], q: tuple[float, ...],
                 placing: bool = False) -> bool:
    return _static_free(world, interpolate(pre, q, 0.02), ignore_held_support=placing)


# ------------------------------------------------------------------ generators
def grasp(ctx: Context, o: str, p: Pose, r: str | None = None
          ) -> Iterator[tuple[Grasp, Config]]:
    """Grasps of ``o`` at pose ``p`` with a reaching, statically collision-free config
    of robot ``r`` (default: the first) from where its base stands now."""
    world = _world(ctx, r)
    _check_object(world, o)
    p = as_pose(p)
    kinds = str(ctx.options.get("grasps", "any"))
    yielded, budget = 0, _budget(ctx)
    robot, base = _owner(world)
    for g in grasp_candidates(world.geometry[o], ctx.rng, kinds):
        if ctx.time_left(1.0) <= 0.01:
            return  # the run's deadline has passed: IK for more candidates is wasted
        world.select(robot)  # other calls may have selected another robot meanwhile
        config = _grasp_config(world, ctx, o, p, g)
        world.set_arm(world.state.q)
        if config is not None:
            yield replace(g, robot=robot, base=base), config
            yielded += 1
            if yielded >= budget:
                return


def _grasp_config(world: PyBulletWorld, ctx: Context, o: str, p: Pose,
                  g: Grasp) -> Config | None:
    robot, base = _owner(world)
    key = ("grasp-config", robot, base, o, p, g)
    if key in ctx.cache:
        return ctx.cache[key]
    hand = p.multiply(g.hand)
    q = solve_ik(world, hand, ctx.rng, settings=_ik(ctx))
    pre = solve_ik(world, g.pregrasp(p), ctx.rng, seed_q=q, settings=_ik(ctx)) if q else None
    ok = q is not None and pre is not None and _approach_ok(world, pre, q)
    config = Config.of(q, obj=o, pre=pre, robot=robot, base=base) if ok else None  # type: ignore[arg-type]
    # a grasp the hand cannot lift the object from (a side grasp without a lift) is none
    ctx.cache[key] = config if config is None or _lift(world, config) is not None else None
    return ctx.cache[key]


def _ik(ctx: Context) -> IkSettings:
    return IkSettings(restarts=int(ctx.options.get("ik_restarts", 5)))


def placement(ctx: Context, o: str, s: str, r: str | None = None
              ) -> Iterator[tuple[Pose, Config]]:
    """Poses of ``o`` on surface ``s`` and the configs of robot ``r`` (default: the
    first) that put it there.

    Uses the current grip if ``o`` is held (else a top grasp). The yielded pose is where
    the object comes to rest when the hand at the config lets go of it: under the hand's
    actual position (IK is within 5 mm / 0.05 rad), upright on the surface. Execution's
    physics settles a released object there; the pose the hand holds it at (up to 5.5 mm
    higher, tilted) left it up to 5.5 mm off, enough for a later trajectory planned
    past it to meet it in execution.
    """
    world = _world(ctx, r)
    _check_object(world, o)
    if s not in world.surfaces:
        raise StampcError([error("PB012", f"unknown surface {s!r}", Span.point("<world>"),
                                 f"surfaces: {', '.join(sorted(world.surfaces))}")])
    surface, geom = world.surfaces[s], world.geometry[o]
    state = world.state
    robot = _owner(world)[0]
    grip = state.grip if state.held == o and state.grip is not None \
        else top_grasp(geom, 0.0).hand.inverse()
    others = [(pose.pos, world.geometry[n].footprint) for n, pose in state.poses
              if n != o and n != state.held and n not in state.removed]
    half_x = surface.size[0] / 2 - geom.footprint - PLACE_MARGIN
    half_y = surface.size[1] / 2 - geom.footprint - PLACE_MARGIN
    if half_x < 0 or half_y < 0:
        return
    yielded, budget = 0, _budget(ctx)
    reach = ctx.options.get("reach")  # m from the robot's base (skip hopeless IK calls)
    base = world.base_pose().pos
    for _ in range(int(ctx.options.get("samples", 50))):
        x = surface.position[0] + ctx.rng.uniform(-half_x, half_x)
        y = surface.position[1] + ctx.rng.uniform(-half_y, half_y)
        if isinstance(reach, (int, float)) and math.dist((x, y), base[:2]) > reach:
            continue
        if any(math.dist((x, y), pos[:2]) < geom.footprint + r + PLACE_SPACING
               for pos, r in others):
            continue
        z = surface.top + geom.height / 2 + PLACE_CLEARANCE
        target = Pose.of((x, y, z), quat_from_yaw(ctx.rng.uniform(-math.pi, math.pi)))
        world.select(robot)  # other calls may have selected another robot meanwhile
        result = _place_config(world, ctx, o, target, grip, surface.top + geom.height / 2)
        world.set_arm(state.q)
        if result is not None:
            yield result
            yielded += 1
            if yielded >= budget:
                return


def _place_config(world: PyBulletWorld, ctx: Context, o: str, target: Pose,
                  grip: Pose, rest_z: float) -> tuple[Pose, Config] | None:
    hand = target.multiply(grip.inverse())
    q = solve_ik(world, hand, ctx.rng, settings=_ik(ctx))
    if q is None:
        return None
    actual = world.ee_pose().multiply(grip)
    above = Pose((hand.pos[0], hand.pos[1], hand.pos[2] + 0.1), hand.quat)
    pre = solve_ik(world, above, ctx.rng, seed_q=q, settings=_ik(ctx))
    if pre is None or not _approach_ok(world, pre, q, placing=world.state.held == o):
        return None
    robot, base = _owner(world)
    rest = Pose.of((actual.pos[0], actual.pos[1], rest_z), quat_from_yaw(yaw_of(actual.quat)))
    world.set_arm(q)
    if arm_meets(world, o, rest, CLEARANCE) or arm_meets(world, o, actual, CLEARANCE):
        return None  # the arm folded into what it puts down (kinematics.arm_meets)
    return rest, Config.of(q, obj=o, pre=pre, robot=robot, base=base)


def motion(ctx: Context, q: Config) -> Iterator[tuple[Traj]]:
    """Trajectories from the current config to ``q``: collision-free ones first, then
    (if the collision-free search fails) ones avoiding only static obstacles, so the
    ``collision`` evaluator can name the movable objects in the way. A config recorded
    for another base pose of the robot yields nothing (it is out of reach from here)."""
    q = as_config(q)
    world = _world(ctx, q.robot)
    if q.base is not None and q.base != world.base_pose():
        return
    budget = _budget(ctx) if "budget" in ctx.options else 4
    base = PlanSettings(planner=str(ctx.options.get("planner", "RRTConnect")),
                        max_checks=int(ctx.options.get("max_checks", 20000)),
                        time_limit=float(ctx.options.get("time_limit", 5.0)))
    stats = ctx.options.get("stats")
    stats = stats if isinstance(stats, PlanStats) else None
    seen: set[Traj] = set()
    for static_only in (False, True):
        for attempt in range(budget):
            if attempt and ctx.time_left(1.0) <= 0.01:
                return  # past the run's deadline
            settings = PlanSettings(base.planner, base.max_checks,
                                    ctx.time_left(base.time_limit),  # the run's deadline
                                    static_only, straight=attempt == 0)
            world.select(q.robot)  # other calls may have selected another robot meanwhile
            planned = plan_swept(world, q, ctx.rng, settings, stats)
            world.set_arm(world.state.q)
            if planned is None:
                break
            traj, hit = planned
            ctx.cache.setdefault(_sweep_key(traj), hit)  # what _swept would find here
            if traj not in seen:
                seen.add(traj)
                yield (traj,)
        if seen:
            return  # collision-free paths exist: no need to blame movable objects


# ------------------------------------------------------------------ evaluators
def _swept(ctx: Context, t: Traj) -> frozenset[int]:
    """Every body trajectory ``t`` (its robot and held object) hits, swept once per
    trajectory and state at fine resolution (the task's own contacts excepted only where
    :func:`~.planning.bad_bodies` says so)."""
    key = _sweep_key(t)
    if key not in ctx.cache:
        world = _world(ctx, t.robot)
        ctx.cache[key] = sweep(world, t)
        world.set_arm(world.state.q)
    return ctx.cache[key]


def _sweep_key(t: Traj) -> tuple:
    """``ctx.cache`` key of the bodies ``t`` hits in the context's state (the motion
    generator stores what its own check of ``t`` met; :func:`_swept` computes it)."""
    return ("sweep", t)


def blocking_objects(ctx: Context, t: Traj) -> frozenset[str]:
    """Movable objects the trajectory (robot and held object) hits. The task's own
    contacts are not hits only where :func:`~.planning.bad_bodies` says so (the object
    just let go, during the retreat; the target, during the approach): elsewhere on the
    path they are real collisions — a place's object left right in the way of the next
    pick's path is one, and ``stampc execute``'s re-check counts it."""
    t = as_traj(t)
    world = _world(ctx, t.robot)
    return frozenset(n for n in world.names(_swept(ctx, t) & world.movable_ids) if n != t.held)


def robots_hit(ctx: Context, t: Traj) -> frozenset[str]:
    """The other robots the trajectory hits where they stand now (a path planned while
    another arm was elsewhere may meet it when reused in another state)."""
    t = as_traj(t)
    world = _world(ctx, t.robot)
    bodies = {arm.body: name for name, arm in world.arms.items() if name != t.robot}
    return frozenset(bodies[b] for b in _swept(ctx, t) if b in bodies)


def collision(ctx: Context, x: str, t: Traj) -> bool:
    """Does ``t`` hit object ``x``? (Never the held object; the target and the object
    just let go only outside the approach and retreat stretches.)"""
    return x in blocking_objects(ctx, t)


def reachable(ctx: Context, o: str, p: Pose) -> bool:
    """Whether some grasp of ``o`` at ``p`` has an IK solution (collisions ignored)."""
    world = _world(ctx)
    _check_object(world, o)
    p = as_pose(p)
    key = ("reachable", o, p)
    if key not in ctx.cache:
        ok = any(solve_ik(world, p.multiply(g.hand), ctx.rng, settings=_ik(ctx)) is not None
                 for g in grasp_candidates(world.geometry[o], ctx.rng))
        world.set_arm(world.state.q)
        ctx.cache[key] = ok
    return ctx.cache[key]


def trajectory_free(ctx: Context, t: Traj) -> bool:
    """Whether ``t`` is collision-free against everything (fine resolution)."""
    t = as_traj(t)
    world = _world(ctx, t.robot)
    hit = sweep(world, t, stop_on_hit=True)
    world.set_arm(world.state.q)
    return not counts(world, hit, static_only=False)


# ------------------------------------------------------------------ executors
def _adds(action: ConcreteAction, predicate: str, obj: str) -> bool:
    return any(name == predicate and obj in args for name, args in action.adds)


def _arg(action: ConcreteAction, name: str) -> object:
    if name not in action.args:
        raise StampcError([error("PB013", f"action '{action.name}' lacks argument '{name}'",
                                 Span.point("<world>"), hint=missing_parameter_hint(action, name))])
    return action.args[name]


def pick(ctx: Context, action: ConcreteAction) -> None:
    """Move to the grasp config; attach ``o`` iff the outcome adds ``holding``."""
    o, q = str(_arg(action, "o")), as_config(_arg(action, "q"))
    world = _world(ctx, q.robot)
    _check_object(world, o)
    _check_base(world, q, "the grasp config")
    world.update(q=q.q, retreat=None, released=None)
    if _adds(action, "holding", o) and world.present(o):
        grip = world.ee_pose().inverse().multiply(world.object_pose(o))
        world.update(held=o, grip=grip, retreat=_lift(world, q) or q.pre)
    else:  # e.g. a slip: the hand backs off from the untouched object
        world.update(retreat=q.pre, released=o)


def _lift(world: PyBulletWorld, q: Config) -> tuple[float, ...] | None:
    """Where the hand backs off to with the object it closed on: the pre-grasp config when
    that lies above the grasp (top grasps), else the hand raised by :data:`LIFT_HEIGHT`
    (side grasps: backing off sideways would drag the object along its support); None
    when that lift has no IK solution. The IK starts from the grasp config with no random
    restarts: deterministic (the pick executor recomputes what the grasp generator
    checked) and a short straight stretch."""
    if q.pre is None:
        return None
    world.set_arm(q.pre)
    pre_z = world.ee_pose().pos[2]
    world.set_arm(q.q)
    hand = world.ee_pose()
    if pre_z - hand.pos[2] >= LIFT_HEIGHT / 2:
        return q.pre
    up = Pose((hand.pos[0], hand.pos[1], hand.pos[2] + LIFT_HEIGHT), hand.quat)
    lift = solve_ik(world, up, random.Random(0), seed_q=q.q, settings=IkSettings(restarts=0))
    world.set_arm(q.q)
    return lift


def place(ctx: Context, action: ConcreteAction) -> None:
    """Move to the place config; put ``o`` at ``p`` iff the outcome adds ``at``; if it
    only deletes ``holding(o)`` the object is let go where the hand holds it; otherwise
    (a slip that keeps it in hand) ``o`` stays held."""
    o, p, q = str(_arg(action, "o")), as_pose(_arg(action, "p")), as_config(_arg(action, "q"))
    world = _world(ctx, q.robot)
    _check_object(world, o)
    _check_base(world, q, "the place config")
    world.update(q=q.q, retreat=None, released=None)
    if world.state.held != o:
        world.update(retreat=q.pre)
    elif _adds(action, "at", o):
        world.update(held=None, grip=None, poses=world.with_object_pose(o, p),
                     retreat=q.pre, released=o)
    elif any(name == "holding" and o in args for name, args in action.deletes):
        dropped = world.ee_pose().multiply(world.state.grip) if world.state.grip else p
        world.update(held=None, grip=None, poses=world.with_object_pose(o, dropped),
                     retreat=q.pre, released=o)
    else:  # the object stays in the hand
        world.update(retreat=q.pre)


def discard(ctx: Context, action: ConcreteAction) -> None:
    """Take ``o`` out of the scene (e.g. a crushed can thrown into a bin)."""
    world = _world(ctx)
    o = str(_arg(action, "o"))
    _check_object(world, o)
    changes: dict = {"removed": world.state.removed | {o}}
    if world.state.held == o:
        changes.update(held=None, grip=None)
    world.update(**changes)
