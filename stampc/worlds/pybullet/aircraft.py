"""Bound functions of the aircraft-inspection domain (examples/aircraft_inspection) on
the PyBullet world, built on :mod:`.aerial`.

- generator ``.aircraft:flight_path`` ``(u, a, b) -> (t,)``: collision-free SE(3)
  flights from the UAV's current pose into region ``b`` (OMPL, see :func:`aerial.fly`);
- evaluator ``.aircraft:battery_suffices`` ``(u, t) -> bool``: the battery left covers
  ``t`` *and* a return-to-charger reserve from ``t``'s end (flights into the charging
  station need no reserve), so a UAV that only takes approved legs can always get home;
- executors ``.aircraft:fly`` (drains the battery, handles drift outcomes),
  ``.aircraft:charge``, ``.aircraft:inspect``.

The charging station is the region named :data:`CHARGER`.
"""

from __future__ import annotations

import math
from typing import Any, Iterator

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.pybullet import aerial
from stampc.worlds.pybullet.values import Traj, as_traj
from stampc.worlds.pybullet.world import PyBulletWorld

CHARGER = "station"
#: the reserve kept for the way home: factor × straight-line distance + margin (m)
RESERVE_FACTOR = 1.5
RESERVE_MARGIN = 0.5


def _charger(world: PyBulletWorld) -> Any:
    box = world.regions.get(CHARGER)
    if box is None:
        raise StampcError([error("PB033", f"the aircraft domain needs a charging region "
                                 f"named {CHARGER!r}", Span.point("<scene regions>"),
                                 f"regions: {', '.join(sorted(world.regions))}")])
    return box


def flight_path(ctx: Context, u: str, a: str, b: str) -> Iterator[tuple[Traj]]:
    """Flights from the UAV's current pose into region ``b`` (``a`` is where the
    abstract state says the UAV is; the concrete start is the world's UAV pose)."""
    for _goal, traj in aerial.fly(ctx, b):
        yield (traj,)


def reserve(world: PyBulletWorld, end: tuple[float, ...]) -> float:
    """Battery (m of flight) to keep at ``end`` for the way back to the charger."""
    box = _charger(world)
    if box.contains(tuple(end[:3])):
        return 0.0
    return RESERVE_FACTOR * math.dist(end[:3], box.position) + RESERVE_MARGIN


def battery_suffices(ctx: Context, u: str, t: Any) -> bool:
    """Whether the battery left covers flight ``t`` plus the reserve at its end."""
    world = aerial._world(ctx)
    traj = as_traj(t)
    return aerial.path_length(traj) + reserve(world, traj.end) <= world.state.battery + 1e-9


def fly(ctx: Context, action: ConcreteAction) -> None:
    """Fly along ``t`` (battery drained by its length); a drift outcome ends the flight
    at the centre of the region it names (see :func:`aerial.fly_to`)."""
    aerial.fly_to(ctx, action)


def charge(ctx: Context, action: ConcreteAction) -> None:
    aerial.charge(ctx, action)


def inspect(ctx: Context, action: ConcreteAction) -> None:
    aerial.inspect(ctx, action)
