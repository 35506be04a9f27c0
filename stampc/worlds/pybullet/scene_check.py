"""Validation of the JSON-friendly scene format (``scene.py``; ``docs/worlds-pybullet.md``).

:func:`parse_scene` turns a scene dict into frozen specs or raises :class:`StampcError`
with located diagnostics (the span file is ``<scene SECTION>``, e.g. ``<scene objects>``;
the "line" is the index of the offending entry, 1-based).
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Any, Mapping, Sequence

from stampc.diagnostics import Diagnostic, Span, StampcError, error
from stampc.worlds.pybullet.scene import (GRASP_KINDS, ROBOT_MODELS, SCENE_FILE, BaseSpec,
                                          BoxSpec, ObjectSpec, RobotSpec, SceneSpec, UavSpec)


class _Checker:
    """Collects diagnostics while reading fields of one scene."""

    def __init__(self) -> None:
        self.diags: list[Diagnostic] = []
        self.section = ""

    def fail(self, where: int, message: str, hint: str | None = None) -> None:
        file = f"<scene {self.section}>" if self.section else SCENE_FILE
        self.diags.append(error("PB001", message, Span.point(file, max(1, where)), hint))

    def vec(self, entry: Mapping, key: str, n: int, where: int, default: Any = None,
            positive: bool = False) -> tuple[float, ...] | None:
        value = entry.get(key, default)
        if value is None:
            self.fail(where, f"missing '{key}' ({n} numbers)")
            return None
        ok = (isinstance(value, Sequence) and not isinstance(value, str) and len(value) == n
              and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value))
        if not ok or (positive and any(v <= 0 for v in value)):
            kind = "positive numbers" if positive else "numbers"
            self.fail(where, f"'{key}' must be a list of {n} {kind}, got {value!r}")
            return None
        return tuple(float(v) for v in value)

    def num(self, entry: Mapping, key: str, where: int, default: float | None = None,
            positive: bool = False) -> float | None:
        value = entry.get(key, default)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.fail(where, f"'{key}' must be a number, got {value!r}")
            return None
        if positive and value <= 0:
            self.fail(where, f"'{key}' must be positive, got {value!r}")
            return None
        return float(value)

    def name(self, entry: Mapping, where: int, seen: set[str]) -> str | None:
        value = entry.get("name")
        if not isinstance(value, str) or not value:
            self.fail(where, f"entry needs a non-empty string 'name', got {value!r}")
            return None
        if value in seen:
            self.fail(where, f"duplicate name '{value}'", "scene names must be unique")
            return None
        seen.add(value)
        return value


def _robot(c: _Checker, raw: Any, where: int, seen: set[str],
           default_name: str = "robot") -> RobotSpec | None:
    if not isinstance(raw, Mapping):
        c.fail(where, "a robot must be an object")
        return None
    model = raw.get("model", "panda")
    if model not in ROBOT_MODELS:
        c.fail(where, f"unknown robot model {model!r}",
               f"known models: {', '.join(ROBOT_MODELS)}")
        return None
    name = c.name({"name": raw.get("name", default_name)}, where, seen)
    bases = _bases(c, raw.get("bases", []), where, seen)
    if bases is None:
        return None
    start = raw.get("start")
    if start is not None and start not in {b.name for b in bases}:
        c.fail(where, f"robot start {start!r} is not one of its 'bases'")
        return None
    if start is None and bases and "base" not in raw:
        start = bases[0].name  # a mobile robot without an explicit pose starts at its first
    first = next((b for b in bases if b.name == start), None)
    base = first.base if first else c.vec(raw, "base", 3, where, default=(0.0, 0.0, 0.0))
    yaw = first.yaw if first else c.num(raw, "yaw", where, default=0.0)
    grasps = raw.get("grasps", "top")
    if grasps not in GRASP_KINDS:
        c.fail(where, f"robot grasps {grasps!r} is not a grasp kind",
               f"one of: {', '.join(GRASP_KINDS)}")
        return None
    if name is None or base is None or yaw is None:
        return None
    return RobotSpec(model, base, yaw, name, bases, start, grasps)  # type: ignore[arg-type]


def _bases(c: _Checker, raw: Any, where: int, seen: set[str]) -> tuple[BaseSpec, ...] | None:
    if not isinstance(raw, Sequence) or isinstance(raw, str):
        c.fail(where, "'bases' must be a list of {name, base, yaw} objects")
        return None
    out = []
    for entry in raw:
        if not isinstance(entry, Mapping):
            c.fail(where, f"a 'bases' entry must be an object, got {entry!r}")
            return None
        name = c.name(entry, where, seen)
        base = c.vec(entry, "base", 3, where)
        yaw = c.num(entry, "yaw", where, default=0.0)
        if name is None or base is None or yaw is None:
            return None
        out.append(BaseSpec(name, base, yaw))  # type: ignore[arg-type]
    return tuple(out)


def _robots(c: _Checker, scene: Mapping, seen: set[str]) -> tuple[RobotSpec, ...]:
    """The ``robots`` list, or the single ``robot`` object (named ``robot``)."""
    if "robot" in scene and "robots" in scene:
        c.fail(1, "give either 'robot' (one) or 'robots' (a list), not both")
        return ()
    if "robot" in scene:
        if scene["robot"] is None:
            return ()
        one = _robot(c, scene["robot"], 1, seen)
        return (one,) if one else ()
    raw = scene.get("robots", [])
    if not isinstance(raw, Sequence) or isinstance(raw, str):
        c.fail(1, "'robots' must be a list of robot objects")
        return ()
    robots = [_robot(c, entry, i, seen, f"robot{i - 1}") for i, entry in enumerate(raw, 1)]
    return tuple(r for r in robots if r is not None)


def _boxes(c: _Checker, raw: Any, key: str, seen: set[str]) -> tuple[BoxSpec, ...]:
    if not isinstance(raw, Sequence) or isinstance(raw, str):
        c.fail(1, f"'{key}' must be a list of objects")
        return ()
    out = []
    for i, entry in enumerate(raw, 1):
        if not isinstance(entry, Mapping):
            c.fail(i, f"{key} entry {i} must be an object")
            continue
        name = c.name(entry, i, seen)
        size = c.vec(entry, "size", 3, i, positive=True)
        pos = c.vec(entry, "position", 3, i)
        color = c.vec(entry, "color", 4, i, default=(0.6, 0.45, 0.3, 1.0))
        if name and size and pos and color:
            out.append(BoxSpec(name, size, pos, color))  # type: ignore[arg-type]
    return tuple(out)


def _object(c: _Checker, entry: Any, i: int, seen: set[str]) -> ObjectSpec | None:
    if not isinstance(entry, Mapping):
        c.fail(i, f"objects entry {i} must be an object")
        return None
    name = c.name(entry, i, seen)
    pos = c.vec(entry, "position", 3, i)
    yaw = c.num(entry, "yaw", i, default=0.0)
    mass = c.num(entry, "mass", i, default=0.1, positive=True)
    color = c.vec(entry, "color", 4, i, default=(0.8, 0.2, 0.2, 1.0))
    scale = c.num(entry, "scale", i, default=1.0, positive=True)
    if "urdf" in entry:
        shape, dims, urdf = "urdf", (), entry["urdf"]
        if not isinstance(urdf, str) or not urdf.endswith(".urdf"):
            c.fail(i, f"'urdf' must be a path to a .urdf file, got {urdf!r}")
            return None
    else:
        shape, urdf = entry.get("shape"), None
        if shape == "cylinder":
            r = c.num(entry, "radius", i, positive=True)
            h = c.num(entry, "height", i, positive=True)
            dims = (r, h) if r and h else None
        elif shape == "box":
            dims = c.vec(entry, "size", 3, i, positive=True)
        else:
            c.fail(i, f"object '{name}' has unknown shape {shape!r}",
                   "use shape 'cylinder' (radius, height), 'box' (size) or a 'urdf' path")
            return None
        if dims is None:
            return None
    if not (name and pos and yaw is not None and mass and color and scale):
        return None
    return ObjectSpec(name, shape, dims, pos, yaw, mass, color, urdf, scale)  # type: ignore[arg-type]


def _uav(c: _Checker, raw: Any, seen: set[str]) -> UavSpec | None:
    if raw is None:
        return None
    if not isinstance(raw, Mapping):
        c.fail(1, "'uav' must be an object")
        return None
    name = raw.get("name", "uav")
    if name in seen:
        c.fail(1, f"duplicate name '{name}'")
        return None
    size = c.vec(raw, "size", 3, 1, default=(0.3, 0.3, 0.08), positive=True)
    pos = c.vec(raw, "position", 3, 1)
    bounds = raw.get("bounds", {})
    if not isinstance(bounds, Mapping):
        c.fail(1, "'uav.bounds' must be an object with 'low' and 'high'")
        return None
    low = c.vec(bounds, "low", 3, 1)
    high = c.vec(bounds, "high", 3, 1)
    battery = c.num(raw, "battery", 1, default=100.0, positive=True)
    mass = c.num(raw, "mass", 1, default=1.0, positive=True)
    if not (size and pos and low and high and battery and mass):
        return None
    if any(lo >= hi for lo, hi in zip(low, high)):
        c.fail(1, "'uav.bounds.low' must be below 'high' on every axis")
        return None
    return UavSpec(str(name), size, pos, low, high, battery, mass)  # type: ignore[arg-type]


def parse_scene(scene: Mapping) -> SceneSpec:
    """Validate a scene dict; raise :class:`StampcError` listing every problem found."""
    c = _Checker()
    if not isinstance(scene, Mapping):
        c.fail(1, f"a scene must be a JSON object, got {type(scene).__name__}")
        raise StampcError(c.diags)
    known = {"robot", "robots", "surfaces", "objects", "poses", "regions", "uav", "name", "meta"}
    for key in scene:
        if key not in known:
            c.fail(1, f"unknown scene key {key!r}", f"known keys: {', '.join(sorted(known))}")
    seen: set[str] = set()
    c.section = "robots" if "robots" in scene else "robot"
    robots = _robots(c, scene, seen)
    c.section = "surfaces"
    surfaces = _boxes(c, scene.get("surfaces", []), "surfaces", seen)
    c.section = "objects"
    objects_raw = scene.get("objects", [])
    if not isinstance(objects_raw, Sequence) or isinstance(objects_raw, str):
        c.fail(1, "'objects' must be a list of objects")
        objects_raw = []
    objects = tuple(o for i, e in enumerate(objects_raw, 1)
                    if (o := _object(c, e, i, seen)) is not None)
    c.section = "regions"
    regions = _boxes(c, scene.get("regions", []), "regions", seen)
    c.section = "uav"
    uav = _uav(c, scene.get("uav"), seen)
    c.section = "poses"
    poses_raw = scene.get("poses", {})
    poses: list[tuple[str, str]] = []
    if not isinstance(poses_raw, Mapping):
        c.fail(1, "'poses' must map pose symbols to object names")
    else:
        names = {o.name for o in objects}
        for i, (sym, obj) in enumerate(poses_raw.items(), 1):
            if obj not in names:
                c.fail(i, f"pose symbol '{sym}' refers to unknown object {obj!r}")
            else:
                poses.append((str(sym), obj))
    meta = scene.get("meta", {})
    meta = meta if isinstance(meta, Mapping) else {}  # free-form: never an error
    c.section = ""
    if not robots and uav is None and not c.diags:
        c.fail(1, "a scene needs a 'robot' or a 'uav'")
    if c.diags:
        raise StampcError(c.diags)
    return SceneSpec(robots, surfaces, objects, tuple(poses), regions, uav,
                     MappingProxyType(dict(meta)))
