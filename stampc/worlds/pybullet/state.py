"""Value records of the PyBullet world: object geometry, the concrete state (per-robot
arm states, object poses, UAV) and the runtime handle of a robot body."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

from stampc.worlds.pybullet.scene import RobotModel, RobotSpec
from stampc.worlds.pybullet.values import Pose, quat_conjugate, quat_rotate


@dataclass(frozen=True)
class Geometry:
    """Shape facts the generators need: kind, dimensions and footprint."""

    kind: str  # "cylinder" | "box"
    dims: tuple[float, ...]  # (radius, height) | (sx, sy, sz)

    @property
    def height(self) -> float:
        return self.dims[1] if self.kind == "cylinder" else self.dims[2]

    def half_extent(self, quat: Sequence[float], axis: Sequence[float]) -> float:
        """Half the object's extent along unit ``axis``, the object turned by ``quat``
        (both in one frame): how far apart closed fingers stand along ``axis``."""
        local = quat_rotate(quat_conjugate(quat), axis)  # the axis in the object's frame
        if self.kind == "cylinder":
            along = min(1.0, abs(local[2]))
            return along * self.dims[1] / 2 + self.dims[0] * math.sqrt(1.0 - along * along)
        return sum(abs(c) * d / 2 for c, d in zip(local, self.dims))

    @property
    def footprint(self) -> float:
        """Radius of a circle around the object's base (for overlap tests)."""
        if self.kind == "cylinder":
            return self.dims[0]
        return 0.5 * (self.dims[0] ** 2 + self.dims[1] ** 2) ** 0.5


@dataclass(frozen=True)
class ArmState:
    """What changes for one robot: joints, base pose, the object in its hand."""

    q: tuple[float, ...]
    base: Pose
    #: the name of the candidate base pose the robot stands at (None: its initial pose)
    base_name: str | None = None
    held: str | None = None
    #: the held object's pose in the end-effector frame
    grip: Pose | None = None
    #: straight back-off the next arm motion starts with (set by pick and place)
    retreat: tuple[float, ...] | None = None
    released: str | None = None
    #: m each finger stands off ``released`` while the arm backs off (None: the world's
    #: ``RELEASE_SLACK``); a put-down may open less where a neighbour stands close
    release_slack: float | None = None


ARM_FIELDS = frozenset(ArmState.__dataclass_fields__)


@dataclass(frozen=True)
class WorldState:
    """Everything that changes while a plan executes (immutable: snapshots share it).

    ``q``, ``held``, ``grip``, ``retreat``, ``released`` read the *active* robot's
    fields (the one the last bound function selected, see ``PyBulletWorld.select``).
    """

    arms: tuple[ArmState, ...]
    poses: tuple[tuple[str, Pose], ...]
    uav: Pose | None = None
    battery: float = 0.0
    #: objects taken out of the scene (e.g. a crushed can thrown away)
    removed: frozenset[str] = frozenset()
    #: removed objects lying where physics let them come to rest (execution: a can in
    #: the tray); the other removed objects wait out of sight
    resting: tuple[tuple[str, Pose], ...] = ()
    #: index of the active robot: a selection, not part of the state's identity
    active: int = field(default=0, compare=False)

    def pose(self, name: str) -> Pose:
        return dict(self.poses)[name]

    @property
    def arm(self) -> ArmState | None:
        return self.arms[self.active] if self.arms else None

    @property
    def q(self) -> tuple[float, ...]:
        return self.arms[self.active].q if self.arms else ()

    @property
    def held(self) -> str | None:
        return self.arms[self.active].held if self.arms else None

    @property
    def grip(self) -> Pose | None:
        return self.arms[self.active].grip if self.arms else None

    @property
    def retreat(self) -> tuple[float, ...] | None:
        return self.arms[self.active].retreat if self.arms else None

    @property
    def released(self) -> str | None:
        return self.arms[self.active].released if self.arms else None

    def all_held(self) -> frozenset[str]:
        return frozenset(a.held for a in self.arms if a.held is not None)


@dataclass(frozen=True)
class Arm:
    """A robot body in the world and what kinematics needs to know about it."""

    name: str
    body: int
    model: RobotModel
    lower: tuple[float, ...]
    upper: tuple[float, ...]
    #: all non-fixed joints, in the order IK returns them
    ik_joints: tuple[int, ...]
    spec: RobotSpec
