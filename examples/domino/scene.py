"""Scene builder and problem generator for the domino domain (Shah et al., ATM-MDP).

``build(n, seed)`` is the PyBullet scene: a Panda in front of a table with ``n``
dominoes (``pybullet_data/domino/domino.urdf``, 0.00635 × 0.0254 × 0.0508 m at
``scale=1``) standing in a row across the table, thickness along the row; objects
``d0..``, pose symbols ``pose_d0..`` (``stampc.worlds.pybullet.scenes.domino_row``).
``problem_text(n, k, seed)`` writes the matching problem: the target domino is drawn
from the seed among those with ``k`` neighbours on both sides, and the static
``near1..near{k}`` facts give the topple reach ``k`` (1..3).

    python -m examples.domino.scene --n 15 --k 3 --seed 1 -o p.stamp
"""

from __future__ import annotations

import argparse
import random
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from stampc.worlds.pybullet.scenes import domino_row

MAX_K = 3  # the domain declares near1..near3
SPACING = 0.03  # m between domino centres along the row
SCALE = 1.0  # URDF scaling: the paper's 0.00635 x 0.0254 x 0.0508 m block


@dataclass(frozen=True)
class Instance:
    """One domino problem: ``n`` dominoes, topple reach ``k``, the target's index."""

    n: int
    k: int
    seed: int
    target: int

    @property
    def name(self) -> str:
        return f"domino_n{self.n}_k{self.k}_s{self.seed}"

    def near(self, distance: int) -> list[tuple[int, int]]:
        """Ordered pairs (a, b) of dominoes ``distance`` places apart."""
        return [(a, b) for a in range(self.n) for b in (a - distance, a + distance)
                if 0 <= b < self.n]


def instance(n: int = 10, k: int = 2, seed: int = 0) -> Instance:
    if not 1 <= k <= MAX_K:
        raise ValueError(f"topple reach k must be in 1..{MAX_K}, got {k}")
    if n < 2 * k + 1:
        raise ValueError(f"need at least 2k+1 = {2 * k + 1} dominoes for k = {k}, got {n}")
    rng = random.Random(f"domino-target:{n}:{k}:{seed}")
    return Instance(n, k, seed, rng.randint(k, n - 1 - k))


def build(n: int = 10, seed: int = 0, *, spacing: float = SPACING, scale: float = SCALE,
          **kwargs: Any) -> dict:
    """The PyBullet scene for ``n`` dominoes (same arguments → same scene)."""
    if n < 1:
        raise ValueError(f"need at least one domino, got {n}")
    scene = domino_row(n, seed, spacing=spacing, scale=scale, **kwargs)
    scene["meta"].update(domain="domino", spacing=spacing, scale=scale)
    return scene


def problem_text(n: int = 10, k: int = 2, seed: int = 0) -> str:
    """The ``.stamp`` problem for instance ``(n, k, seed)`` (domain: ``domain.stamp``)."""
    inst = instance(n, k, seed)
    target = f"d{inst.target}"
    lines = [f"# {n} dominoes in a row, topple reach k = {k}; {target} is the target.",
             f"problem {inst.name} for domino", "",
             f"object d0..d{n - 1}: domino",
             "object table, tray: surface",
             f"object pose_d0..pose_d{n - 1}: pose", ""]
    facts = ["handempty", f"target({target})"] + [f"at(d{i}, pose_d{i})" for i in range(n)]
    for distance in range(1, k + 1):
        facts += [f"near{distance}(d{a}, d{b})" for a, b in inst.near(distance)]
    lines.append("init " + "\n     ".join(facts))
    lines += ["", f"goal holding({target})",
              "     forall (d: domino) (toppled(d) implies notified(d))", "",
              f"horizon {2 * 2 * k + 4}", "",
              f'scene builder "examples.domino.scene:build"(n={n}, seed={seed})', ""]
    return "\n".join(lines)


def write_problem(path: str | Path, n: int = 10, k: int = 2, seed: int = 0) -> Path:
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(problem_text(n, k, seed), encoding="utf-8")
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="write a domino problem")
    parser.add_argument("--n", type=int, default=10)
    parser.add_argument("--k", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("-o", "--output", help="file to write (default: stdout)")
    args = parser.parse_args(argv)
    if args.output:
        write_problem(args.output, args.n, args.k, args.seed)
    else:
        print(problem_text(args.n, args.k, args.seed), end="")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
