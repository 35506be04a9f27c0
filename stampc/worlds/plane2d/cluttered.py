"""Cluttered-table bindings for the plane2d world (``examples/cluttered_table``).

Fixed-base domain (``domain_fixed.stamp``):
- ``.cluttered:grasp`` / ``.cluttered:placement``: the manipulation generators as they
  are (plane2d's grasps already come clear-of-other-objects first);
- ``.cluttered:discard``: follow ``t`` to ``q`` carrying the can, then take it out of the
  scene (it obstructs nothing afterwards).

Mobile-base domain (``domain.stamp``; the scene's ``robot.bases`` are named candidate
base positions, ``b`` arguments are their names) — the same contract as the PyBullet
world's ``stampc.worlds.pybullet.cluttered``:
- ``.cluttered:grasp_at(b, o, p)``: the contact grasps from base ``b``; nothing unless
  the robot stands at ``b`` (a grasp is only meaningful from where the arm is);
- ``.cluttered:placement_here(o, s)``: placements within reach of the current base;
- ``.cluttered:bin_drop(o)``: the gripper over the bin the robot carries on its base;
- ``.cluttered:reaches(b, o, p)`` (evaluator): some contact grasp of ``o`` at ``p`` is
  within reach of base ``b`` and clear of static geometry (other cans ignored: they are
  what ``collision`` facts are for);
- ``.cluttered:move_base`` (executor, arguments ``a``, ``b``): tuck the gripper in over
  the base and drive to ``b`` (a held can comes along).
"""

from __future__ import annotations

from typing import Any, Iterator

from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.plane2d.manipulation import _follow, grasp, placement, reachable_from
from stampc.worlds.plane2d.manipulation import discard as _remove
from stampc.worlds.plane2d.support import arg, name_arg, world_of
from stampc.worlds.plane2d.values import Config2, Grasp2, Pose2, as_pose

__all__ = ["bin_drop", "discard", "grasp", "grasp_at", "move_base", "placement",
           "placement_here", "reaches"]


def discard(ctx: Context, action: ConcreteAction) -> None:
    """Carry ``o`` along ``t`` to ``q`` and remove it from the scene."""
    world = world_of(ctx)
    if "q" in action.args:
        _follow(world, action)
    _remove(ctx, action)


def grasp_at(ctx: Context, b: str, o: str, p: Any) -> Iterator[tuple[Grasp2, Config2]]:
    """Contact grasps of ``o`` at ``p`` from base ``b``; nothing unless the robot is there."""
    world = world_of(ctx)
    if world.base_position(b) != world.base:
        world.spec(o)   # still reject an unknown object
        return iter(())
    return grasp(ctx, o, p)


def placement_here(ctx: Context, o: str, s: str) -> Iterator[tuple[Pose2, Config2]]:
    """Placements of ``o`` on ``s`` within reach of where the robot stands."""
    return placement(ctx, o, s)


def bin_drop(ctx: Context, o: str) -> Iterator[tuple[Config2]]:
    """The gripper centred over the robot's base, where its bin rides; only while ``o``
    is the held can (a drop config is relative to the grip)."""
    world = world_of(ctx)
    world.spec(o)
    if world.held == o:
        x, y = world.base
        yield (Config2(x, y, target=o),)


def reaches(ctx: Context, b: str, o: str, p: Any) -> bool:
    """Some contact grasp of ``o`` at ``p`` is within reach of base ``b`` and clear of
    static geometry."""
    world = world_of(ctx)
    base = world.base_position(b)
    world.spec(o)
    return reachable_from(world, o, as_pose(p), base)


def move_base(ctx: Context, action: ConcreteAction) -> None:
    """Drive to base ``b`` with the gripper tucked in over the base."""
    world_of(ctx).move_base(arg(action, "b", name_arg))
