"""Scenes and problem generator for the cluttered-table domain (Shah et al., ATM-MDP).

``build_random(n, seed)`` is the paper's PyBullet scene (``domain.stamp``): ``n`` cans
uniformly at random on the table, a random target, a Panda on a mobile base with
candidate base poses around the table; ``build2d_random(n, seed)`` is its plane2d twin
(same domain, four bases around a 2-D table). ``build(n, seed)`` is the earlier
fixed-base scene (``domain_fixed.stamp``; ``can0`` is the target, ``can1..can3`` stand
between it and the robot), ``build2d(n, seed)`` the plane2d one (``domain_fixed.stamp``;
the target sits in a shelf open towards the robot, the blockers in its opening).
``problem_text(n, seed, variant, world)`` writes the matching problem: which cans are
delicate is drawn from the same seed, and the crush variant (``low`` 0.1, ``mid`` 0.5,
``high`` 0.9) picks the ``delicate_*`` predicate used.

    python -m examples.cluttered_table.scene --n 20 --seed 3 --variant high -o p.stamp
"""

from __future__ import annotations

import argparse
import math
import random
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from stampc.worlds.plane2d.scenes import cluttered as plane2d_cluttered
from stampc.worlds.plane2d.scenes import cluttered_mobile as plane2d_cluttered_mobile
from stampc.worlds.pybullet.scenes import cluttered_table, cluttered_table_random

VARIANTS = {"low": "1/10", "mid": "1/2", "high": "9/10"}  # crush probability of delicate cans
DELICATE_FRACTION = 0.2
TARGET = "can0"  # the fixed-base scenes' target (the paper's scene draws its own)
#: "pybullet" / "plane2d": the paper's scene, domain.stamp; "pybullet-fixed" /
#: "plane2d-fixed": the fixed-base scenes with arranged blockers, domain_fixed.stamp
WORLDS = ("pybullet", "plane2d", "pybullet-fixed", "plane2d-fixed")
NEAR = 0.85  # m: the Panda's reach (its top-grasp reach over the table is ~0.8 m)


@dataclass(frozen=True)
class Instance:
    """One cluttered-table problem: what ``problem_text`` writes."""

    n: int
    seed: int
    variant: str
    world: str
    delicate: tuple[str, ...]


def delicate_cans(n: int, seed: int, fraction: float = DELICATE_FRACTION) -> tuple[str, ...]:
    """The delicate cans of instance ``(n, seed)`` (at least one), sorted by index."""
    rng = random.Random(f"delicate:{n}:{seed}")
    k = max(1, round(fraction * n))
    return tuple(f"can{i}" for i in sorted(rng.sample(range(n), k)))


def build(n: int = 15, seed: int = 0, *, n_blockers: int = 3, **kwargs: Any) -> dict:
    """The PyBullet scene (via ``stampc.worlds.pybullet.scenes.cluttered_table``);
    ``meta`` also lists the delicate cans. Every can is kept (``tries`` is raised until
    none is dropped) so that the problem's objects all exist."""
    tries = int(kwargs.pop("tries", 50))
    while True:
        scene = cluttered_table(n, seed, n_blockers=n_blockers, tries=tries, **kwargs)
        if scene["meta"]["dropped"] == 0 or tries >= 5000:
            break
        tries *= 4
    scene["meta"]["delicate"] = list(delicate_cans(n, seed))
    return scene


def build_random(n: int = 15, seed: int = 0, **kwargs: Any) -> dict:
    """The paper's scene (``stampc.worlds.pybullet.scenes.cluttered_table_random``):
    cans uniformly at random, a random target, a mobile robot with candidate base
    poses around the table; ``meta`` also lists the delicate cans."""
    scene = cluttered_table_random(n, seed, **kwargs)
    scene["meta"]["delicate"] = [c for c in delicate_cans(n, seed)
                                 if any(o["name"] == c for o in scene["objects"])]
    return scene


def build2d_random(n: int = 15, seed: int = 0, **kwargs: Any) -> dict:
    """The paper's scene on plane2d (``stampc.worlds.plane2d.scenes.cluttered_mobile``):
    same domain, cans at random, a random target, four candidate bases."""
    scene = plane2d_cluttered_mobile(n, seed, **kwargs)
    scene["meta"]["delicate"] = list(delicate_cans(n, seed))
    return scene


#: the paper's (mobile-base) scene builder of each world
MOBILE_BUILDERS = {"pybullet": build_random, "plane2d": build2d_random}


def build2d(n: int = 15, seed: int = 0, *, blockers: int = 2, shelf: bool = True,
            **kwargs: Any) -> dict:
    """The plane2d scene (``stampc.worlds.plane2d.scenes.cluttered``), same names."""
    scene = plane2d_cluttered(n, seed, target=TARGET, blockers=blockers, shelf=shelf, **kwargs)
    scene["meta"]["delicate"] = list(delicate_cans(n, seed))
    return scene


def instance(n: int = 15, seed: int = 0, variant: str = "mid",
             world: str = "pybullet") -> Instance:
    if variant not in VARIANTS:
        raise ValueError(f"unknown crush variant {variant!r}; expected one of "
                         f"{', '.join(VARIANTS)}")
    if world not in WORLDS:
        raise ValueError(f"unknown world {world!r}; expected one of {', '.join(WORLDS)}")
    if n < 2:
        raise ValueError(f"need at least 2 cans, got {n}")
    return Instance(n, seed, variant, world, delicate_cans(n, seed))


def problem_text(n: int = 15, seed: int = 0, variant: str = "mid",
                 world: str = "pybullet") -> str:
    """The ``.stamp`` problem for ``(n, seed, variant)``: on ``pybullet`` / ``plane2d`` the
    paper's scene for ``domain.stamp`` (random target, mobile base), on ``*-fixed`` the
    arranged scenes for ``domain_fixed.stamp``."""
    inst = instance(n, seed, variant, world)
    if world not in MOBILE_BUILDERS:
        return _fixed_problem(inst)
    builder = MOBILE_BUILDERS[world]
    scene = builder(n, seed)
    cans = [o["name"] for o in scene["objects"]]
    target, bases, size = scene["meta"]["target"], scene["meta"]["bases"], scene["meta"]["table"]
    delicate = [c for c in inst.delicate if c in cans]
    lines = [
        f"# {len(cans)} cans at random on a {' x '.join(map(str, size))} m "
        f"table; {target} is the target. Delicate cans",
        f"# crush with probability {VARIANTS[variant]} ({variant}), the others with 1/20. The "
        f"robot starts at base {scene['robot']['start']}.",
        f"# Generated by examples/cluttered_table/scene.py (n={n}, seed={seed}, "
        f"variant={variant}, world={world}).",
        f"problem pick_{target}_n{n}_s{seed}_{variant} for cluttered_table",
        "",
        f"object can0..can{len(cans) - 1}: can",
        "object table: surface",
        f"object {bases[0]}..{bases[-1]}: base",
        f"object pose_can0..pose_can{len(cans) - 1}: pose",
        "",
        "init handempty",
        f"     base_at({scene['robot']['start']})",
    ]
    lines += [f"     delicate_{variant}({c})" for c in delicate]
    lines += [f"     at({c}, pose_{c})" for c in cans]
    lines += [f"     near({b}, pose_{c})" for c, b in near_bases(scene)]
    lines += ["", f"goal holding({target})", "",
              f'scene builder "examples.cluttered_table.scene:{builder.__name__}"'
              f'(n={n}, seed={seed})',
              ""]
    return "\n".join(lines)


def near_bases(scene: dict) -> list[tuple[str, str]]:
    """(can, base) pairs with the base within the arm's reach of the can's initial
    position (plain geometry, a superset of what IK or the 2-D reach disc allows;
    refinement learns the rest)."""
    bases = scene["robot"]["bases"]
    return [(o["name"], b["name"]) for o in scene["objects"] for b in bases
            if math.dist(_xy(o), b["base"][:2]) <= _near(scene)]


def _xy(obj: dict) -> tuple[float, float]:
    return tuple(obj["position"][:2]) if "position" in obj else (obj["x"], obj["y"])


def _near(scene: dict) -> float:
    """PyBullet: the Panda's reach; plane2d: the reach disc plus a contact grasp's offset."""
    robot = scene["robot"]
    if "reach" not in robot:
        return NEAR
    can = max((o.get("radius", 0.0) for o in scene["objects"]), default=0.0)
    return robot["reach"] + robot["gripper_radius"] + can


def _fixed_problem(inst: Instance) -> str:
    n, seed, variant = inst.n, inst.seed, inst.variant
    builder = "build" if inst.world == "pybullet-fixed" else "build2d"
    last = n - 1
    lines = [
        f"# {n} cans on a table; {TARGET} is the target. Delicate cans crush with "
        f"probability {VARIANTS[variant]} ({variant}),",
        "# the others with 1/20. Generated by examples/cluttered_table/scene.py "
        f"(n={n}, seed={seed}, variant={variant}, world={inst.world}); domain: domain_fixed.stamp.",
        f"problem pick_{TARGET}_n{n}_s{seed}_{variant} for cluttered_table_fixed",
        "",
        f"object can0..can{last}: can",
        "object table, tray: surface",
        f"object pose_can0..pose_can{last}: pose",
        "",
        "init handempty",
        "     is_tray(tray)",
    ]
    lines += [f"     delicate_{variant}({c})" for c in inst.delicate]
    lines += [f"     at(can{i}, pose_can{i})" for i in range(n)]
    lines += [
        "",
        f"goal holding({TARGET})",
        "",
        f'scene builder "examples.cluttered_table.scene:{builder}"(n={n}, seed={seed})',
        "",
    ]
    return "\n".join(lines)


def write_problem(path: str | Path, n: int = 15, seed: int = 0, variant: str = "mid",
                  world: str = "pybullet") -> Path:
    """Write ``problem_text(...)`` to ``path`` (next to ``domain.stamp`` or anywhere:
    the refine command takes both files); returns the path."""
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(problem_text(n, seed, variant, world), encoding="utf-8")
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="write a cluttered-table problem")
    parser.add_argument("--n", type=int, default=15)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--variant", choices=sorted(VARIANTS), default="mid")
    parser.add_argument("--world", choices=WORLDS, default="pybullet")
    parser.add_argument("-o", "--output", help="file to write (default: stdout)")
    args = parser.parse_args(argv)
    if args.output:
        write_problem(args.output, args.n, args.seed, args.variant, args.world)
    else:
        print(problem_text(args.n, args.seed, args.variant, args.world), end="")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
