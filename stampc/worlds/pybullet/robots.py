"""Bindings for scenes with several robots and mobile bases.

Robot-first variants of the manipulation generators (a domain with two arms passes the
arm as the first generator input) and the mobile-base pair:

- ``.robots:grasp(r, o, p) -> (g, q)``, ``.robots:placement(r, o, s) -> (p, q)``: as
  ``.manipulation:grasp`` / ``:placement`` for robot ``r`` from where its base stands;
- ``.robots:base_pose(r, o, p) -> (b,)``: robot ``r``'s candidate base poses (the
  scene's ``bases``) from which some top grasp of ``o`` at ``p`` has an IK solution,
  nearest first (a heuristic order: every reachable candidate is still yielded);
- ``.robots:move_base`` (executor, argument ``b``): re-place the robot at base ``b``.

Motion, collision, pick and place need no robot argument: configs and trajectories
record the robot and base pose they were generated for.
"""

from __future__ import annotations

import math
from typing import Iterator

from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.pybullet import manipulation
from stampc.worlds.pybullet.kinematics import IkSettings, grasps_of_kind, solve_ik
from stampc.worlds.pybullet.values import Base, Config, Grasp, Pose, as_base, as_pose
from stampc.worlds.pybullet.world import PyBulletWorld

#: horizontal distance (m) beyond which a base cannot reach an object (Panda: 0.855 m)
MAX_REACH = 0.9
REACH_IK = IkSettings(restarts=2)


def grasp(ctx: Context, r: str, o: str, p: Pose) -> Iterator[tuple[Grasp, Config]]:
    return manipulation.grasp(ctx, o, p, r)


def placement(ctx: Context, r: str, o: str, s: str) -> Iterator[tuple[Pose, Config]]:
    return manipulation.placement(ctx, o, s, r)


def reaches(world: PyBulletWorld, ctx: Context, o: str, p: Pose, base: Pose) -> bool:
    """Whether the active robot standing at ``base`` has an IK solution for one of its
    grasps of ``o`` at ``p`` (its scene's grasp kinds; collisions ignored); the world's
    state is left as it was."""
    if math.dist(base.pos[:2], p.pos[:2]) > MAX_REACH:
        return False
    key = ("base-reaches", world.active_arm.name if world.active_arm else None, base, o, p)
    if key in ctx.cache:
        return ctx.cache[key]
    saved = world.snapshot()
    try:
        world.update(base=base)
        grasps = grasps_of_kind(world.geometry[o], world.grasp_kinds())
        ok = any(solve_ik(world, p.multiply(g.hand), ctx.rng, settings=REACH_IK) is not None
                 for g in grasps)
    finally:
        world.restore(saved)
    ctx.cache[key] = ok
    return ok


def base_pose(ctx: Context, r: str, o: str, p: Pose) -> Iterator[tuple[Base]]:
    """Candidate base poses of robot ``r`` that reach ``o`` at ``p``, nearest first."""
    world = manipulation._world(ctx, r)
    manipulation._check_object(world, o)
    p = as_pose(p)
    candidates = sorted(world.candidate_bases(r).items(),
                        key=lambda item: (math.dist(item[1].pos[:2], p.pos[:2]), item[0]))
    yielded, budget = 0, manipulation._budget(ctx)
    for name, pose in candidates:
        world.select(r)  # other calls may have selected another robot meanwhile
        if reaches(world, ctx, o, p, pose):
            yield (Base(r, name, pose),)
            yielded += 1
            if yielded >= budget:
                return


def move_base(ctx: Context, action: ConcreteAction) -> None:
    """Drive robot ``b.robot`` to base pose ``b`` (the arm keeps its joints)."""
    b = as_base(manipulation._arg(action, "b"))
    world = manipulation._world(ctx, b.robot)
    world.move_base(b.pose, b.name)
