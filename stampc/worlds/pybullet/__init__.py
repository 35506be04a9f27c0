"""The PyBullet + OMPL concrete world (Franka Panda / KUKA iiwa arms, a free-flying UAV).

``open_world(scene, seed=...)`` validates a scene dict (see :mod:`.scene`) and returns a
:class:`PyBulletWorld`; bound generators, evaluators and executors live in
:mod:`.manipulation` and :mod:`.aerial`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping

from stampc.worlds.base import scene_argument
from stampc.worlds.pybullet.scene_check import parse_scene
from stampc.worlds.pybullet.values import Config, Grasp, Pose, Traj
from stampc.worlds.pybullet.world import PyBulletWorld, WorldState

__all__ = ["open_world", "PyBulletWorld", "WorldState", "Pose", "Grasp", "Config", "Traj"]


def open_world(scene: Mapping[str, Any] | str | Path, *, seed: int,
               verbose: bool = False, visuals: bool = True) -> PyBulletWorld:
    """Build the world described by ``scene`` (a dict or a JSON file) on a fresh PyBullet
    DIRECT client. ``seed`` is recorded; every bound function samples from ``ctx.rng``.
    ``visuals=False`` skips the visual shapes, which only rendering uses (a Panda loads
    in a tenth of the time); such a world cannot ``render``."""
    scene, _ = scene_argument(scene, seed, read_code="PB003", seed_code="PB004",
                              world="pybullet")
    return PyBulletWorld(parse_scene(scene), seed=seed, verbose=verbose, visuals=visuals)
