"""Headless rendering with PyBullet's CPU TinyRenderer, and GIF writing.

A 640×480 frame costs ~60 ms on the CPU (shadows would multiply that by 2.5).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Iterable, Sequence

import numpy as np

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.pybullet._pb import p
from stampc.worlds.pybullet.values import Traj, interpolate

if TYPE_CHECKING:  # annotations only: the world imports this module to render itself
    from stampc.worlds.pybullet.world import PyBulletWorld


def _camera(world: PyBulletWorld) -> tuple[list[float], float, float, float]:
    """A default camera looking at the scene's centre (target, distance, yaw, pitch)."""
    if world.spec.uav is not None and world.robot < 0:
        return [0.0, 0.0, 1.5], 11.0, 45.0, -35.0
    if world.spec.surfaces:  # the first surface (the table) in the middle of the frame
        table = world.spec.surfaces[0]
        return [table.position[0], table.position[1], table.top + 0.1], \
            1.3 + 0.6 * max(table.size[:2]), 60.0, -35.0
    return [0.45, 0.0, 0.1], 1.6, 60.0, -35.0


def render_frame(world: PyBulletWorld, width: int = 320, height: int = 240, *,
                 target: Sequence[float] | None = None, distance: float | None = None,
                 yaw: float | None = None, pitch: float | None = None) -> np.ndarray:
    """An RGB image (``height × width × 3``, uint8) of the world's current bodies."""
    if width <= 0 or height <= 0:
        raise StampcError([error("PB040", f"frame size must be positive, got {width}x{height}",
                                 Span.point("<render>"))])
    if not world.visuals:
        raise StampcError([error("PB043", "this world was built without visual shapes, so it "
                                 "cannot render", Span.point("<render>"),
                                 "open it with open_world(..., visuals=True)")])
    d_target, d_dist, d_yaw, d_pitch = _camera(world)
    view = p.computeViewMatrixFromYawPitchRoll(
        cameraTargetPosition=list(target or d_target), distance=distance or d_dist,
        yaw=d_yaw if yaw is None else yaw, pitch=d_pitch if pitch is None else pitch,
        roll=0.0, upAxisIndex=2, physicsClientId=world.client)
    proj = p.computeProjectionMatrixFOV(fov=50.0, aspect=width / height, nearVal=0.05,
                                        farVal=50.0, physicsClientId=world.client)
    _, _, rgba, _, _ = p.getCameraImage(width, height, view, proj,
                                        renderer=p.ER_TINY_RENDERER,
                                        physicsClientId=world.client)
    image = np.asarray(rgba, dtype=np.uint8).reshape(height, width, 4)
    return image[:, :, :3].copy()


def render_trajectory(world: PyBulletWorld, traj: Traj, width: int = 320, height: int = 240,
                      step: float = 0.15) -> list[np.ndarray]:
    """Frames of the arm moving along ``traj`` (the world's state is left unchanged)."""
    frames = []
    try:
        for a, b in zip(traj.configs, traj.configs[1:]):
            for q in interpolate(a, b, step)[:-1]:
                world.set_arm(q)
                frames.append(render_frame(world, width, height))
        world.set_arm(traj.end)
        frames.append(render_frame(world, width, height))
    finally:
        world.set_arm(world.state.q)
    return frames


def write_gif(frames: Iterable[np.ndarray], path: str | Path, fps: float = 10.0) -> Path:
    """Write frames to an animated GIF; raises ``StampcError`` if there are none or the
    file cannot be written."""
    import imageio.v2 as imageio

    frames = list(frames)
    out = Path(path)
    if not frames:
        raise StampcError([error("PB041", "no frames to write", Span.point(str(out)))])
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        imageio.mimsave(out, frames, duration=1.0 / fps, loop=0)
    except OSError as exc:
        raise StampcError([error("PB042", f"cannot write {out}: {exc}", Span.point(str(out)))])
    return out
