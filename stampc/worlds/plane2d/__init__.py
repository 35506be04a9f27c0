"""stampc.worlds.plane2d: a fast, exact 2-D table-top world.

A top-down table with discs and boxes, a disc gripper that reaches along straight or
RRT-Connect paths, swept-area collision checks and a 2-D UAV. It implements the same
bound-function contract as the PyBullet world, so a domain bound with relative bindings
(``".manipulation:grasp"``) runs on both. See docs/worlds-plane2d.md.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping

from stampc.worlds.base import scene_argument
from stampc.worlds.plane2d.scene import Scene, parse_scene
from stampc.worlds.plane2d.values import Config2, Grasp2, Pose2, Traj2
from stampc.worlds.plane2d.world import Plane2DWorld, WorldState

__all__ = ["open_world", "Plane2DWorld", "WorldState", "Scene", "parse_scene",
           "Pose2", "Grasp2", "Config2", "Traj2"]


def open_world(scene: Mapping[str, Any] | str | Path, *, seed: int,
               verbose: bool = False, visuals: bool = True) -> Plane2DWorld:
    """Build a world from a scene dict (or the path of a JSON scene file).

    The world itself is deterministic (every bound function samples from ``ctx.rng``);
    ``seed`` is recorded for reproducibility reports. ``verbose`` prints planning
    fallbacks to stderr. ``visuals`` is accepted for the worlds' common signature: this
    world draws from its state alone, so it can always render.

    Raises :class:`StampcError` with ``S2xx`` diagnostics for malformed scenes.
    """
    scene, source = scene_argument(scene, seed, read_code="S200", seed_code="S202",
                                   world="plane2d")
    return Plane2DWorld(parse_scene(scene, source=source), seed=seed, verbose=verbose)
