"""Target structures of the keva domain as *roles*: one per plank of the structure, with
its support relation (on the table, on one plank, across two), its orientation and its
target pose.

Planks are identical, so the abstract model names them by role (``r0``, ``r1``, ...):
the goal is the structure's relations between roles, and a put-down action gives the
plank in the hand a role. The first plank's pose is sampled per seed (:func:`site`);
every other pose follows from the structure relative to it.

- ``pi``: ``levels`` stacked π shapes — two upright legs (on the table, or on the π
  below's top plank), then a plank lying across them;
- ``tower``: a log-cabin tower of ``levels`` levels of two parallel planks lying across
  the two planks below, each level turned 90°;
- ``twisted``: the tower with each level turned a further ``TWIST``;
- ``3towers``: three log-cabin towers of ``levels`` levels side by side.

Planks are boxes of the Keva length 0.117475 m with ``pybullet_data/jenga/jenga.urdf``'s
proportions (its 0.15 × 0.05 × 0.03 m block scaled by 0.117475 / 0.15).
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass

from stampc.worlds.pybullet.values import Pose, quat_from_axes, quat_from_yaw

PLANK = (0.117475, 0.05 * 0.117475 / 0.15, 0.03 * 0.117475 / 0.15)  # length, width, thickness
ORIENTATIONS = ("vertical", "horizontal", "sideways")
TOWER_OFFSET = 0.04  # m from a tower level's axis to each of its two planks
PI_LEG_OFFSET = 0.045  # m from a π's axis to each leg
TWIST = math.pi / 12  # extra turn per level of the twisted tower
TOWER_SPACING = 0.15  # m between the axes of the 3-towers structure's towers
STRUCTURES = ("pi", "tower", "twisted", "3towers")
#: the region the structure's site (its first plank's frame) is sampled from:
#: x, y ranges in the world frame (in front of the two arms) and the yaw range
SITE_X, SITE_Y, SITE_YAW = (0.5, 0.56), (-0.06, 0.06), (0.0, math.pi)
#: the row of three towers runs across the table (never towards the feeds)
ROW_YAW = (math.pi / 4, 3 * math.pi / 4)


@dataclass(frozen=True)
class Role:
    """One plank of a structure: where it goes and what it rests on."""

    name: str
    level: int  # 0 on the table; a plank rests on planks of the level below
    orientation: str  # one of ORIENTATIONS
    supports: tuple[str, ...]  # () on the table, (j,) on one plank, (j1, j2) across two
    pose: Pose
    #: the layer of planks this one belongs to; the planks it rests on form the layer
    #: right below (one layer per level, or per level of one tower in ``3towers``)
    layer: int = -1

    @property
    def group(self) -> int:
        return self.level if self.layer < 0 else self.layer


@dataclass(frozen=True)
class Site:
    """The frame the structure is built in: the first plank's level-0 frame."""

    x: float
    y: float
    yaw: float

    def place(self, lx: float, ly: float, z: float, quat) -> Pose:
        """A local pose (x, y in the site frame) in the world frame."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        turn = Pose((0.0, 0.0, 0.0), quat_from_yaw(self.yaw))
        return Pose.of((self.x + c * lx - s * ly, self.y + s * lx + c * ly, z),
                       turn.multiply(Pose((0.0, 0.0, 0.0), tuple(quat))).quat)


def site(seed: int, structure: str = "tower") -> Site:
    """The structure's site for ``seed``: uniform in ``SITE_X × SITE_Y × SITE_YAW``
    (``ROW_YAW`` for the three towers)."""
    rng = random.Random(f"keva-site:{seed}")
    yaws = ROW_YAW if structure == "3towers" else SITE_YAW
    return Site(round(rng.uniform(*SITE_X), 4), round(rng.uniform(*SITE_Y), 4),
                round(rng.uniform(*yaws), 4))


def _tower(levels: int, twist: float, at: Site, cx: float = 0.0,
           first: int = 0, prefix: str = "r") -> list[Role]:
    """Two parallel flat planks per level, level ``i`` turned ``i (π/2 + twist)``,
    each resting across both planks of the level below."""
    _, _, t = PLANK
    out: list[Role] = []
    for level in range(levels):
        yaw = level * (math.pi / 2 + twist)
        nx, ny = -math.sin(yaw), math.cos(yaw)  # across the planks
        below = tuple(r.name for r in out[-2:]) if level else ()
        for side in (-1, 1):
            pose = at.place(cx + side * TOWER_OFFSET * nx, side * TOWER_OFFSET * ny,
                            t / 2 + level * t, quat_from_yaw(yaw))
            out.append(Role(f"{prefix}{first + len(out)}", level, "horizontal", below, pose))
    return out


def _pi(levels: int, at: Site) -> list[Role]:
    """``levels`` stacked π shapes along the site's y axis."""
    length, _, t = PLANK
    out: list[Role] = []
    for k in range(levels):
        base = k * (length + t)
        top_below = (out[-1].name,) if out else ()
        for side in (-1, 1):
            # upright leg: length along z, width along x, thickness along y, the plank's
            # top face (the grasped one) pointing away from the other leg
            upright = quat_from_axes((0.0, 0.0, 1.0), (side * 1.0, 0.0, 0.0),
                                     (0.0, side * 1.0, 0.0))
            pose = at.place(0.0, side * PI_LEG_OFFSET, base + length / 2, upright)
            out.append(Role(f"r{len(out)}", 2 * k, "vertical", top_below, pose))
        legs = (out[-2].name, out[-1].name)
        pose = at.place(0.0, 0.0, base + length + t / 2, quat_from_yaw(math.pi / 2))
        out.append(Role(f"r{len(out)}", 2 * k + 1, "horizontal", legs, pose))
    return out


def _three_towers(levels: int, at: Site) -> list[Role]:
    """Three towers along the site's x axis; roles numbered level by level."""
    towers = [_tower(levels, 0.0, at, cx=(i - 1) * TOWER_SPACING, prefix=f"t{i}_")
              for i in range(3)]
    names: dict[str, str] = {}
    ordered = []
    for level in range(levels):
        for tower in towers:
            for role in tower[2 * level:2 * level + 2]:
                names[role.name] = f"r{len(ordered)}"
                ordered.append(role)
    layer = {id(r): 3 * r.level + i for i, tower in enumerate(towers) for r in tower}
    return [Role(names[r.name], r.level, r.orientation,
                 tuple(names[s] for s in r.supports), r.pose, layer[id(r)])
            for r in ordered]


def roles(structure: str, levels: int, seed: int = 0) -> list[Role]:
    """The roles of ``structure`` with ``levels`` levels built at ``site(seed)``."""
    if structure not in STRUCTURES:
        raise ValueError(f"unknown structure {structure!r}; expected one of "
                         f"{', '.join(STRUCTURES)}")
    if levels < 1:
        raise ValueError(f"need at least one level, got {levels}")
    at = site(seed, structure)
    if structure == "pi":
        return _pi(levels, at)
    if structure == "3towers":
        return _three_towers(levels, at)
    return _tower(levels, TWIST if structure == "twisted" else 0.0, at)


def relations(role: Role) -> list[str]:
    """The goal atoms describing ``role``."""
    atoms = [f"oriented({role.name}, {role.orientation})"]
    if role.supports:
        atoms += [f"on({role.name}, {s})" for s in role.supports]
    else:
        atoms.append(f"on_table({role.name})")
    return atoms
