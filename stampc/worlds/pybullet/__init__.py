"""The PyBullet + OMPL concrete world (Franka Panda / KUKA iiwa arms, a free-flying UAV).

``open_world(scene, seed=...)`` validates a scene dict (see :mod:`.scene`) and returns a
:class:`PyBulletWorld`; bound generators, evaluators and executors live in
:mod:`.manipulation` and :mod:`.aerial`.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Mapping

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.pybullet.scene import parse_scene
from stampc.worlds.pybullet.values import Config, Grasp, Pose, Traj
from stampc.worlds.pybullet.world import PyBulletWorld, WorldState

__all__ = ["open_world", "PyBulletWorld", "WorldState", "Pose", "Grasp", "Config", "Traj"]


def open_world(scene: Mapping[str, Any] | str | Path, *, seed: int,
               verbose: bool = False) -> PyBulletWorld:
    """Build the world described by ``scene`` (a dict or a JSON file) on a fresh PyBullet
    DIRECT client. ``seed`` is recorded; every bound function samples from ``ctx.rng``."""
    if isinstance(scene, (str, Path)):
        source = str(scene)
        try:
            scene = json.loads(Path(scene).read_text(encoding="utf-8"))
        except OSError as exc:
            raise StampcError([error("PB003", f"cannot read scene file {source!r}: "
                                     f"{exc.strerror}", Span.point(source))]) from None
        except json.JSONDecodeError as exc:
            raise StampcError([error("PB003", f"scene file is not valid JSON: {exc.msg}",
                                     Span.point(source, exc.lineno, exc.colno))]) from None
    if isinstance(seed, bool) or not isinstance(seed, int):
        raise StampcError([error("PB004", f"seed must be an integer, got {seed!r}",
                                 Span.point("<pybullet world>"))])
    return PyBulletWorld(parse_scene(scene), seed=seed, verbose=verbose)
