"""Seeded scene builders (plain dicts, see :mod:`.scene`): cluttered table, domino row,
aircraft with a UAV. Same arguments → same scene.

Bind them from a problem as a scene builder, e.g.
``stampc.worlds.pybullet.scenes:cluttered_table`` with ``n_cans=15, seed=3``.
"""

from __future__ import annotations

import math
import random

TABLE = {"name": "table", "size": [0.45, 0.7, 0.05], "position": [0.525, 0.0, -0.025]}
TRAY = {"name": "tray", "size": [0.2, 0.2, 0.02], "position": [0.3, -0.5, -0.01],
        "color": [0.3, 0.3, 0.35, 1.0]}
CAN_COLORS = ([0.85, 0.2, 0.2, 1.0], [0.2, 0.5, 0.85, 1.0], [0.25, 0.7, 0.3, 1.0],
              [0.9, 0.7, 0.15, 1.0])


def _can(name: str, x: float, y: float, height: float, radius: float, color: list) -> dict:
    return {"name": name, "shape": "cylinder", "radius": radius, "height": round(height, 4),
            "position": [round(x, 4), round(y, 4), round(height / 2, 4)], "mass": 0.1,
            "color": color}


def _free(x: float, y: float, placed: list[tuple[float, float]], min_dist: float) -> bool:
    return all(math.dist((x, y), c) >= min_dist for c in placed)


def cluttered_table(n_cans: int, seed: int, *, obstruct_target: bool = True,
                    n_blockers: int = 3, radius: float = 0.03,
                    heights: tuple[float, float] = (0.12, 0.2), gap: float = 0.01,
                    robot: str = "panda", tries: int = 50) -> dict:
    """A table with ``n_cans`` cans (``can0`` is the target) and a tray beside it.

    Cans stand uniformly at random on the table top, rejecting overlaps (``tries`` per
    can, as in the paper's code; a can that finds no room is left out and
    ``meta.dropped`` counts it). With ``obstruct_target``, ``n_blockers`` tall cans
    stand right next to the target on the side facing the robot, so its grasps are
    blocked until they are moved; ``meta.blockers`` names them.
    """
    rng = random.Random(seed)
    size, pos = TABLE["size"], TABLE["position"]
    margin = radius + 0.02
    lo_x, hi_x = pos[0] - size[0] / 2 + margin, pos[0] + size[0] / 2 - margin
    lo_y, hi_y = pos[1] - size[1] / 2 + margin, pos[1] + size[1] / 2 - margin
    min_dist = 2 * radius + gap
    # the target: short, in the middle band of the table so it is reachable
    tx, ty = rng.uniform(0.5, 0.62), rng.uniform(-0.12, 0.12)
    objects = [_can("can0", tx, ty, heights[0], radius, [0.95, 0.95, 0.95, 1.0])]
    placed = [(tx, ty)]
    blockers: list[str] = []
    if obstruct_target:
        towards_robot = math.atan2(-ty, -tx)
        spread = math.radians(60)
        for k in range(min(n_blockers, n_cans - 1)):
            offset = spread * (k - (n_blockers - 1) / 2)
            ang = towards_robot + offset
            d = min_dist + 0.002
            x, y = tx + d * math.cos(ang), ty + d * math.sin(ang)
            name = f"can{len(objects)}"
            objects.append(_can(name, x, y, heights[1], radius, CAN_COLORS[0]))
            placed.append((x, y))
            blockers.append(name)
    dropped = 0
    while len(objects) + dropped < n_cans:
        for _ in range(tries):
            x, y = rng.uniform(lo_x, hi_x), rng.uniform(lo_y, hi_y)
            if _free(x, y, placed, min_dist):
                name = f"can{len(objects)}"
                h = rng.uniform(*heights)
                objects.append(_can(name, x, y, h, radius, CAN_COLORS[len(objects) % 4]))
                placed.append((x, y))
                break
        else:
            dropped += 1
    return {
        "robot": {"model": robot, "base": [0.0, 0.0, 0.0], "yaw": 0.0},
        "surfaces": [dict(TABLE), dict(TRAY)],
        "objects": objects,
        "poses": {f"pose_{o['name']}": o["name"] for o in objects},
        "meta": {"target": "can0", "blockers": blockers, "dropped": dropped, "seed": seed},
    }


def domino_row(n: int, seed: int, *, spacing: float = 0.045, scale: float = 2.0,
               jitter: float = 0.003, robot: str = "panda") -> dict:
    """``n`` dominoes (``pybullet_data/domino``) standing in a row across the table."""
    rng = random.Random(seed)
    height = 0.0508 * scale
    y0 = -spacing * (n - 1) / 2
    objects = []
    for i in range(n):
        objects.append({
            "name": f"d{i}", "urdf": "domino/domino.urdf", "scale": scale, "mass": 0.05,
            "position": [round(0.5 + rng.uniform(-jitter, jitter), 4),
                         round(y0 + i * spacing, 4), round(height / 2, 4)],
            # thickness (the URDF's x) along the row, so neighbours topple into each other
            "yaw": round(math.pi / 2 + rng.uniform(-0.05, 0.05), 4),
        })
    return {
        "robot": {"model": robot, "base": [0.0, 0.0, 0.0], "yaw": 0.0},
        "surfaces": [dict(TABLE), dict(TRAY)],
        "objects": objects,
        "poses": {f"pose_{o['name']}": o["name"] for o in objects},
        "meta": {"seed": seed},
    }


def aircraft(seed: int, *, battery: float = 30.0, n_scaffolds: int = 3) -> dict:
    """An aircraft made of boxes in a hangar, inspection regions around its parts, a
    charging station and a UAV; ``n_scaffolds`` random boxes clutter the floor."""
    rng = random.Random(seed)
    parts = [
        {"name": "fuselage", "size": [6.0, 1.0, 1.0], "position": [0.0, 0.0, 1.5]},
        {"name": "left_wing_body", "size": [1.4, 3.5, 0.15], "position": [0.3, 2.25, 1.5]},
        {"name": "right_wing_body", "size": [1.4, 3.5, 0.15], "position": [0.3, -2.25, 1.5]},
        {"name": "tail_body", "size": [0.6, 0.12, 1.2], "position": [-2.7, 0.0, 2.6]},
        {"name": "floor", "size": [12.0, 12.0, 0.1], "position": [0.0, 0.0, -0.05]},
    ]
    for part in parts:
        part["color"] = [0.75, 0.75, 0.8, 1.0]
    regions = [
        {"name": "left_wing", "size": [1.2, 2.0, 0.8], "position": [0.3, 2.5, 2.2]},
        {"name": "right_wing", "size": [1.2, 2.0, 0.8], "position": [0.3, -2.5, 2.2]},
        {"name": "tail", "size": [1.0, 1.0, 1.0], "position": [-3.6, 0.0, 2.8]},
        {"name": "nose", "size": [1.0, 1.2, 1.0], "position": [3.7, 0.0, 1.5]},
        {"name": "station", "size": [0.8, 0.8, 0.6], "position": [4.0, 4.0, 0.5]},
    ]
    scaffolds = []
    while len(scaffolds) < n_scaffolds:
        x, y = rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0)
        if abs(y) < 4.2 and abs(x) < 4.3 or math.dist((x, y), (4.0, 4.0)) < 1.2:
            continue  # keep the aircraft's footprint and the station clear
        h = rng.uniform(0.5, 2.5)
        scaffolds.append({"name": f"scaffold{len(scaffolds)}", "size": [0.4, 0.4, round(h, 3)],
                          "position": [round(x, 3), round(y, 3), round(h / 2, 3)],
                          "color": [0.5, 0.4, 0.2, 1.0]})
    return {
        "surfaces": parts + scaffolds,
        "regions": regions,
        "uav": {"name": "uav", "size": [0.3, 0.3, 0.08], "position": [4.0, 4.0, 0.5],
                "battery": battery, "bounds": {"low": [-6.0, -6.0, 0.2],
                                               "high": [6.0, 6.0, 4.0]}},
        "meta": {"seed": seed},
    }


# ------------------------------------------------------------------ the paper's table
#: the paper's tables (x × y, m): the small one up to 25 cans, the large one for 30+
SMALL_TABLE, LARGE_TABLE = (0.90, 0.90), (2.235, 0.94)
BASE_CLEARANCE = 0.30  # m between a table edge and a base pose on that side
#: on the large table the long sides need three base poses each (the Panda reaches
#: ~0.8 m): every point of the top is then within 0.8 m of one of them
LONG_SIDE_XS = (-0.75, 0.0, 0.75)
LONG_SIDE_CLEARANCE = 0.23


def table_bases(size: tuple[float, float]) -> list[dict]:
    """Candidate base poses around a table centred at the origin, facing its centre
    line: the middle of each side on the small table; three per long side on the
    large one (the Panda reaches ~0.8 m where the paper's Fetch reached ~1.1 m, so its
    4 poses 1 m out become poses 0.23-0.3 m from the edges; see docs)."""
    sx, sy = size
    if sx <= 1.0:
        spots = [(-(sx / 2 + BASE_CLEARANCE), 0.0), (0.0, -(sy / 2 + BASE_CLEARANCE)),
                 (sx / 2 + BASE_CLEARANCE, 0.0), (0.0, sy / 2 + BASE_CLEARANCE)]
    else:
        d = sy / 2 + LONG_SIDE_CLEARANCE
        spots = [(x, y) for y in (-d, d) for x in LONG_SIDE_XS]
    out = []
    for i, (x, y) in enumerate(spots):
        facing = math.atan2(-y, -x) if abs(y) < 1e-9 else (-math.pi / 2 if y > 0 else math.pi / 2)
        out.append({"name": f"b{i}", "base": [round(x, 4), round(y, 4), 0.0],
                    "yaw": round(facing, 6)})
    return out


def cluttered_table_random(n_cans: int, seed: int, *, table: str = "auto",
                           radius: float = 0.03, height: float = 0.2, gap: float = 0.005,
                           tries: int = 50, robot: str = "panda",
                           grasps: str = "side") -> dict:
    """The paper's cluttered table: ``n_cans`` cans (radius 0.03 m, height 0.2 m)
    uniformly at random on the table top, up to ``tries`` rejections each for overlaps
    (a can that finds no room is left out: ``meta.dropped``), and a target drawn
    uniformly among them (``meta.target``). Nothing is arranged around the target.

    ``table``: ``"small"`` (0.90 × 0.90 m), ``"large"`` (2.235 × 0.94 m) or ``"auto"``
    (large from 30 cans). The robot (named ``robot``) has the candidate base poses of
    :func:`table_bases` (``b0..``) and starts at one drawn from the seed.

    ``grasps``: the robot's grasp kind (``side`` by default: the paper's Fetch took the
    cans from the side, so the cans between it and the target are in the way; with
    equal-height cans, top grasps are almost never obstructed: docs/benchmarks.md).
    """
    rng = random.Random(f"cluttered-random:{n_cans}:{seed}")
    size = LARGE_TABLE if table == "large" or (table == "auto" and n_cans >= 30) else SMALL_TABLE
    top = {"name": "table", "size": [size[0], size[1], 0.05], "position": [0.0, 0.0, -0.025]}
    margin = radius + 0.01
    min_dist = 2 * radius + gap
    placed: list[tuple[float, float]] = []
    objects, dropped = [], 0
    for _ in range(n_cans):
        for _ in range(tries):
            x = rng.uniform(-size[0] / 2 + margin, size[0] / 2 - margin)
            y = rng.uniform(-size[1] / 2 + margin, size[1] / 2 - margin)
            if _free(x, y, placed, min_dist):
                name = f"can{len(objects)}"
                objects.append(_can(name, x, y, height, radius, CAN_COLORS[len(objects) % 4]))
                placed.append((x, y))
                break
        else:
            dropped += 1
    target = f"can{rng.randrange(len(objects))}" if objects else None
    for o in objects:
        if o["name"] == target:
            o["color"] = [0.95, 0.95, 0.95, 1.0]
    bases = table_bases(size)
    return {
        "robot": {"name": "robot", "model": robot, "bases": bases, "grasps": grasps,
                  "start": bases[rng.randrange(len(bases))]["name"]},
        "surfaces": [top],
        "objects": objects,
        "poses": {f"pose_{o['name']}": o["name"] for o in objects},
        "meta": {"target": target, "dropped": dropped, "seed": seed,
                 "table": list(size), "bases": [b["name"] for b in bases]},
    }
