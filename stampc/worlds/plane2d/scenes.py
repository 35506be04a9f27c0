"""Seeded random scene generators (return plain JSON-friendly scene dicts).

Same arguments → identical dict. Generated objects never overlap (each pair keeps at
least ``gap`` clearance); a request that cannot be satisfied (too many objects for the
table) raises :class:`StampcError` with a ``S210`` diagnostic instead of looping.
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass
from typing import Any

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.plane2d.geometry import Box, Disc, overlaps

TABLE = {"x0": 0.0, "y0": 0.0, "x1": 1.0, "y1": 0.6}
TRAY = {"x0": 0.78, "y0": 0.04, "x1": 0.97, "y1": 0.24}
ROBOT = {"base": [0.5, -0.12], "gripper_radius": 0.025, "reach": 0.9}
_TRIES = 4000


def _fail(message: str, hint: str | None = None) -> StampcError:
    return StampcError([error("S210", f"scene generator: {message}",
                              Span.point("<scene generator>"), hint=hint)])


def _clear(x: float, y: float, r: float, placed: list[tuple[float, float, float]],
           gap: float) -> bool:
    return all(math.hypot(x - px, y - py) >= r + pr + gap for px, py, pr in placed)


def _in_rect(x: float, y: float, r: float, rect: dict) -> bool:
    return rect["x0"] + r <= x <= rect["x1"] - r and rect["y0"] + r <= y <= rect["y1"] - r


def _near_rect(x: float, y: float, r: float, rect: dict) -> bool:
    return rect["x0"] - r <= x <= rect["x1"] + r and rect["y0"] - r <= y <= rect["y1"] + r


def cluttered(n: int, seed: int, *, target: str = "can0", blockers: int = 2,
              radius: float = 0.035, gap: float = 0.01, tray: bool = True,
              shelf: bool = False) -> dict[str, Any]:
    """``n`` cans (discs ``can0``…) on a 1 m × 0.6 m table, robot base below the near
    edge. ``target`` sits near the far edge; the next ``blockers`` cans are put in its
    approach corridor (within gripper + can radius of the straight line from the robot
    base to the grasp facing it), so the straight reach to the target is blocked.

    With ``shelf=True`` the target stands in a U-shaped static shelf open towards the
    robot, and the blockers sit centred in it: no path goes around them, so a planner
    must move them (the scenario the ``collision`` evaluator exists for)."""
    names = [f"can{i}" for i in range(n)]
    if n < 1 or target not in names:
        raise _fail(f"target {target!r} is not one of the {n} cans can0…can{n - 1}")
    if not 0 <= blockers < n:
        raise _fail(f"blockers must be in [0, {n - 1}], got {blockers}")
    rng = random.Random(seed)
    order = [target] + [m for m in names if m != target]
    placed: list[tuple[float, float, float]] = []
    poses: dict[str, tuple[float, float]] = {}
    tx, ty = rng.uniform(0.3, 0.7), rng.uniform(0.42, TABLE["y1"] - radius - gap)
    placed.append((tx, ty, radius))
    poses[target] = (tx, ty)
    bx, by = ROBOT["base"]
    reach_r = ROBOT["gripper_radius"] + radius
    d = math.hypot(tx - bx, ty - by)
    ux, uy = (bx - tx) / d, (by - ty) / d          # from the target towards the base
    grasp = (tx + ux * reach_r, ty + uy * reach_r)
    seg = math.dist(grasp, (bx, by))
    walls = _shelf((tx, ty), (ux, uy), radius, reach_r, gap, 0.8 * seg) if shelf else []
    lateral, far = (0.1, 0.75 * seg - radius) if shelf else (0.6, 0.75 * seg)
    for name in order[1: 1 + blockers]:
        poses[name] = _sample(rng, placed, radius, gap, name, lambda: _corridor_point(
            rng, grasp, (ux, uy), reach_r, lateral, far), walls)
    for name in order[1 + blockers:]:
        poses[name] = _sample(rng, placed, radius, gap, name, lambda: _table_point(rng, radius),
            walls)
    surfaces = {"table": dict(TABLE)}
    if tray:
        surfaces["tray"] = dict(TRAY)
    return {
        "table": dict(TABLE), "robot": {**ROBOT, "base": list(ROBOT["base"])},
        "surfaces": surfaces,
        "objects": [{"name": m, "shape": "disc", "radius": radius, "x": poses[m][0],
                     "y": poses[m][1], "theta": 0.0} for m in names],
        "poses": {f"pose_{m}": m for m in names},
        "obstacles": [w.to_json(f"shelf{i}") for i, w in enumerate(walls)],
        "meta": {"target": target, "blockers": order[1: 1 + blockers], "seed": seed},
    }


#: candidate bases of the mobile robot around the table (near, far, left, right edge)
MOBILE_BASES = (("b0", (0.5, -0.12)), ("b1", (0.5, 0.72)), ("b2", (-0.12, 0.3)),
                ("b3", (1.12, 0.3)))
MOBILE_REACH = 0.55  # m: from one base the gripper covers about half the table


def cluttered_mobile(n: int, seed: int, *, radius: float = 0.035,
                     gap: float = 0.01) -> dict[str, Any]:
    """``n`` cans uniformly at random on the 1 m × 0.6 m table and a random target (the
    paper's scene, nothing arranged), for a robot that stands at one of
    :data:`MOBILE_BASES` (the start drawn from the seed) and reaches
    :data:`MOBILE_REACH` from it, so which base reaches a can is part of the problem."""
    if n < 1:
        raise _fail(f"need at least one can, got {n}")
    rng = random.Random(f"mobile:{seed}")
    placed: list[tuple[float, float, float]] = []
    objects = []
    for i in range(n):
        x, y = _sample(rng, placed, radius, gap, f"can{i}", lambda: _table_point(rng, radius),
            tray=None)
        objects.append({"name": f"can{i}", "shape": "disc", "radius": radius, "x": x, "y": y,
                        "theta": 0.0})
    bases = [{"name": b, "base": list(xy)} for b, xy in MOBILE_BASES]
    start = bases[rng.randrange(len(bases))]["name"]
    return {
        "table": dict(TABLE),
        "robot": {"bases": bases, "start": start, "gripper_radius": ROBOT["gripper_radius"],
                  "reach": MOBILE_REACH},
        "surfaces": {"table": dict(TABLE)},
        "objects": objects,
        "poses": {f"pose_can{i}": f"can{i}" for i in range(n)},
        "meta": {"target": f"can{rng.randrange(n)}", "bases": [b for b, _ in MOBILE_BASES],
                 "table": [TABLE["x1"] - TABLE["x0"], TABLE["y1"] - TABLE["y0"]], "seed": seed},
    }


def _table_point(rng: random.Random, radius: float) -> tuple[float, float]:
    """A uniform centre for a disc of ``radius`` on the table."""
    return rng.uniform(radius, TABLE["x1"] - radius), rng.uniform(radius, TABLE["y1"] - radius)


def _corridor_point(rng: random.Random, grasp, u, reach_r: float, lateral: float,
                    far: float):
    """A point whose disc crosses the straight gripper path to ``grasp``."""
    s = rng.uniform(2 * reach_r, far)
    v = rng.uniform(-lateral, lateral) * reach_r
    return (grasp[0] + u[0] * s - u[1] * v, grasp[1] + u[1] * s + u[0] * v)


@dataclass(frozen=True)
class _Wall:
    box: Box

    def to_json(self, name: str) -> dict[str, Any]:
        b = self.box
        return {"name": name, "shape": "box", "size": [2 * b.hx, 2 * b.hy],
                "x": b.x, "y": b.y, "theta": b.theta}


def _shelf(target, u, radius: float, reach_r: float, gap: float, length: float) -> list[_Wall]:
    """Two side walls and a back wall around the corridor from ``target`` along ``u``.

    The inner half-width leaves each centred blocker less than a gripper diameter of
    room on either side, so nothing can pass beside it."""
    thick = 0.02
    inner = radius + 0.1 * reach_r + gap
    theta = math.atan2(u[1], u[0])
    back = radius + gap + thick / 2

    def at(s: float, v: float, hs: float, hv: float) -> _Wall:
        return _Wall(Box(target[0] + u[0] * s - u[1] * v, target[1] + u[1] * s + u[0] * v,
                         hs, hv, theta))

    mid = (length - back) / 2
    half = (length + back) / 2
    return [at(mid, inner + thick / 2, half, thick / 2),
            at(mid, -inner - thick / 2, half, thick / 2),
            at(-back, 0.0, thick / 2, inner + thick)]


def _sample(rng: random.Random, placed, radius: float, gap: float, name: str, draw,
            walls: list[_Wall] = (), tray: dict | None = TRAY):
    for _ in range(_TRIES):
        x, y = draw()
        if _in_rect(x, y, radius, TABLE) \
                and not (tray and _near_rect(x, y, radius + gap, tray)) \
                and _clear(x, y, radius, placed, gap) \
                and not any(overlaps(Disc(x, y, radius), w.box, gap) for w in walls):
            placed.append((x, y, radius))
            return (x, y)
    raise _fail(f"could not place {name} without overlaps after {_TRIES} tries",
                hint="use fewer objects, fewer blockers or a smaller radius")


def domino_row(n: int, seed: int = 0, *, spacing: float = 0.07,
               size: tuple[float, float] = (0.015, 0.06), jitter: float = 0.0) -> dict[str, Any]:
    """``n`` thin boxes ``d0``… (names as in the PyBullet world) standing in a row across the table (x axis), with
    optional seeded jitter of their positions (never enough to make them overlap)."""
    if n < 1:
        raise _fail(f"domino_row needs n ≥ 1, got {n}")
    if spacing - size[0] - 2 * jitter <= 0:
        raise _fail("dominoes would overlap", hint="increase spacing or reduce jitter/size")
    width = (n - 1) * spacing
    x0 = (TABLE["x1"] - width) / 2
    if x0 < size[0] or width > TABLE["x1"] - size[0]:
        raise _fail(f"{n} dominoes spaced {spacing} m do not fit on the table")
    rng = random.Random(seed)
    objects = []
    for i in range(n):
        objects.append({"name": f"d{i}", "shape": "box", "size": list(size),
                        "x": x0 + i * spacing + rng.uniform(-jitter, jitter),
                        "y": 0.35 + rng.uniform(-jitter, jitter), "theta": 0.0})
    return {"table": dict(TABLE), "robot": {**ROBOT, "base": list(ROBOT["base"])},
            "surfaces": {"table": dict(TABLE), "tray": dict(TRAY)}, "objects": objects,
            "poses": {f"pose_d{i}": f"d{i}" for i in range(n)}, "meta": {"seed": seed}}


AIRCRAFT_REGIONS = {
    "fuselage": {"x0": 0.9, "y0": 1.75, "x1": 3.3, "y1": 2.25},
    "left_wing": {"x0": 1.7, "y0": 2.35, "x1": 2.4, "y1": 3.5},
    "right_wing": {"x0": 1.7, "y0": 0.5, "x1": 2.4, "y1": 1.65},
    "tail": {"x0": 0.2, "y0": 1.5, "x1": 0.8, "y1": 2.5},
    "charger": {"x0": 3.4, "y0": 0.2, "x1": 3.8, "y1": 0.6},
}


def aircraft(seed: int = 0, *, obstacles: int = 4, battery: float = 6.0,
             uav_radius: float = 0.06) -> dict[str, Any]:
    """A 4 m × 4 m hangar seen from above: inspection regions of an aircraft
    (``left_wing``, ``right_wing``, ``fuselage``, ``tail``) and a ``charger``, with
    ``obstacles`` seeded boxes (ground equipment) that overlap no region."""
    rng = random.Random(seed)
    hangar = {"x0": 0.0, "y0": 0.0, "x1": 4.0, "y1": 4.0}
    boxes: list[dict[str, Any]] = []
    placed: list[tuple[float, float, float]] = []
    for i in range(obstacles):
        for _ in range(_TRIES):
            w, h = rng.uniform(0.15, 0.4), rng.uniform(0.15, 0.4)
            r = math.hypot(w, h) / 2
            x, y = rng.uniform(r, 4.0 - r), rng.uniform(r, 4.0 - r)
            margin = r + 2 * uav_radius   # leave room to fly around every region
            if any(_near_rect(x, y, margin, reg) for reg in AIRCRAFT_REGIONS.values()) \
                    or not _clear(x, y, r, placed, 2 * uav_radius + 0.05):
                continue
            placed.append((x, y, r))
            boxes.append({"name": f"equipment{i}", "shape": "box", "size": [w, h],
                          "x": x, "y": y, "theta": rng.uniform(0, math.pi)})
            break
        else:
            raise _fail(f"could not place {obstacles} obstacles in the hangar")
    charger = AIRCRAFT_REGIONS["charger"]
    return {
        "table": hangar, "workspace": hangar,
        "robot": {"base": [(charger["x0"] + charger["x1"]) / 2, (charger["y0"] + charger["y1"]) / 2],
                  "gripper_radius": 0.02, "reach": 0.1},
        "regions": {k: dict(v) for k, v in AIRCRAFT_REGIONS.items()},
        "obstacles": boxes,
        "uav": {"start": "charger", "battery": battery, "radius": uav_radius},
        "poses": {"pose_uav0": "uav"},
        "meta": {"seed": seed},
    }
