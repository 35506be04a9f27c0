"""Scene format of the plane2d world: a JSON-friendly dict, validated into a frozen
:class:`Scene`.

Every problem is reported (all at once) as an ``S2xx`` diagnostic naming the offending
key path, e.g. ``objects[2].radius: must be a positive number``; nothing raises a raw
``KeyError``/``TypeError``. See docs/worlds-plane2d.md for the format.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

from stampc.diagnostics import Diagnostic, Span, StampcError, error
from stampc.worlds.plane2d.geometry import Box, Disc, Shape
from stampc.worlds.plane2d.values import Pose2

#: pseudo-object names usable in ``poses`` besides movable objects
GRIPPER = "gripper"
UAV = "uav"


@dataclass(frozen=True)
class Rect:
    x0: float
    y0: float
    x1: float
    y1: float

    def contains(self, x: float, y: float, margin: float = 0.0) -> bool:
        return (self.x0 + margin <= x <= self.x1 - margin
                and self.y0 + margin <= y <= self.y1 - margin)

    @property
    def centre(self) -> tuple[float, float]:
        return ((self.x0 + self.x1) / 2, (self.y0 + self.y1) / 2)

    def to_json(self) -> dict:
        return {"x0": self.x0, "y0": self.y0, "x1": self.x1, "y1": self.y1}


@dataclass(frozen=True)
class ObjectSpec:
    """A movable (or static) object: ``shape`` is ``"disc"`` or ``"box"``."""

    name: str
    shape: str
    radius: float = 0.0           # discs
    hx: float = 0.0               # boxes: half extents
    hy: float = 0.0

    @property
    def bounding_radius(self) -> float:
        return self.radius if self.shape == "disc" else math.hypot(self.hx, self.hy)

    def at(self, pose: Pose2) -> Shape:
        if self.shape == "disc":
            return Disc(pose.x, pose.y, self.radius)
        return Box(pose.x, pose.y, self.hx, self.hy, pose.theta)


@dataclass(frozen=True)
class Robot:
    """The gripper's reach disc around ``base`` (where the robot starts). A mobile robot
    also lists named candidate ``bases`` (name, position) it may drive between."""

    base: tuple[float, float]
    gripper_radius: float
    reach: float
    bases: tuple[tuple[str, tuple[float, float]], ...] = ()

    def base_named(self, name: str) -> tuple[float, float] | None:
        return dict(self.bases).get(name)


@dataclass(frozen=True)
class UavSpec:
    start: str
    battery: float
    radius: float


@dataclass(frozen=True)
class Scene:
    table: Rect
    robot: Robot
    workspace: Rect
    surfaces: tuple[tuple[str, Rect], ...]
    objects: tuple[ObjectSpec, ...]
    initial_poses: tuple[tuple[str, Pose2], ...]
    obstacles: tuple[tuple[ObjectSpec, Pose2], ...] = ()
    poses: tuple[tuple[str, str], ...] = ()
    regions: tuple[tuple[str, Rect], ...] = ()
    uav: UavSpec | None = None

    def surface(self, name: str) -> Rect | None:
        return dict(self.surfaces).get(name)

    def region(self, name: str) -> Rect | None:
        return dict(self.regions).get(name)

    def spec(self, name: str) -> ObjectSpec | None:
        return next((o for o in self.objects if o.name == name), None)

    def static_shapes(self) -> tuple[Shape, ...]:
        return tuple(spec.at(pose) for spec, pose in self.obstacles)


# ------------------------------------------------------------------ parsing
class _Parser:
    def __init__(self, source: str):
        self.span = Span.point(source)
        self.diags: list[Diagnostic] = []

    def fail(self, path: str, message: str, hint: str | None = None) -> None:
        self.diags.append(error("S201", f"scene {path}: {message}", self.span, hint=hint))

    def number(self, data: Any, key: str, path: str, *, positive: bool = False,
               default: float | None = None) -> float:
        if not isinstance(data, Mapping) or key not in data:
            if default is not None:
                return default
            self.fail(f"{path}.{key}", "missing")
            return 1.0
        v = data[key]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                or (positive and v <= 0):
            self.fail(f"{path}.{key}", f"must be a {'positive ' if positive else ''}number, "
                      f"got {v!r}")
            return 1.0
        return float(v)

    def pair(self, v: Any, path: str, *, positive: bool = False) -> tuple[float, float]:
        ok = (isinstance(v, Sequence) and not isinstance(v, str) and len(v) == 2
              and all(isinstance(c, (int, float)) and not isinstance(c, bool)
                      and math.isfinite(c) and (c > 0 or not positive) for c in v))
        if not ok:
            self.fail(path, f"must be a pair of {'positive ' if positive else ''}numbers, "
                      f"got {v!r}")
            return (1.0, 1.0)
        return (float(v[0]), float(v[1]))

    def rect(self, v: Any, path: str) -> Rect:
        if not isinstance(v, Mapping):
            self.fail(path, 'must be a rectangle {"x0","y0","x1","y1"}')
            return Rect(0.0, 0.0, 1.0, 1.0)
        r = Rect(*(self.number(v, k, path) for k in ("x0", "y0", "x1", "y1")))
        if not (r.x0 < r.x1 and r.y0 < r.y1):
            self.fail(path, "needs x0 < x1 and y0 < y1")
        return r

    def named_rects(self, v: Any, path: str) -> tuple[tuple[str, Rect], ...]:
        if v is None:
            return ()
        if isinstance(v, Mapping):
            items = [(k, r) for k, r in v.items()]
        elif isinstance(v, Sequence) and not isinstance(v, str):
            items = [(r.get("name") if isinstance(r, Mapping) else None, r) for r in v]
        else:
            self.fail(path, "must map names to rectangles")
            return ()
        out = []
        for i, (name, r) in enumerate(items):
            if not isinstance(name, str) or not name:
                self.fail(f"{path}[{i}]", "needs a non-empty string name")
                continue
            out.append((name, self.rect(r, f"{path}.{name}")))
        return tuple(out)

    def shape(self, v: Any, path: str) -> tuple[ObjectSpec, Pose2] | None:
        if not isinstance(v, Mapping):
            self.fail(path, "must be an object description")
            return None
        name = v.get("name")
        if not isinstance(name, str) or not name:
            self.fail(f"{path}.name", "must be a non-empty string")
            name = f"?{path}"
        kind = v.get("shape", "disc")
        pose = Pose2(self.number(v, "x", path), self.number(v, "y", path),
                     self.number(v, "theta", path, default=0.0))
        if kind == "disc":
            return ObjectSpec(name, "disc", radius=self.number(v, "radius", path, positive=True)), pose
        if kind == "box":
            w, h = self.pair(v.get("size"), f"{path}.size", positive=True)
            return ObjectSpec(name, "box", hx=w / 2, hy=h / 2), pose
        self.fail(f"{path}.shape", f"must be 'disc' or 'box', got {kind!r}")
        return None

    def shapes(self, v: Any, path: str) -> list[tuple[ObjectSpec, Pose2]]:
        if v is None:
            return []
        if not isinstance(v, Sequence) or isinstance(v, str):
            self.fail(path, "must be a list of objects")
            return []
        out, seen = [], set()
        for i, item in enumerate(v):
            parsed = self.shape(item, f"{path}[{i}]")
            if parsed is None:
                continue
            if parsed[0].name in seen:
                self.fail(f"{path}[{i}].name", f"duplicate object name {parsed[0].name!r}")
            seen.add(parsed[0].name)
            out.append(parsed)
        return out


def parse_scene(data: Any, *, source: str = "<scene>") -> Scene:
    """Validate a scene dict; raise :class:`StampcError` listing every problem found."""
    p = _Parser(source)
    if not isinstance(data, Mapping):
        p.fail("", f"must be a JSON object, got {type(data).__name__}")
        raise StampcError(p.diags)
    table = p.rect(data.get("table"), "table")
    robot_data = data.get("robot")
    if isinstance(robot_data, Mapping):
        robot = _robot(p, robot_data)
    else:
        p.fail("robot", 'missing {"base": [x, y], "gripper_radius": r, "reach": R}')
        robot = Robot((0.0, 0.0), 1.0, 1.0)
    surfaces = p.named_rects(data.get("surfaces"), "surfaces")
    if "table" not in dict(surfaces):
        surfaces = (("table", table),) + surfaces
    regions = p.named_rects(data.get("regions"), "regions")
    movables = p.shapes(data.get("objects"), "objects")
    obstacles = p.shapes(data.get("obstacles"), "obstacles")
    names = {s.name for s, _ in movables}
    clash = names & {s.name for s, _ in obstacles} | (names & {GRIPPER, UAV})
    for n in sorted(clash):
        p.fail("objects", f"name {n!r} is reserved or used twice")
    uav = _uav(p, data.get("uav"), dict(regions))
    poses = _poses(p, data.get("poses"), names | {GRIPPER} | ({UAV} if uav else set()))
    workspace = (p.rect(data["workspace"], "workspace") if "workspace" in data
                 else _default_workspace(table, robot, surfaces, regions))
    if p.diags:
        raise StampcError(p.diags)
    return Scene(table, robot, workspace, surfaces, tuple(s for s, _ in movables),
                 tuple((s.name, pose) for s, pose in movables), tuple(obstacles),
                 poses, regions, uav)


def _poses(p: _Parser, v: Any, names: set[str]) -> tuple[tuple[str, str], ...]:
    if v is None:
        return ()
    if not isinstance(v, Mapping):
        p.fail("poses", 'must map pose symbols to object names, e.g. {"pose_can0": "can0"}')
        return ()
    out = []
    for sym, obj in v.items():
        if not isinstance(obj, str) or obj not in names:
            p.fail(f"poses.{sym}", f"names no object of the scene: {obj!r}")
            continue
        out.append((str(sym), obj))
    return tuple(out)


def _uav(p: _Parser, v: Any, regions: dict[str, Rect]) -> UavSpec | None:
    if v is None:
        return None
    if not isinstance(v, Mapping):
        p.fail("uav", 'must be {"start": region, "battery": B, "radius": r}')
        return None
    start = v.get("start")
    if start not in regions:
        p.fail("uav.start", f"must name a region, got {start!r}",
               hint="known regions: " + ", ".join(sorted(regions)) if regions else None)
    return UavSpec(str(start), p.number(v, "battery", "uav", positive=True),
                   p.number(v, "radius", "uav", positive=True, default=0.05))


def _robot(p: _Parser, data: Mapping) -> Robot:
    """``{"base": [x, y], ...}`` or, for a mobile robot, ``{"bases": [{"name": "b0",
    "base": [x, y]}, ...], "start": "b0", ...}`` (``base`` then defaults to the start's)."""
    radius = p.number(data, "gripper_radius", "robot", positive=True)
    reach = p.number(data, "reach", "robot", positive=True)
    if "bases" not in data:
        return Robot(p.pair(data.get("base"), "robot.base"), radius, reach)
    bases = _bases(p, data["bases"])
    start = data.get("start", bases[0][0] if bases else None)
    where = dict(bases).get(start) if isinstance(start, str) else None
    if bases and where is None:
        p.fail("robot.start", f"must name one of the robot's bases, got {start!r}",
               hint="bases: " + ", ".join(n for n, _ in bases))
    base = p.pair(data["base"], "robot.base") if "base" in data else (where or (0.0, 0.0))
    return Robot(base, radius, reach, bases)


def _bases(p: _Parser, v: Any) -> tuple[tuple[str, tuple[float, float]], ...]:
    if not isinstance(v, Sequence) or isinstance(v, str) or not v:
        p.fail("robot.bases", 'must be a non-empty list of {"name": ..., "base": [x, y]}')
        return ()
    out: dict[str, tuple[float, float]] = {}
    for i, item in enumerate(v):
        name = item.get("name") if isinstance(item, Mapping) else None
        if not isinstance(name, str) or not name or name in out:
            p.fail(f"robot.bases[{i}].name", f"must be a new non-empty string, got {name!r}")
            continue
        out[name] = p.pair(item.get("base"), f"robot.bases[{i}].base")
    return tuple(out.items())


def _default_workspace(table: Rect, robot: Robot, surfaces, regions) -> Rect:
    rects = [table] + [r for _, r in surfaces] + [r for _, r in regions]
    pad = robot.gripper_radius
    stands = [robot.base] + [xy for _, xy in robot.bases]
    xs = [r.x0 for r in rects] + [x - pad for x, _ in stands]
    ys = [r.y0 for r in rects] + [y - pad for _, y in stands]
    xe = [r.x1 for r in rects] + [x + pad for x, _ in stands]
    ye = [r.y1 for r in rects] + [y + pad for _, y in stands]
    return Rect(min(xs) - pad, min(ys) - pad, max(xe) + pad, max(ye) + pad)
