"""The JSON-friendly scene format: the frozen specs a scene is read into
(validation: :func:`stampc.worlds.pybullet.scene_check.parse_scene`).

A scene is a plain dict (see ``docs/worlds-pybullet.md``)::

    {"robot": {"model": "panda", "base": [0, 0, 0], "yaw": 0},
     # or several, each optionally a mobile base with named candidate base poses:
     # "robots": [{"name": "left", "model": "panda", "base": [...], "yaw": 0,
     #             "bases": [{"name": "north", "base": [x, y, 0], "yaw": 0}, ...],
     #             "start": "north", "grasps": "side"}],   # grasps: top (default) / side / any
     "surfaces": [{"name": "table", "size": [sx, sy, sz], "position": [x, y, z]}],
     "objects": [{"name": "can0", "shape": "cylinder", "radius": 0.03, "height": 0.15,
                  "position": [x, y, z], "yaw": 0, "mass": 0.1, "color": [r, g, b, a]},
                 {"name": "d0", "urdf": "domino/domino.urdf", "scale": 1.0, ...}],
     "poses": {"pose_can0": "can0"},
     "regions": [{"name": "left_wing", "size": [...], "position": [...]}],
     "uav": {"size": [0.3, 0.3, 0.08], "position": [...], "battery": 20.0,
             "bounds": {"low": [...], "high": [...]}}}

Positions are body-frame origins (the centre of a primitive shape).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Mapping, Sequence


SCENE_FILE = "<scene>"


@dataclass(frozen=True)
class RobotModel:
    """What the world needs to know about an arm from ``pybullet_data``."""

    urdf: str
    arm_joints: tuple[int, ...]
    ee_link: int
    rest: tuple[float, ...]
    finger_joints: tuple[int, ...] = ()
    finger_open: float = 0.0
    #: link pairs whose contact is an artefact of the meshes (always touching)
    ignored_self_pairs: tuple[tuple[int, int], ...] = ()
    #: the end-effector frame's z axis is the approach direction, y the closing direction
    self_collision: bool = True


#: the grasp kinds a robot entry may name (``"grasps"``)
GRASP_KINDS = ("top", "side", "any")

#: The robot-model table (read-only); add an entry to support another arm.
ROBOT_MODELS: Mapping[str, RobotModel] = MappingProxyType({
    "panda": RobotModel(
        urdf="franka_panda/panda.urdf",
        arm_joints=(0, 1, 2, 3, 4, 5, 6),
        ee_link=11,  # panda_grasptarget: between the fingertips
        rest=(0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785),
        finger_joints=(9, 10),
        finger_open=0.04,
        ignored_self_pairs=((6, 8),),
    ),
    "kuka_iiwa": RobotModel(
        urdf="kuka_iiwa/model.urdf",
        arm_joints=(0, 1, 2, 3, 4, 5, 6),
        ee_link=6,
        rest=(0.0, 0.5, 0.0, -1.5, 0.0, 1.0, 0.0),
        self_collision=False,
    ),
})


@dataclass(frozen=True)
class BaseSpec:
    """A named base pose a mobile robot can be moved to (position of the base, yaw)."""

    name: str
    base: tuple[float, float, float]
    yaw: float


@dataclass(frozen=True)
class RobotSpec:
    """One robot: its model, initial base pose and (for a mobile base) the candidate
    base poses it can be re-placed at."""

    model: str
    base: tuple[float, float, float]
    yaw: float
    name: str = "robot"
    bases: tuple[BaseSpec, ...] = ()
    #: the candidate base the robot starts at (None: its ``base``/``yaw`` fields)
    start: str | None = None
    #: the grasps its grasp generators and reach checks use: "top", "side" or "any"
    grasps: str = "top"


@dataclass(frozen=True)
class BoxSpec:
    """A fixed box (surface) or a named region (no body, used by the UAV)."""

    name: str
    size: tuple[float, float, float]
    position: tuple[float, float, float]
    color: tuple[float, float, float, float] = (0.6, 0.45, 0.3, 1.0)

    @property
    def top(self) -> float:
        return self.position[2] + self.size[2] / 2.0

    def contains(self, point: Sequence[float], margin: float = 0.0) -> bool:
        return all(abs(p - c) <= s / 2.0 - margin
                   for p, c, s in zip(point, self.position, self.size))


@dataclass(frozen=True)
class ObjectSpec:
    name: str
    shape: str  # "cylinder" | "box" | "urdf"
    dims: tuple[float, ...]  # (radius, height) | (sx, sy, sz) | () for urdf
    position: tuple[float, float, float]
    yaw: float = 0.0
    mass: float = 0.1
    color: tuple[float, float, float, float] = (0.8, 0.2, 0.2, 1.0)
    urdf: str | None = None
    scale: float = 1.0


@dataclass(frozen=True)
class UavSpec:
    name: str
    size: tuple[float, float, float]
    position: tuple[float, float, float]
    low: tuple[float, float, float]
    high: tuple[float, float, float]
    battery: float
    mass: float = 1.0


@dataclass(frozen=True)
class SceneSpec:
    robots: tuple[RobotSpec, ...]
    surfaces: tuple[BoxSpec, ...]
    objects: tuple[ObjectSpec, ...]
    poses: tuple[tuple[str, str], ...]
    regions: tuple[BoxSpec, ...]
    uav: UavSpec | None
    #: the scene's free-form ``meta`` section, read-only (domain bindings may read it,
    #: e.g. the keva structure's slot poses); not compared
    meta: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}),
                                    compare=False)

    @property
    def robot(self) -> RobotSpec | None:
        """The first robot (the only one in single-robot scenes), or None."""
        return self.robots[0] if self.robots else None
