"""The warehouse robot's bound generator on the plane2d world."""

from __future__ import annotations

from typing import Any, Iterator

from stampc.worlds.base import Context
from stampc.worlds.plane2d.aerial import fly


def drive_to(ctx: Context, a: str, b: str) -> Iterator[tuple[Any, Any]]:
    """Poses in cell ``b`` with a path from the robot's current position (in cell ``a``):
    the world's UAV ``fly`` generator, which plans from wherever the robot is. Taking
    ``a`` as an input gives every (a, b) move its own symbols, so a route planned from
    one cell is never used from another."""
    yield from fly(ctx, b)
