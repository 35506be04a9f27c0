"""Target structures, scene builder and problem generator for the keva domain.

A structure is a list of *slots*, one target pose per plank, in build order
(:func:`slots`): ``pi`` stacks ``levels`` π shapes (two planks standing upright, one
lying across them), ``tower`` is a log-cabin tower of ``levels`` levels of two parallel
planks (each level turned 90°), ``twisted`` turns each level a further ``twist`` rad.
Planks are boxes of the Keva length 0.117475 m with ``pybullet_data/jenga/jenga.urdf``'s
proportions (its 0.15 × 0.05 × 0.03 m block scaled by 0.117475 / 0.15).

``build(structure, levels, seed)`` is the PyBullet scene: a Panda, a table with the two
feed locations and the structure's site, and a supply table out of the arm's reach where
the planks wait until they "arrive" at a feed location (``k0`` starts at feed 1).
``meta.slots`` / ``meta.feeds`` hold the slot and feed poses that the bound functions
(``stampc.worlds.pybullet.keva``) read. ``problem_text(...)`` writes the problem.

    python -m examples.keva.scene --structure twisted --levels 12 -o p.stamp
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass
from pathlib import Path

from stampc.worlds.pybullet.scenes import TABLE
from stampc.worlds.pybullet.values import Pose, quat_from_axes, quat_from_yaw

PLANK = (0.117475, 0.05 * 0.117475 / 0.15, 0.03 * 0.117475 / 0.15)  # length, width, thickness
SITE = (0.5, 0.14)  # (x, y) of the structure's centre on the table
FEEDS = {"feed1": (0.42, -0.22, 0.0), "feed2": (0.6, -0.22, 0.0)}  # x, y, yaw
TOWER_OFFSET = 0.04  # m from a tower level's axis to each of its two planks
PI_LEG_OFFSET = 0.045  # m from a π's axis to each leg
TWIST = math.pi / 12  # extra turn per level of the twisted tower
STRUCTURES = ("pi", "tower", "twisted")
SUPPLY = {"name": "supply", "size": [0.6, 0.3, 0.05], "position": [0.0, 1.5, -0.025],
          "color": [0.45, 0.45, 0.5, 1.0]}


@dataclass(frozen=True)
class Slot:
    """One plank's target pose in a structure."""

    name: str
    pose: Pose


def _flat(x: float, y: float, z: float, yaw: float) -> Pose:
    return Pose.of((x, y, z), quat_from_yaw(yaw))


def tower_slots(levels: int, twist: float = 0.0) -> list[Slot]:
    """Two parallel planks per level; level ``i`` is turned by ``i (π/2 + twist)``."""
    _, _, t = PLANK
    out = []
    for level in range(levels):
        yaw = level * (math.pi / 2 + twist)
        nx, ny = -math.sin(yaw), math.cos(yaw)  # across the planks
        for side in (-1, 1):
            x, y = SITE[0] + side * TOWER_OFFSET * nx, SITE[1] + side * TOWER_OFFSET * ny
            out.append(Slot(f"s{len(out)}", _flat(x, y, t / 2 + level * t, yaw)))
    return out


def pi_slots(levels: int) -> list[Slot]:
    """``levels`` stacked π shapes along y: two upright legs, then a plank across."""
    length, _, t = PLANK
    out = []
    for level in range(levels):
        base = level * (length + t)
        for side in (-1, 1):
            # upright leg: length along z, width along x, thickness along y with the
            # plank's top face (the grasped one) pointing away from the other leg
            upright = quat_from_axes((0.0, 0.0, 1.0), (side * 1.0, 0.0, 0.0),
                                     (0.0, side * 1.0, 0.0))
            pos = (SITE[0], SITE[1] + side * PI_LEG_OFFSET, base + length / 2)
            out.append(Slot(f"s{len(out)}", Pose.of(pos, upright)))
        out.append(Slot(f"s{len(out)}", _flat(SITE[0], SITE[1], base + length + t / 2,
                                              math.pi / 2)))
    return out


def slots(structure: str, levels: int) -> list[Slot]:
    if structure not in STRUCTURES:
        raise ValueError(f"unknown structure {structure!r}; expected one of "
                         f"{', '.join(STRUCTURES)}")
    if levels < 1:
        raise ValueError(f"need at least one level, got {levels}")
    if structure == "pi":
        return pi_slots(levels)
    return tower_slots(levels, TWIST if structure == "twisted" else 0.0)


def build(structure: str = "tower", levels: int = 2, seed: int = 0, *,
          robot: str = "panda") -> dict:
    """The PyBullet scene; ``seed`` is recorded only (the layout is fixed)."""
    targets = slots(structure, levels)
    length, width, t = PLANK
    sx, sy, _ = SUPPLY["position"]
    objects = []
    for i in range(len(targets)):
        if i == 0:
            x, y, yaw = FEEDS["feed1"]
        else:  # wait on the supply table, out of reach, in rows of 4
            x = sx - 0.21 + 0.14 * ((i - 1) % 4)
            y, yaw = sy - 0.1 + 0.05 * ((i - 1) // 4 % 5), 0.0
        z = t / 2 + 0.03 * ((i - 1) // 20) if i else t / 2
        objects.append({"name": f"k{i}", "shape": "box", "size": list(PLANK),
                        "position": [round(x, 5), round(y, 5), round(z, 5)], "yaw": yaw,
                        "mass": 0.02, "color": [0.85, 0.7, 0.45, 1.0]})
    feeds = {name: Pose.of((x, y, t / 2), quat_from_yaw(yaw)).to_json()
             for name, (x, y, yaw) in FEEDS.items()}
    return {
        "robot": {"model": robot, "base": [0.0, 0.0, 0.0], "yaw": 0.0},
        "surfaces": [dict(TABLE), dict(SUPPLY)],
        "objects": objects,
        "meta": {"domain": "keva", "structure": structure, "levels": levels, "seed": seed,
                 "plank": list(PLANK), "feeds": feeds,
                 "slots": {s.name: s.pose.to_json() for s in targets}},
    }


def problem_text(structure: str = "tower", levels: int = 2, seed: int = 0) -> str:
    """The ``.stamp`` problem building ``structure`` (domain: ``domain.stamp``)."""
    n = len(slots(structure, levels))
    name = f"keva_{structure}{levels}"
    facts = ["handempty", "at_feed(k0, feed1)", "ready(s0)", f"last_slot(s{n - 1})"]
    facts += [f"plank_for(k{i}, s{i})" for i in range(n)]
    facts += [f"next_slot(s{i}, s{i + 1})" for i in range(n - 1)]
    facts += [f"next_plank(k{i}, k{i + 1})" for i in range(n - 1)]
    lines = [f"# Build a {structure} of {levels} levels from {n} Keva planks.",
             f"problem {name} for keva", "",
             f"object k0..k{n - 1}: plank",
             f"object s0..s{n - 1}: slot",
             "object table: surface", "",
             "init " + "\n     ".join(facts), "",
             "goal forall (s: slot) filled(s)", "",
             f"horizon {2 * n + 2}", "",
             f'scene builder "examples.keva.scene:build"(structure="{structure}", '
             f"levels={levels}, seed={seed})", ""]
    return "\n".join(lines)


def write_problem(path: str | Path, structure: str = "tower", levels: int = 2,
                  seed: int = 0) -> Path:
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(problem_text(structure, levels, seed), encoding="utf-8")
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="write a keva problem")
    parser.add_argument("--structure", choices=STRUCTURES, default="tower")
    parser.add_argument("--levels", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("-o", "--output", help="file to write (default: stdout)")
    args = parser.parse_args(argv)
    if args.output:
        write_problem(args.output, args.structure, args.levels, args.seed)
    else:
        print(problem_text(args.structure, args.levels, args.seed), end="")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
