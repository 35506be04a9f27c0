"""stampc.worlds.plane2d: a fast, exact 2-D table-top world.

A top-down table with discs and boxes, a disc gripper that reaches along straight or
RRT-Connect paths, swept-area collision checks and a 2-D UAV. It implements the same
bound-function contract as the PyBullet world, so a domain bound with relative bindings
(``".manipulation:grasp"``) runs on both. See docs/worlds-plane2d.md.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Mapping

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.plane2d.scene import Scene, parse_scene
from stampc.worlds.plane2d.values import Config2, Grasp2, Pose2, Traj2
from stampc.worlds.plane2d.world import Plane2DWorld, WorldState

__all__ = ["open_world", "Plane2DWorld", "WorldState", "Scene", "parse_scene",
           "Pose2", "Grasp2", "Config2", "Traj2"]


def open_world(scene: Mapping[str, Any] | str | Path, *, seed: int,
               verbose: bool = False) -> Plane2DWorld:
    """Build a world from a scene dict (or the path of a JSON scene file).

    The world itself is deterministic (every bound function samples from ``ctx.rng``);
    ``seed`` is recorded for reproducibility reports. ``verbose`` prints planning
    fallbacks to stderr.

    Raises :class:`StampcError` with ``S2xx`` diagnostics for malformed scenes.
    """
    source = "<scene>"
    if isinstance(scene, (str, Path)):
        source = str(scene)
        try:
            scene = json.loads(Path(scene).read_text(encoding="utf-8"))
        except OSError as exc:
            raise StampcError([error("S200", f"cannot read scene file {source!r}: "
                                     f"{exc.strerror}", Span.point(source))]) from None
        except json.JSONDecodeError as exc:
            raise StampcError([error("S200", f"scene file is not valid JSON: {exc.msg}",
                                     Span.point(source, exc.lineno, exc.colno))]) from None
    if isinstance(seed, bool) or not isinstance(seed, int):
        raise StampcError([error("S202", f"plane2d: seed must be an integer, got {seed!r}",
                                 Span.point("<plane2d world>"))])
    return Plane2DWorld(parse_scene(scene, source=source), seed=seed, verbose=verbose)
