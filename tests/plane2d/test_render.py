"""Rendering writes a real PNG and leaves the world state untouched."""

from __future__ import annotations

import imageio.v3 as iio

from stampc.worlds.plane2d import manipulation as m
from stampc.worlds.plane2d.render import render_png

from .conftest import make_ctx


def test_render_png_with_trajectory(world, tmp_path):
    ctx = make_ctx(world)
    _, q = next(m.grasp(ctx, "can0", world.pose("can0")))
    (t,) = next(m.motion(ctx, q))
    start = world.snapshot()
    m.discard(ctx, m.ConcreteAction("discard", {"o": "can4"}))
    out = render_png(world, tmp_path / "state.png", state=start, trajectories=[t], title="x")
    assert world.snapshot() is not start and not world.present("can4")   # state restored
    image = iio.imread(out)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert image.shape[0] > 100 and image.shape[1] > 100
    assert len({tuple(px) for px in image.reshape(-1, image.shape[-1])[::97]}) > 5


def test_world_render_returns_fixed_size_rgb_frames(world):
    first = world.render()
    m.discard(make_ctx(world), m.ConcreteAction("discard", {"o": "can1"}))
    second = world.render()
    assert first.dtype.name == "uint8" and first.ndim == 3 and first.shape[2] == 3
    assert first.shape == second.shape
    assert (first != second).any()           # can1 vanished from the picture


def test_render_to_missing_folder_is_a_diagnostic(world, tmp_path):
    import pytest

    from stampc.diagnostics import StampcError

    with pytest.raises(StampcError) as info:
        render_png(world, tmp_path / "no" / "such" / "dir.png")
    assert info.value.diagnostics[0].code == "S280"
