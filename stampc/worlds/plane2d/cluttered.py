"""Cluttered-table bindings for the plane2d world (``examples/cluttered_table``).

- ``.cluttered:grasp`` / ``.cluttered:placement``: the manipulation generators as they
  are (plane2d's grasps already come clear-of-other-objects first).
- ``.cluttered:discard``: follow ``t`` to ``q`` over the tray carrying the can, then
  take it out of the scene (it obstructs nothing afterwards).
"""

from __future__ import annotations

from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.plane2d.manipulation import _follow, grasp, placement
from stampc.worlds.plane2d.manipulation import discard as _remove
from stampc.worlds.plane2d.support import world_of

__all__ = ["discard", "grasp", "placement"]


def discard(ctx: Context, action: ConcreteAction) -> None:
    """Carry ``o`` along ``t`` to ``q`` and remove it from the scene."""
    world = world_of(ctx)
    if "q" in action.args:
        _follow(world, action)
    _remove(ctx, action)
