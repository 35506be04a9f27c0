"""Scene builder and problem generator for the keva domain (structures: ``structures.py``).

``build(structure, levels, seed)`` is the PyBullet scene: two Pandas (``left``,
``right``) standing in for the YuMi's arms, a table with the two feed locations where
the person puts the next plank, and a supply table out of reach where the planks wait.
The structure's site (the first plank's pose) is sampled from ``seed``; ``meta.roles``
holds every role's target pose, orientation and supports, ``meta.feeds`` the feed poses
(read by ``stampc.worlds.pybullet.keva``).

``problem_text(structure, levels, seed)`` writes the problem: the goal is the
structure's relations between roles (``structures.relations``), the initial state says
nothing about the order. ``local=False`` drops the levels (every plank may go on any
placed plank), for measuring what locality buys the abstract solver.

    python -m examples.keva.scene --structure twisted --levels 12 --seed 3 -o p.stamp
"""

from __future__ import annotations

import argparse
from pathlib import Path

from examples.keva.structures import PLANK, STRUCTURES, Role, relations, roles, site
from stampc.worlds.pybullet.values import Pose, quat_from_yaw

ARMS = {"left": (0.0, 0.16), "right": (0.0, -0.16)}  # base (x, y) of the two Pandas
#: x, y, yaw of the person's two feed locations and of the buffer (hand-over) spot
FEEDS = {"feed1": (0.28, 0.3, 0.0), "feed2": (0.28, -0.3, 0.0), "buffer": (0.26, 0.0, 0.0)}
TABLE = {"name": "table", "size": [0.6, 0.9, 0.05], "position": [0.55, 0.0, -0.025]}
SUPPLY = {"name": "supply", "size": [0.6, 0.4, 0.05], "position": [-0.2, 1.6, -0.025],
          "color": [0.45, 0.45, 0.5, 1.0]}


def supply_position(i: int) -> list[float]:
    """Where body ``k<i>`` waits on the supply table (rows of 4, stacks of 25)."""
    sx, sy, _ = SUPPLY["position"]
    _, _, t = PLANK
    x = sx - 0.21 + 0.14 * (i % 4)
    y = sy - 0.15 + 0.05 * (i // 4 % 6)
    return [round(x, 5), round(y, 5), round(t / 2 + t * 1.5 * (i // 24), 5)]


def build(structure: str = "tower", levels: int = 2, seed: int = 0) -> dict:
    """The PyBullet scene of instance ``(structure, levels, seed)``."""
    targets = roles(structure, levels, seed)
    _, _, t = PLANK
    objects = [{"name": f"k{i}", "shape": "box", "size": list(PLANK),
                "position": supply_position(i), "yaw": 0.0, "mass": 0.02,
                "color": [0.85, 0.7, 0.45, 1.0]} for i in range(len(targets))]
    feeds = {name: Pose.of((x, y, t / 2), quat_from_yaw(yaw)).to_json()
             for name, (x, y, yaw) in FEEDS.items()}
    at = site(seed, structure)
    return {
        "robots": [{"name": name, "model": "panda", "base": [x, y, 0.0], "yaw": 0.0}
                   for name, (x, y) in ARMS.items()],
        "surfaces": [dict(TABLE), dict(SUPPLY)],
        "objects": objects,
        "meta": {"domain": "keva", "structure": structure, "levels": levels, "seed": seed,
                 "plank": list(PLANK), "feeds": feeds,
                 "site": {"x": at.x, "y": at.y, "yaw": at.yaw},
                 "roles": {r.name: _role_json(r) for r in targets}},
    }


def _role_json(role: Role) -> dict:
    return {"pose": role.pose.to_json(), "orientation": role.orientation,
            "supports": list(role.supports), "level": role.level, "layer": role.group}


def problem_text(structure: str = "tower", levels: int = 2, seed: int = 0, *,
                 local: bool = True) -> str:
    """The ``.stamp`` problem building ``structure`` (domain: ``domain.stamp``)."""
    targets = roles(structure, levels, seed)
    n = len(targets)
    level_of = {r.name: (r.group if local else 0) for r in targets}
    n_levels = max(level_of.values()) + 1
    under = {level_of[r.name]: level_of[r.supports[0]] for r in targets if r.supports}
    facts = ["free(left)", "free(right)", "spans(horizontal)",
             "spans(sideways)"]
    facts += [f"ground_level(l{g})" for g in sorted({level_of[r.name] for r in targets
                                                      if not r.supports})]
    facts += [f"below(l{m}, l{g})" for g, m in sorted(under.items())]
    facts += [f"unplaced({r.name})" for r in targets]
    facts += [f"in_level({r.name}, l{level_of[r.name]})" for r in targets]
    facts += [f"before({a.name}, {b.name})" for i, a in enumerate(targets)
              for b in targets[i + 1:] if level_of[a.name] == level_of[b.name]]
    goal = [atom for r in targets for atom in relations(r)]
    name = f"keva_{structure}{levels}_s{seed}" + ("" if local else "_flat")
    lines = [f"# Build a {structure} of {levels} levels from {n} Keva planks (seed {seed}).",
             f"problem {name} for keva", "",
             f"object r0..r{n - 1}: plank",
             f"object l0..l{n_levels - 1}: level", "",
             "init " + "\n     ".join(facts), "",
             "goal " + "\n     ".join(goal), "",
             f"horizon {3 * n + 2}", "",
             f'scene builder "examples.keva.scene:build"(structure="{structure}", '
             f"levels={levels}, seed={seed})", ""]
    return "\n".join(lines)


def write_problem(path: str | Path, structure: str = "tower", levels: int = 2,
                  seed: int = 0, *, local: bool = True) -> Path:
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(problem_text(structure, levels, seed, local=local), encoding="utf-8")
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="write a keva problem")
    parser.add_argument("--structure", choices=STRUCTURES, default="tower")
    parser.add_argument("--levels", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--flat", action="store_true",
                        help="no levels: any plank may go on any placed plank")
    parser.add_argument("-o", "--output", help="file to write (default: stdout)")
    args = parser.parse_args(argv)
    try:
        text = problem_text(args.structure, args.levels, args.seed, local=not args.flat)
    except ValueError as exc:
        parser.error(str(exc))
    if args.output:
        out = Path(args.output)
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(text, encoding="utf-8")
    else:
        print(text, end="")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
