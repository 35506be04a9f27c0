"""Dynamics for execution: objects settle under gravity after every release and event.

Planning moves bodies kinematically (``resetBasePositionAndOrientation``). Execution asks
physics what really happens next: after each action, every object the action moved or
let go of (placed, dropped, discarded, toppled) is simulated under gravity until it comes
to rest (or :data:`MAX_STEPS`), and the world's state takes the poses physics reports.
A discarded object is dropped where the hand let go of it and lands in the tray (it
stays out of the symbolic scene: the world's ``removed`` set, drawn at its resting pose).
The held object hangs on a fixed constraint to the hand while the others settle.

Only the settling objects are dynamic; the rest are frozen (mass 0) for the duration, so
a settle never drifts objects that nothing touched. PyBullet is deterministic for the
same sequence of calls, and DIRECT mode is kept: same seed, same poses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable

from stampc.worlds.pybullet._pb import p
from stampc.worlds.pybullet.values import Pose
from stampc.worlds.pybullet.world import (G_HELD, G_MOVABLE, G_ROBOT, G_STATIC, G_UAV,
                                          PyBulletWorld)

TIME_STEP = 1.0 / 240.0
MAX_STEPS = 480          # 2 s of simulated time at most
REST_SPEED = 1e-3        # m/s and rad/s below which a body is at rest
REST_STEPS = 24          # consecutive steps at rest before stopping
MOVED = 1e-6             # m: a pose change smaller than this is no change
TIP_SPEED = 30.0         # rad/s: the push that tips a toppled object over (slower ones are
#                          absorbed by the table contact and the domino rocks back upright)
#: the collision filter of world.py for movable objects, restored after settling
MOVABLE_MASK = G_ROBOT | G_HELD | G_UAV
ALL = G_ROBOT | G_HELD | G_MOVABLE | G_STATIC | G_UAV


@dataclass
class Physics:
    """Settles what each action moved; ``on_frame(world)`` sees every ``frame_every``-th
    simulation step (for rendering), ``resting`` holds where discarded objects lie."""

    world: PyBulletWorld
    on_frame: Callable[[PyBulletWorld], None] | None = None
    frame_every: int = 12
    resting: dict[str, Pose] = field(default_factory=dict)
    _before: Any = None

    def before_action(self, world: Any, action: Any) -> None:
        self._before = world.state

    def after_action(self, world: Any, action: Any) -> None:
        before, after = self._before, world.state
        if before is None:
            return
        old, new = dict(before.poses), dict(after.poses)
        held_before, held_after = before.all_held(), after.all_held()
        moved = [n for n in new if n not in held_after and n not in after.removed
                 and (n not in old or old[n].distance(new[n]) > MOVED
                      or old[n].angle(new[n]) > MOVED)]
        dropped = sorted(after.removed - before.removed)
        released = [n for n in sorted(held_before - held_after) if n not in dropped
                    and n not in moved and n not in after.removed]
        starts = {n: new[n] for n in moved + released}
        # only an event lays a free-standing object down; a hand may turn what it put
        # (a Keva plank set upright), which is a placement, not a topple
        spins = {n: _tip_over(old[n], new[n]) for n in moved
                 if n in old and n not in held_before}
        for n, spin in spins.items():
            if spin is not None:  # toppled: let it fall from where it stood
                starts[n] = old[n]
        for n in dropped:  # let go where the hand holds it now (e.g. over the tray)
            held_here = n == before.held and before.grip is not None and world.robot >= 0
            starts[n] = world.ee_pose().multiply(before.grip) if held_here else old[n]
        if starts:
            self.settle(starts, {n: w for n, w in spins.items() if w is not None})

    def settle(self, starts: dict[str, Pose],
               spins: dict[str, tuple[float, float, float]] | None = None) -> dict[str, Pose]:
        """Simulate the bodies in ``starts`` from those poses (``spins``: initial angular
        velocities) until they rest; update the world state with their final poses
        (removed ones go to :attr:`resting`)."""
        world, cid = self.world, self.world.client
        names = sorted(starts)
        frozen = self._freeze_others(names)
        constraint = self._hold(world)
        for n in names:
            pose = starts[n]
            p.resetBasePositionAndOrientation(world.body[n], pose.pos, pose.quat,
                                              physicsClientId=cid)
            p.resetBaseVelocity(world.body[n], (0, 0, 0), (spins or {}).get(n, (0, 0, 0)),
                                physicsClientId=cid)
            p.setCollisionFilterGroupMask(world.body[n], -1, G_MOVABLE, ALL, physicsClientId=cid)
        statics = list(world.static_ids)
        for b in statics:
            p.setCollisionFilterGroupMask(b, -1, G_STATIC, ALL, physicsClientId=cid)
        p.setGravity(0, 0, -9.81, physicsClientId=cid)
        p.setTimeStep(TIME_STEP, physicsClientId=cid)
        try:
            self._run(names)
        finally:
            p.setGravity(0, 0, 0, physicsClientId=cid)
            for b in statics:
                p.setCollisionFilterGroupMask(b, -1, G_STATIC, MOVABLE_MASK, physicsClientId=cid)
            for n in names:
                p.setCollisionFilterGroupMask(world.body[n], -1, G_MOVABLE, MOVABLE_MASK,
                                              physicsClientId=cid)
            if constraint is not None:
                p.removeConstraint(constraint, physicsClientId=cid)
            self._unfreeze(frozen)
        final = {n: Pose.of(*p.getBasePositionAndOrientation(world.body[n],
                                                              physicsClientId=cid))
                 for n in names}
        self._record(final)
        return final

    def _run(self, names: list[str]) -> None:
        world, cid = self.world, self.world.client
        q = world.state.q
        still = 0
        for step in range(MAX_STEPS):
            p.stepSimulation(physicsClientId=cid)
            if world.robot >= 0:
                world.set_arm(q)  # the arm stands still; the held object rides on it
            if self.on_frame is not None and step % self.frame_every == 0:
                self.on_frame(world)
            fast = any(max(map(abs, lin + ang)) > REST_SPEED for lin, ang in (
                p.getBaseVelocity(world.body[n], physicsClientId=cid) for n in names))
            still = 0 if fast else still + 1
            if still >= REST_STEPS:
                break

    def _freeze_others(self, names: Iterable[str]) -> list[tuple[int, float]]:
        cid, frozen = self.world.client, []
        moving = {self.world.body[n] for n in names}
        for b in self.world.movable_ids - moving:
            mass = p.getDynamicsInfo(b, -1, physicsClientId=cid)[0]
            p.changeDynamics(b, -1, mass=0.0, physicsClientId=cid)
            frozen.append((b, mass))
        return frozen

    def _unfreeze(self, frozen: list[tuple[int, float]]) -> None:
        for b, mass in frozen:
            p.changeDynamics(b, -1, mass=mass, physicsClientId=self.world.client)

    def _hold(self, world: PyBulletWorld) -> int | None:
        """A fixed constraint from the hand to the held object (it must not fall)."""
        state = world.state
        if state.held is None or state.grip is None or world.robot < 0:
            return None
        return p.createConstraint(world.robot, world.model.ee_link, world.body[state.held],
                                  -1, p.JOINT_FIXED, (0, 0, 0), state.grip.pos, (0, 0, 0),
                                  state.grip.quat, (0, 0, 0, 1),
                                  physicsClientId=world.client)

    def _record(self, final: dict[str, Pose]) -> None:
        world = self.world
        removed = world.state.removed
        self.resting.update({n: pose for n, pose in final.items() if n in removed})
        kept = {n: pose for n, pose in final.items() if n not in removed}
        if kept:
            world.update(poses=tuple((n, kept.get(n, pose)) for n, pose in world.state.poses))
        for n, pose in final.items():
            if n in removed:  # drawn where it lies; out of the robot's way (in the bin)
                world.rest_removed(n, pose)


def _tip_over(before: Pose, after: Pose) -> tuple[float, float, float] | None:
    """The angular velocity that tips a body standing at ``before`` towards ``after``
    when an event laid it down (its up axis turned by more than 45°), else None."""
    from stampc.worlds.pybullet.values import quat_rotate

    up0, up1 = quat_rotate(before.quat, (0, 0, 1)), quat_rotate(after.quat, (0, 0, 1))
    if sum(a * b for a, b in zip(up0, up1)) > math.cos(math.pi / 4):
        return None
    dx, dy = after.pos[0] - before.pos[0], after.pos[1] - before.pos[1]
    norm = math.hypot(dx, dy)
    if norm < 1e-9:
        return None
    # ω along up × d tips the top towards d
    return (-dy / norm * TIP_SPEED, dx / norm * TIP_SPEED, 0.0)
