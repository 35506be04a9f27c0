"""The independent re-check: before an action runs, every trajectory it follows is swept
against the objects' current concrete poses, with what is held attached, at 10× the
planning resolution. Each contact outside the task's own (the hand at its target, a
held object on its support while lifting or setting down) counts as a collision.

* PyBullet arm paths: every ``CHECK_RESOLUTION`` rad (``PLAN_RESOLUTION / 10``, 0.005
  rad: the configurations refinement's final check tested, now in the state execution
  reached), with the same stretch rules as planning
  (:func:`stampc.worlds.pybullet.planning.bad_bodies`) but without planning's 1 mm
  clearance from movable objects (``world.CLEARANCE``): only penetration counts, of a
  movable object at any depth, of a static one deeper than 0.1 mm;
* PyBullet UAV flights: every ``FLY_RESOLUTION / 10`` m (5 mm);
* plane2d: the swept discs of the gripper (and held object) or the UAV along the
  polyline, densified 10× (the test per segment is exact).

A recheck returns the names of the bodies hit (empty: clear).
"""

from __future__ import annotations

import math
from typing import Any, Callable

REFINE = 10  # × the planning resolution


def recheck_for(world: Any) -> Callable[[Any, Any], list[str]]:
    from stampc.worlds.plane2d.world import Plane2DWorld

    return plane2d_recheck if isinstance(world, Plane2DWorld) else pybullet_recheck


def _trajectories(action: Any, kind: type) -> list[Any]:
    return [v for v in action.args.values() if isinstance(v, kind)]


def pybullet_trajectories(action: Any) -> list[Any]:
    """The PyBullet trajectories among ``action``'s arguments; a policy file stores them
    as JSON (``{"configs": ...}``), decoded here."""
    from stampc.worlds.pybullet.values import Traj, as_traj

    return [as_traj(v) for v in action.args.values()
            if isinstance(v, Traj) or (isinstance(v, dict) and "configs" in v)]


# ------------------------------------------------------------------ PyBullet
def pybullet_recheck(world: Any, action: Any) -> list[str]:
    hits: set[str] = set()
    for traj in pybullet_trajectories(action):
        if traj.configs and len(traj.configs[0]) == 7 and world.uav >= 0:
            hits |= _flight_hits(world, traj)
        elif world.robot >= 0:
            hits |= _arm_hits(world, traj)
    return sorted(hits)


def _arm_hits(world: Any, traj: Any) -> set[str]:
    from stampc.worlds.pybullet.planning import CHECK_RESOLUTION, bad_bodies, stretches
    from stampc.worlds.pybullet.values import interpolate

    if traj.robot is not None and traj.robot in world.arms:
        world.select(traj.robot)  # the arm that follows it (two-arm Keva), not the last one
    state = world.state
    hit: set[int] = set()
    try:
        for kind, a, b in stretches(traj) or [("middle", traj.start, traj.start)]:
            for q in interpolate(a, b, CHECK_RESOLUTION):
                hit |= bad_bodies(world, q, kind, state.held, traj.target, traj.released,
                                  clearance=0.0)
    finally:
        world.set_arm(state.q)
    return {world.name_of.get(b, f"body{b}") if b != world.robot else "robot (self)"
            for b in hit}


def _flight_hits(world: Any, traj: Any) -> set[str]:
    from stampc.worlds.pybullet.aerial import FLY_RESOLUTION, flight_contacts

    return {world.name_of.get(b, f"body{b}")
            for b in flight_contacts(world, traj, FLY_RESOLUTION / REFINE)}


# ------------------------------------------------------------------ plane2d
def plane2d_recheck(world: Any, action: Any) -> list[str]:
    from stampc.worlds.plane2d.values import Traj2

    hits: set[str] = set()
    for traj in _trajectories(action, Traj2):
        points = _densified(traj.points)
        uav = world.uav
        if uav is not None and traj.points and math.dist(traj.points[0], uav) < 1e-9 \
                and world.scene.uav is not None:
            checker = world.checker(footprints=(((0.0, 0.0), world.scene.uav.radius),),
                                    reach=math.inf)
        else:
            exclude = tuple(n for n in (traj.target, world.held) if n is not None)
            checker = world.checker(exclude=exclude)
        hits |= set(checker.blockers(points))
    return sorted(hits)


def _densified(points: tuple) -> list[tuple[float, float]]:
    out = [tuple(points[0])] if points else []
    for a, b in zip(points, points[1:]):
        out += [(a[0] + (b[0] - a[0]) * i / REFINE, a[1] + (b[1] - a[1]) * i / REFINE)
                for i in range(1, REFINE + 1)]
    return out
