"""Headless rendering and GIF output."""

from __future__ import annotations

import imageio.v2 as imageio
import numpy as np
import pytest

from stampc.diagnostics import StampcError
from stampc.worlds.pybullet import open_world
from stampc.worlds.pybullet.render import render_frame, render_trajectory, write_gif
from stampc.worlds.pybullet.scenes import cluttered_table
from stampc.worlds.pybullet.values import Traj


@pytest.fixture(scope="module")
def world():
    w = open_world(cluttered_table(5, seed=0), seed=0)
    yield w
    w.close()


def test_frame_shows_the_scene(world):
    frame = render_frame(world, 96, 64)
    assert frame.shape == (64, 96, 3) and frame.dtype == np.uint8
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 10  # not a blank image


def test_frames_change_when_the_arm_moves_and_gif_roundtrips(world, tmp_path):
    q0 = world.state.q
    q1 = tuple(v + d for v, d in zip(q0, (0.8, 0.4, 0, 0.3, 0, 0, 0)))
    frames = render_trajectory(world, Traj((q0, q1)), 64, 48, step=0.3)
    assert len(frames) >= 3
    assert np.abs(frames[0].astype(int) - frames[-1].astype(int)).sum() > 0
    assert world.state.q == q0
    out = write_gif(frames, tmp_path / "sub" / "arm.gif")
    back = imageio.mimread(out)
    assert len(back) == len(frames) and back[0].shape[:2] == (48, 64)


def test_render_errors_are_diagnostics(world, tmp_path):
    with pytest.raises(StampcError):
        write_gif([], tmp_path / "empty.gif")
    with pytest.raises(StampcError):
        render_frame(world, 0, 10)


def test_a_world_without_visuals_collides_alike_and_refuses_to_render(world):
    """The refinement's worlds skip visual shapes (loading them is most of a Panda's
    load time): collision verdicts must not change, and drawing must say why it cannot."""
    bare = open_world(cluttered_table(5, seed=0), seed=0, visuals=False)
    try:
        with pytest.raises(StampcError) as info:
            render_frame(bare, 32, 24)
        assert info.value.diagnostics[0].code == "PB043"
        rng = np.random.default_rng(3)
        hit_configs = 0
        for _ in range(60):
            q = tuple(rng.uniform(world.lower, world.upper))
            verdict = world.hits(q)
            assert bare.hits(q) == verdict
            hit_configs += bool(verdict[0])
        assert 0 < hit_configs < 60  # both kinds of verdict were compared
    finally:
        bare.close()
