"""Concrete value types of the PyBullet world and the rigid-transform math they need.

Quaternions follow PyBullet's ``(x, y, z, w)`` order. All value types are frozen, hashable
and JSON-friendly through ``to_json()`` so the refinement engine can record them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]

IDENTITY_QUAT: Quat = (0.0, 0.0, 0.0, 1.0)


# ------------------------------------------------------------------ transform math
def quat_multiply(a: Sequence[float], b: Sequence[float]) -> Quat:
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def quat_conjugate(q: Sequence[float]) -> Quat:
    return (-q[0], -q[1], -q[2], q[3])


def quat_rotate(q: Sequence[float], v: Sequence[float]) -> Vec3:
    x, y, z, _ = quat_multiply(quat_multiply(q, (v[0], v[1], v[2], 0.0)), quat_conjugate(q))
    return (x, y, z)


def quat_from_axis_angle(axis: Sequence[float], angle: float) -> Quat:
    n = math.sqrt(sum(a * a for a in axis))
    s = math.sin(angle / 2.0) / n
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(angle / 2.0))


def quat_from_yaw(yaw: float) -> Quat:
    return quat_from_axis_angle((0.0, 0.0, 1.0), yaw)


def yaw_of(q: Sequence[float]) -> float:
    """The heading (rotation about z) of the orientation ``q`` (x, y, z, w)."""
    x, y, z, w = q
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def quat_angle(a: Sequence[float], b: Sequence[float]) -> float:
    """The rotation angle between two orientations (0..pi)."""
    dot = abs(sum(x * y for x, y in zip(a, b)))
    return 2.0 * math.acos(min(1.0, dot))


def normalize_quat(q: Sequence[float]) -> Quat:
    n = math.sqrt(sum(c * c for c in q)) or 1.0
    if abs(n - 1.0) < 1e-12:  # keep unit quaternions bit-exact (JSON round trips)
        return (q[0], q[1], q[2], q[3])
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n)


# ------------------------------------------------------------------ value types
@dataclass(frozen=True)
class Pose:
    """A rigid pose: position (m) and orientation quaternion (x, y, z, w)."""

    pos: Vec3
    quat: Quat = IDENTITY_QUAT

    @staticmethod
    def of(pos: Sequence[float], quat: Sequence[float] = IDENTITY_QUAT) -> "Pose":
        if len(pos) != 3 or len(quat) != 4:
            raise ValueError("a pose needs 3 coordinates and a 4-component quaternion")
        return Pose(tuple(float(c) for c in pos), normalize_quat([float(c) for c in quat]))

    def multiply(self, other: "Pose") -> "Pose":
        """``self * other``: ``other`` expressed in ``self``'s frame, moved to the world."""
        rotated = quat_rotate(self.quat, other.pos)
        pos = tuple(a + b for a, b in zip(self.pos, rotated))
        return Pose(pos, normalize_quat(quat_multiply(self.quat, other.quat)))

    def inverse(self) -> "Pose":
        inv = quat_conjugate(self.quat)
        return Pose(tuple(-c for c in quat_rotate(inv, self.pos)), inv)

    def distance(self, other: "Pose") -> float:
        return math.dist(self.pos, other.pos)

    def angle(self, other: "Pose") -> float:
        return quat_angle(self.quat, other.quat)

    def to_json(self) -> dict:
        return {"pos": list(self.pos), "quat": list(self.quat)}


@dataclass(frozen=True)
class Grasp:
    """Where the hand sits relative to the object, and the direction it approaches from.

    ``hand`` is the end-effector (grasp target) pose in the object frame, so the hand's
    world pose is ``object_pose * hand``. ``approach`` is the unit direction of the final
    straight approach in the object frame (``(0, 0, -1)`` for a top grasp); the pre-grasp
    pose backs off against it by ``standoff`` metres.
    """

    hand: Pose
    approach: Vec3
    kind: str = "top"
    standoff: float = 0.1
    #: the robot and base pose the grasp was generated for (None: not recorded)
    robot: str | None = None
    base: Pose | None = None

    def pregrasp(self, object_pose: Pose) -> Pose:
        hand = object_pose.multiply(self.hand)
        back = quat_rotate(object_pose.quat, self.approach)
        return Pose(tuple(h - self.standoff * b for h, b in zip(hand.pos, back)), hand.quat)

    def to_json(self) -> dict:
        return {"hand": self.hand.to_json(), "approach": list(self.approach),
                "kind": self.kind, "standoff": self.standoff, **_owner(self)}


@dataclass(frozen=True)
class Config:
    """An arm configuration (joint vector, radians).

    ``obj`` names the object this configuration grasps or places, and ``pre`` is the
    pre-grasp / pre-place configuration the arm passes through on its straight approach
    (and backs off to afterwards).
    """

    q: tuple[float, ...]
    obj: str | None = None
    pre: tuple[float, ...] | None = None
    #: the robot whose joints these are and its base pose (None: not recorded)
    robot: str | None = None
    base: Pose | None = None

    @staticmethod
    def of(q: Sequence[float], obj: str | None = None, pre: Sequence[float] | None = None,
           robot: str | None = None, base: Pose | None = None) -> "Config":
        return Config(tuple(float(v) for v in q), obj,
                      None if pre is None else tuple(float(v) for v in pre), robot, base)

    def to_json(self) -> dict:
        out: dict = {"q": list(self.q)}
        if self.obj is not None:
            out["obj"] = self.obj
        if self.pre is not None:
            out["pre"] = list(self.pre)
        return {**out, **_owner(self)}


@dataclass(frozen=True)
class Traj:
    """A joint-space path.

    ``configs[:retreat_end + 1]`` is the initial straight back-off from the previous
    contact (lifting a just-picked object or leaving a just-placed ``released`` one);
    ``configs[approach_start:]`` the final straight approach to ``target``. Contacts of
    the held object with support surfaces, and of the hand with ``released``/``target``,
    are expected in those two stretches only.
    """

    configs: tuple[tuple[float, ...], ...]
    held: str | None = None
    target: str | None = None
    released: str | None = None
    retreat_end: int = 0
    approach_start: int = -1
    #: True when planned against static obstacles only (it may hit movable objects)
    static_only: bool = False
    #: the robot that moves and its base pose (None: not recorded)
    robot: str | None = None
    base: Pose | None = None

    def __post_init__(self) -> None:
        if self.approach_start < 0:
            object.__setattr__(self, "approach_start", len(self.configs))

    @property
    def start(self) -> tuple[float, ...]:
        return self.configs[0]

    @property
    def end(self) -> tuple[float, ...]:
        return self.configs[-1]

    def length(self) -> float:
        """Joint-space path length (radians, Euclidean)."""
        return sum(math.dist(a, b) for a, b in zip(self.configs, self.configs[1:]))

    def to_json(self) -> dict:
        return {"configs": [list(c) for c in self.configs], "held": self.held,
                "target": self.target, "released": self.released,
                "retreat_end": self.retreat_end, "approach_start": self.approach_start,
                "static_only": self.static_only, **_owner(self)}


@dataclass(frozen=True)
class Base:
    """A base pose of a mobile robot: which robot, the candidate's name, where."""

    robot: str
    name: str
    pose: Pose

    def to_json(self) -> dict:
        return {"robot": self.robot, "name": self.name, "pose": self.pose.to_json()}


def _owner(value: "Grasp | Config | Traj") -> dict:
    """The JSON fields naming the robot and base pose a value belongs to (if recorded)."""
    out: dict = {}
    if value.robot is not None:
        out["robot"] = value.robot
    if value.base is not None:
        out["base"] = value.base.to_json()
    return out


def interpolate(a: Sequence[float], b: Sequence[float], step: float) -> list[tuple[float, ...]]:
    """Points from ``a`` to ``b`` (both included) no further apart than ``step``."""
    n = max(1, math.ceil(math.dist(a, b) / step))
    return [tuple(x + (y - x) * i / n for x, y in zip(a, b)) for i in range(n + 1)]


def quat_from_axes(x: Sequence[float], y: Sequence[float], z: Sequence[float]) -> Quat:
    """Quaternion of the rotation whose matrix has columns ``x``, ``y``, ``z``."""
    m00, m10, m20 = x
    m01, m11, m21 = y
    m02, m12, m22 = z
    trace = m00 + m11 + m22
    if trace > 0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = ((m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25 * s)
    elif m00 > m11 and m00 > m22:
        s = 2.0 * math.sqrt(1.0 + m00 - m11 - m22)
        q = (0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s)
    elif m11 > m22:
        s = 2.0 * math.sqrt(1.0 + m11 - m00 - m22)
        q = ((m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + m22 - m00 - m11)
        q = ((m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s)
    return normalize_quat(q)


# ------------------------------------------------------------------ coercion
def _bad_value(kind: str, value: object) -> Exception:
    from stampc.diagnostics import Span, StampcError, error

    return StampcError([error("PB014", f"expected a {kind}, got {type(value).__name__}: "
                              f"{str(value)[:80]}", Span.point("<value>"),
                              f"pass a {kind} or its to_json() form")])


def as_pose(value: object) -> Pose:
    """Accept a :class:`Pose` or its ``to_json()`` dict; raise ``StampcError`` otherwise."""
    if isinstance(value, Pose):
        return value
    try:
        return Pose.of(value["pos"], value.get("quat", IDENTITY_QUAT))  # type: ignore[index,union-attr]
    except (TypeError, KeyError, AttributeError, ValueError, ZeroDivisionError):
        raise _bad_value("Pose", value) from None


def _base_of(data: object) -> Pose | None:
    return None if data is None else as_pose(data)


def as_config(value: object) -> Config:
    if isinstance(value, Config):
        return value
    try:
        return Config.of(value["q"], value.get("obj"), value.get("pre"),  # type: ignore[index,union-attr]
                         value.get("robot"), _base_of(value.get("base")))  # type: ignore[union-attr]
    except (TypeError, KeyError, AttributeError, ValueError):
        raise _bad_value("Config", value) from None


def as_traj(value: object) -> Traj:
    if isinstance(value, Traj):
        return value
    try:
        data = dict(value)  # type: ignore[call-overload]
        configs = tuple(tuple(float(v) for v in c) for c in data.pop("configs"))
        data["base"] = _base_of(data.get("base"))
        return Traj(configs, **data)
    except (TypeError, KeyError, AttributeError, ValueError):
        raise _bad_value("Traj", value) from None


def as_base(value: object) -> Base:
    if isinstance(value, Base):
        return value
    try:
        return Base(str(value["robot"]), str(value["name"]), as_pose(value["pose"]))  # type: ignore[index]
    except (TypeError, KeyError, AttributeError, ValueError):
        raise _bad_value("Base", value) from None
