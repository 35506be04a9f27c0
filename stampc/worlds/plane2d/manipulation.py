"""Bound functions of the manipulation domain on the plane2d world.

Same names and signatures as ``stampc.worlds.pybullet.manipulation`` so one domain
(``stdlib/manipulation.stamp``, bindings ``".manipulation:grasp"`` ...) runs on both.

- generators: :func:`grasp`, :func:`placement`, :func:`motion`
- evaluators: :func:`collision`, :func:`reachable`, :func:`trajectory_free`
- executors: :func:`pick`, :func:`place`, :func:`discard`
"""

from __future__ import annotations

import math
import sys
from typing import Any, Iterator

from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.plane2d.geometry import Disc, Point, ray_exit_rounded_box
from stampc.worlds.plane2d.planning import rrt_connect
from stampc.worlds.plane2d.support import (arg, float_option, int_option, mentions,
                                           name_arg, normalize_angle, world_of)
from stampc.worlds.plane2d.values import (Config2, Grasp2, Pose2, Traj2, as_config,
                                          as_pose, as_traj)
from stampc.worlds.plane2d.world import Plane2DWorld, angle_to

#: fixed approach directions tried by ``grasp`` (then random ones if the budget allows)
N_APPROACHES = 8
_BLOCKING_KEY = "plane2d.blocking"


# ------------------------------------------------------------------- grasping
def grasp_config(world: Plane2DWorld, o: str, p: Pose2, angle: float) -> Config2:
    """Gripper centre touching object ``o`` at pose ``p`` from approach ``angle``."""
    spec = world.spec(o)
    r = world.scene.robot.gripper_radius
    if spec.shape == "disc":
        d = spec.radius + r
    else:
        d = ray_exit_rounded_box(spec.hx, spec.hy, r, angle)
    direction = p.theta + angle
    return Config2(p.x + d * math.cos(direction), p.y + d * math.sin(direction), target=o)


def facing_angle(world: Plane2DWorld, p: Pose2, base: Point | None = None) -> float:
    """Approach angle (object frame) pointing from the object towards the robot base
    (where it stands, or ``base``)."""
    return normalize_angle(angle_to(p.xy, base or world.base) - p.theta)


def _approach_angles(world: Plane2DWorld, p: Pose2, base: Point | None = None) -> list[float]:
    """Facing the base first, then alternately either side of it, then behind."""
    base = facing_angle(world, p, base)
    step = 2 * math.pi / N_APPROACHES
    angles = [base]
    for k in range(1, N_APPROACHES // 2):
        angles += [base + k * step, base - k * step]
    angles.append(base + math.pi)
    return [normalize_angle(a) for a in angles]


def _config_ok(world: Plane2DWorld, q: Config2, base: Point | None = None) -> bool:
    gripper = Disc(q.x, q.y, world.scene.robot.gripper_radius)
    return world.admissible(q.xy, base) and not world.static_overlap(gripper)


def grasp(ctx: Context, o: str, p: Any) -> Iterator[tuple[Grasp2, Config2]]:
    """Contact grasps of ``o`` at ``p``: reachable, clear of static geometry; grasps whose
    gripper also overlaps another movable object come last."""
    world, p = world_of(ctx), as_pose(p)
    world.spec(o)
    budget = int_option(ctx, "budget", N_APPROACHES)
    angles = _approach_angles(world, p)
    angles += [ctx.rng.uniform(-math.pi, math.pi) for _ in range(max(0, budget - len(angles)))]
    r = world.scene.robot.gripper_radius
    ranked = []
    for k, a in enumerate(angles):
        q = grasp_config(world, o, p, a)
        if not _config_ok(world, q):
            continue
        crowded = bool(world.movable_overlaps(Disc(q.x, q.y, r), exclude=(o, world.held)))
        ranked.append((crowded, k, Grasp2(a), q))
    ranked.sort(key=lambda c: (c[0], c[1]))
    for _, _, g, q in ranked[:budget]:
        yield g, q


def reachable(ctx: Context, o: str, p: Any) -> bool:
    """Some contact grasp of ``o`` at ``p`` is within reach and clear of static geometry."""
    return reachable_from(world_of(ctx), o, as_pose(p))


def reachable_from(world: Plane2DWorld, o: str, p: Pose2, base: Point | None = None) -> bool:
    """``reachable`` from the robot base where it stands, or from ``base``."""
    return any(_config_ok(world, grasp_config(world, o, p, a), base)
               for a in _approach_angles(world, p, base))


# ------------------------------------------------------------------ placement
def _half_extents(world: Plane2DWorld, o: str, theta: float) -> tuple[float, float]:
    spec = world.spec(o)
    if spec.shape == "disc":
        return spec.radius, spec.radius
    c, s = abs(math.cos(theta)), abs(math.sin(theta))
    return c * spec.hx + s * spec.hy, s * spec.hx + c * spec.hy


def _holding_offset(world: Plane2DWorld, o: str, p: Pose2) -> tuple[float, float]:
    """Object centre minus gripper centre when ``o`` sits at ``p``: the current grasp if
    ``o`` is held, else the grasp facing the robot base."""
    if world.held == o:
        return world.state.held_offset
    q = grasp_config(world, o, p, facing_angle(world, p))
    return (p.x - q.x, p.y - q.y)


def placement(ctx: Context, o: str, s: str) -> Iterator[tuple[Pose2, Config2]]:
    """Poses of ``o`` inside surface ``s`` (with ``margin``, default 5 mm) whose footprint
    (bounding disc) is clear of every other object, with a reachable gripper config."""
    world = world_of(ctx)
    rect, spec = world.surface(s), world.spec(o)
    budget = int_option(ctx, "budget", 8)
    tries = int_option(ctx, "tries", 60)
    margin = float_option(ctx, "margin", 0.005)
    current = world.pose(o)
    theta = current.theta if current is not None else 0.0
    ex, ey = _half_extents(world, o, theta)
    x0, x1, y0, y1 = rect.x0 + ex + margin, rect.x1 - ex - margin, rect.y0 + ey + margin, \
        rect.y1 - ey - margin
    if x0 > x1 or y0 > y1:
        return
    r = world.scene.robot.gripper_radius
    found = 0
    for _ in range(tries * budget):
        pose = Pose2(ctx.rng.uniform(x0, x1), ctx.rng.uniform(y0, y1), theta)
        footprint = Disc(pose.x, pose.y, spec.bounding_radius)
        if world.static_overlap(spec.at(pose)) or \
                world.movable_overlaps(footprint, exclude=(o,), margin=margin):
            continue
        ox, oy = _holding_offset(world, o, pose)
        q = Config2(pose.x - ox, pose.y - oy, target=o)
        if not _config_ok(world, q) or world.movable_overlaps(Disc(q.x, q.y, r), exclude=(o,)):
            continue
        yield pose, q
        found += 1
        if found >= budget:
            return


# --------------------------------------------------------------------- motion
def motion(ctx: Context, q: Any) -> Iterator[tuple[Traj2]]:
    """Paths of the gripper (and what it holds) from where it is to ``q``.

    Straight segment if free; else up to ``budget`` seeded RRT-Connect attempts
    (``iterations`` each) avoiding every object except ``q.target`` and the held one;
    if none succeeds, the path that avoids static geometry only (straight if possible),
    so that the ``collision`` evaluator can name the objects in the way.
    """
    world, q = world_of(ctx), as_config(q)
    budget = int_option(ctx, "budget", 4)
    iterations = int_option(ctx, "iterations", 400)
    start, held = world.gripper, world.held
    exclude = tuple(n for n in (q.target, held) if n is not None)
    full = world.checker(exclude=exclude)

    def traj(points) -> tuple[Traj2]:
        return (Traj2(tuple((float(x), float(y)) for x, y in points), held, q.target),)

    if full.segment_free(start, q.xy):
        yield traj([start, q.xy])
        return
    found = False
    if full.point_free(q.xy):
        for _ in range(budget):
            path = rrt_connect(start, q.xy, full, ctx.rng, iterations=iterations)
            if path is not None:
                found = True
                yield traj(path)
    if found:
        return
    if world.verbose:
        print(f"plane2d: no collision-free motion to ({q.x:.3f}, {q.y:.3f}) within budget; "
              "yielding the path that ignores movable objects", file=sys.stderr)
    static = world.checker(exclude=exclude, movables=False)
    if static.segment_free(start, q.xy):
        yield traj([start, q.xy])
        return
    path = rrt_connect(start, q.xy, static, ctx.rng, iterations=iterations)
    if path is not None:
        yield traj(path)


def blocking_objects(ctx: Context, t: Any) -> frozenset[str]:
    """Movable objects the swept area of ``t`` overlaps, excluding ``t.held`` and
    ``t.target``; computed once per trajectory and state (``ctx.cache``)."""
    world, t = world_of(ctx), as_traj(t)
    key = (_BLOCKING_KEY, t)
    if key not in ctx.cache:
        exclude = tuple(n for n in (t.held, t.target) if n is not None)
        footprints = (((0.0, 0.0), world.scene.robot.gripper_radius),) \
            + world.held_footprints(t.held)
        hits = world.checker(exclude=exclude, footprints=footprints).blockers(t.points)
        ctx.cache[key] = frozenset(n for n in hits if world.is_movable(n))
    return ctx.cache[key]


def collision(ctx: Context, x: str, t: Any) -> bool:
    """Does the swept area of ``t`` (gripper + held object) overlap object ``x``?"""
    return x in blocking_objects(ctx, t)


def trajectory_free(ctx: Context, t: Any) -> bool:
    """``t`` stays admissible and overlaps nothing, static or movable (except its held
    object and target) — same contract as the PyBullet world's evaluator."""
    world, t = world_of(ctx), as_traj(t)
    if blocking_objects(ctx, t):
        return False
    footprints = (((0.0, 0.0), world.scene.robot.gripper_radius),) + world.held_footprints(t.held)
    return world.checker(movables=False, footprints=footprints).path_free(t.points)


# ------------------------------------------------------------------ executors
def _follow(world: Plane2DWorld, action: ConcreteAction) -> None:
    q = arg(action, "q", as_config)
    points = arg(action, "t", as_traj).points if "t" in action.args else ()
    world.move_gripper(tuple(points) + (q.xy,))


def pick(ctx: Context, action: ConcreteAction) -> None:
    """Move along ``t`` to ``q``; attach ``o`` iff the outcome adds ``holding(o)``."""
    world = world_of(ctx)
    o = arg(action, "o", name_arg)
    _follow(world, action)
    if mentions(action.adds, "holding", o) and world.present(o):
        world.attach(o)


def place(ctx: Context, action: ConcreteAction) -> None:
    """Move along ``t`` to ``q`` carrying ``o``; release it at ``p`` iff the outcome adds
    ``at``; if the outcome only deletes ``holding(o)`` it drops where it is; otherwise
    (a slip that keeps it in hand) ``o`` stays held."""
    world = world_of(ctx)
    o = arg(action, "o", name_arg)
    _follow(world, action)
    if not world.present(o):
        return
    if mentions(action.adds, "at", o):
        world.release(o, arg(action, "p", as_pose))
    elif mentions(action.deletes, "holding", o):
        world.release(o)


def discard(ctx: Context, action: ConcreteAction) -> None:
    """Remove object ``o`` from the scene (e.g. a crushed can thrown away)."""
    world = world_of(ctx)
    o = arg(action, "o", name_arg)
    if world.present(o):
        world.remove(o)
