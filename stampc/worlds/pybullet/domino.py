"""Bound functions of the domino domain on the PyBullet world.

``.domino:pick`` is the stdlib pick (``.manipulation:pick``) followed by the topple
outcome: every domino the outcome marks ``toppled`` is laid down on the table, on its
wide face, fallen away from the robot (+x of its standing pose), so the concrete world
shows what the abstract outcome says.
"""

from __future__ import annotations

import math

from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.pybullet import manipulation
from stampc.worlds.pybullet.values import Pose, quat_from_axes
from stampc.worlds.pybullet.world import PyBulletWorld

LIE_CLEARANCE = 0.0005  # m between a fallen domino and the table


def fallen_pose(world: PyBulletWorld, name: str, standing: Pose) -> Pose:
    """Where domino ``name`` lies after toppling from ``standing`` (yaw-only pose).

    The domino's thin axis (body x) ends up vertical and its height axis (body z) points
    away from the robot base along the standing pose's horizontal direction.
    """
    sx, sy, sz = world.geometry[name].dims  # axis-aligned extents at identity
    base = world.base_pose().pos if world.arms else (0.0, 0.0, 0.0)
    dx, dy = standing.pos[0] - base[0], standing.pos[1] - base[1]
    norm = math.hypot(dx, dy) or 1.0
    away = (dx / norm, dy / norm, 0.0)
    up = (0.0, 0.0, 1.0)
    # body y = body z × body x = away × up keeps the frame right-handed (issue 13: the
    # former up × away made a reflection, whose "quaternion" left dominoes upright)
    side = (away[1] * up[2] - away[2] * up[1], away[2] * up[0] - away[0] * up[2],
            away[0] * up[1] - away[1] * up[0])
    quat = quat_from_axes(up, side, away)
    reach = sz / 2.0 + sy / 2.0  # pivot over the far bottom edge
    pos = (standing.pos[0] + away[0] * reach, standing.pos[1] + away[1] * reach,
           standing.pos[2] - sz / 2.0 + sx / 2.0 + LIE_CLEARANCE)
    return Pose.of(pos, quat)


def pick(ctx: Context, action: ConcreteAction) -> None:
    """Pick ``o`` (stdlib semantics), then lay down the dominoes the outcome topples."""
    manipulation.pick(ctx, action)
    world = ctx.world
    assert isinstance(world, PyBulletWorld)
    fallen = sorted({str(args[0]) for name, args in action.adds if name == "toppled"})
    poses = dict(world.state.poses)
    for name in fallen:
        manipulation._check_object(world, name)
        if name != world.state.held:
            poses[name] = fallen_pose(world, name, poses[name])
    world.update(poses=tuple((n, poses[n]) for n, _ in world.state.poses))
