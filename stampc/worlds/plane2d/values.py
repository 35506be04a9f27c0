"""Concrete value types of the plane2d world (frozen, hashable, JSON-friendly).

Bound functions accept these types, and also their JSON form (what ``to_json()``
returns, or a plain sequence of numbers), so that values that went through a policy
file or a log can be fed back. Malformed values raise :class:`StampcError` with a
``S260`` diagnostic rather than a raw exception.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

from stampc.diagnostics import Span, StampcError, error

Point = tuple[float, float]


@dataclass(frozen=True)
class Pose2:
    """An object pose on the table: position (m) and heading (rad)."""

    x: float
    y: float
    theta: float = 0.0

    @property
    def xy(self) -> Point:
        return (self.x, self.y)

    def to_json(self) -> dict:
        return {"x": self.x, "y": self.y, "theta": self.theta}


@dataclass(frozen=True)
class Grasp2:
    """Approach direction (rad) from the object's centre to the gripper, in the object's
    frame (0 = along the object's local x axis)."""

    angle: float

    def to_json(self) -> dict:
        return {"angle": self.angle}


@dataclass(frozen=True)
class Config2:
    """A gripper position; ``target`` names the object this configuration is about
    (grasped or placed), which is never an obstacle for its own approach."""

    x: float
    y: float
    target: str | None = None

    @property
    def xy(self) -> Point:
        return (self.x, self.y)

    def to_json(self) -> dict:
        return {"x": self.x, "y": self.y, "target": self.target}


@dataclass(frozen=True)
class Traj2:
    """A gripper (or UAV) polyline from the current position to a configuration."""

    points: tuple[Point, ...]
    held: str | None = None
    target: str | None = None

    @property
    def start(self) -> Point:
        return self.points[0]

    @property
    def end(self) -> Point:
        return self.points[-1]

    @property
    def length(self) -> float:
        return sum(math.dist(a, b) for a, b in zip(self.points, self.points[1:]))

    def to_json(self) -> dict:
        return {"points": [list(p) for p in self.points], "held": self.held,
                "target": self.target}


# ------------------------------------------------------------------- coercion
def _bad(kind: str, value: Any) -> StampcError:
    text = repr(value)
    if len(text) > 80:
        text = text[:77] + "..."
    return StampcError([error("S260", f"plane2d: expected a {kind}, got {text}",
                              Span.point("<plane2d value>"),
                              hint=f"pass a {kind} or its to_json() form")])


def _num(v: Any, kind: str, whole: Any) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise _bad(kind, whole)
    return float(v)


def _name(v: Any, kind: str, whole: Any) -> str | None:
    if v is None or isinstance(v, str):
        return v
    raise _bad(kind, whole)


def as_pose(v: Any) -> Pose2:
    if isinstance(v, Pose2):
        return v
    if isinstance(v, Mapping) and "x" in v and "y" in v:
        return Pose2(_num(v["x"], "Pose2", v), _num(v["y"], "Pose2", v),
                     _num(v.get("theta", 0.0), "Pose2", v))
    if isinstance(v, Sequence) and not isinstance(v, str) and len(v) in (2, 3):
        return Pose2(*(_num(c, "Pose2", v) for c in v))
    raise _bad("Pose2", v)


def as_grasp(v: Any) -> Grasp2:
    if isinstance(v, Grasp2):
        return v
    if isinstance(v, Mapping) and "angle" in v:
        return Grasp2(_num(v["angle"], "Grasp2", v))
    if isinstance(v, (int, float)) and not isinstance(v, bool):
        return Grasp2(_num(v, "Grasp2", v))
    raise _bad("Grasp2", v)


def as_config(v: Any) -> Config2:
    if isinstance(v, Config2):
        return v
    if isinstance(v, Mapping) and "x" in v and "y" in v:
        return Config2(_num(v["x"], "Config2", v), _num(v["y"], "Config2", v),
                       _name(v.get("target"), "Config2", v))
    if isinstance(v, Sequence) and not isinstance(v, str) and len(v) == 2:
        return Config2(_num(v[0], "Config2", v), _num(v[1], "Config2", v))
    raise _bad("Config2", v)


def as_traj(v: Any) -> Traj2:
    if isinstance(v, Traj2):
        return v
    if isinstance(v, Mapping) and "points" in v:
        pts = v["points"]
        if not isinstance(pts, Sequence) or isinstance(pts, str) or not pts:
            raise _bad("Traj2", v)
        points = []
        for p in pts:
            if not isinstance(p, Sequence) or isinstance(p, str) or len(p) != 2:
                raise _bad("Traj2", v)
            points.append((_num(p[0], "Traj2", v), _num(p[1], "Traj2", v)))
        return Traj2(tuple(points), _name(v.get("held"), "Traj2", v),
                     _name(v.get("target"), "Traj2", v))
    raise _bad("Traj2", v)


_DECODERS = {
    frozenset(("x", "y", "theta")): as_pose,
    frozenset(("x", "y", "target")): as_config,
    frozenset(("angle",)): as_grasp,
    frozenset(("points", "held", "target")): as_traj,
}


def decode(data: Any) -> Any:
    """Inverse of ``to_json()`` for the plane2d value types (policy files store values as
    JSON); anything that is not one of their JSON forms is returned unchanged."""
    if isinstance(data, Mapping):
        convert = _DECODERS.get(frozenset(data))
        if convert is not None:
            return convert(data)
    return data
