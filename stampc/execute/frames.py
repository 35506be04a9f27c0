"""Frames of the first run: along every trajectory (at least :data:`PER_MOTION` frames per
motion), after every action and every few physics steps while objects settle; written
as PNGs, an animated GIF and — when ``imageio-ffmpeg`` is installed — an MP4."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

PER_MOTION = 12
FPS = 12.0


class Recorder:
    def __init__(self, out: Path) -> None:
        self.out = out
        self.frames: list = []
        self.active = True
        out.mkdir(parents=True, exist_ok=True)

    def start(self, world: Any) -> None:
        self.frames.append(world.render())

    def on_run_start(self, run: int) -> None:
        self.active = run == 0

    def frame(self, world: Any) -> None:
        if self.active:
            self.frames.append(world.render())

    def on_step(self, run: int, world: Any) -> None:
        if run == 0:
            self.frames.append(world.render())

    def motion(self, world: Any, action: Any) -> None:
        """Frames of the robot following each trajectory of ``action`` (state unchanged)."""
        if not self.active:
            return
        if hasattr(world, "move_gripper"):
            self._plane2d(world, action)
            return
        from stampc.execute.recheck import pybullet_trajectories

        for traj in pybullet_trajectories(action):
            if world.uav >= 0 and traj.configs and len(traj.configs[0]) == 7:
                self._flight(world, traj)
            elif world.robot >= 0:
                self._arm(world, traj)

    def _plane2d(self, world: Any, action: Any) -> None:
        from stampc.worlds.plane2d.values import Traj2

        start = world.snapshot()
        for traj in (v for v in action.args.values() if isinstance(v, Traj2)):
            uav = world.uav is not None and traj.points and traj.points[0] == world.uav
            try:
                for point in along(traj.points, PER_MOTION):
                    if uav:
                        world.set_uav(point, world.battery)
                    else:
                        world.move_gripper([traj.points[0], point])
                    self.frames.append(world.render())
            finally:
                world.restore(start)

    def _arm(self, world: Any, traj: Any) -> None:
        try:
            for q in along(traj.configs, PER_MOTION):
                world.set_arm(q)
                self.frames.append(world.render())
        finally:
            world.set_arm(world.state.q)

    def _flight(self, world: Any, traj: Any) -> None:
        from stampc.worlds.pybullet._pb import p

        try:
            for c in along(traj.configs, PER_MOTION):
                norm = math.sqrt(sum(v * v for v in c[3:])) or 1.0
                p.resetBasePositionAndOrientation(world.uav, c[:3], [v / norm for v in c[3:]],
                                                  physicsClientId=world.client)
                self.frames.append(world.render())
        finally:
            uav = world.state.uav
            if uav is not None:
                p.resetBasePositionAndOrientation(world.uav, uav.pos, uav.quat,
                                                  physicsClientId=world.client)

    def finish(self) -> list[Path]:
        import imageio.v2 as imageio

        for i, frame in enumerate(self.frames):
            imageio.imwrite(self.out / f"frame_{i:03d}.png", frame)
        written = [self.out / "run.gif"]
        imageio.mimsave(written[0], self.frames, duration=1.0 / FPS, loop=0)
        import importlib.util
        if importlib.util.find_spec("imageio_ffmpeg") is None:  # the optional [video] extra
            return written
        writer = imageio.get_writer(self.out / "run.mp4", fps=FPS, macro_block_size=8)
        for frame in self.frames:
            writer.append_data(_padded(frame, 8))  # codecs want sides divisible by 8
        writer.close()
        return written + [self.out / "run.mp4"]


def along(configs: tuple, n: int) -> list[tuple[float, ...]]:
    """``n`` (or more: every waypoint) configurations evenly spaced along a polyline."""
    lengths = [math.dist(a, b) for a, b in zip(configs, configs[1:])]
    total = sum(lengths)
    if total == 0 or len(configs) < 2:
        return [tuple(configs[-1])] if configs else []
    out = []
    for k in range(n + 1):
        s, i = total * k / n, 0
        while i < len(lengths) - 1 and s > lengths[i]:
            s -= lengths[i]
            i += 1
        t = min(1.0, s / lengths[i]) if lengths[i] else 1.0
        a, b = configs[i], configs[i + 1]
        out.append(tuple(x + (y - x) * t for x, y in zip(a, b)))
    return out


def _padded(frame: Any, block: int) -> Any:
    import numpy as np

    h, w = frame.shape[:2]
    pad = ((0, -h % block), (0, -w % block), (0, 0))
    return np.pad(frame, pad, constant_values=255)
