"""Cluttered-table bindings for the PyBullet world (``examples/cluttered_table``).

- ``.cluttered:grasp`` / ``.cluttered:placement``: the manipulation generators, reordered
  so that configs whose hand (and held can) is clear of the other cans come first. In a
  packed table most top grasps of a can close a finger on a neighbour; taking such a
  sample first would make refinement learn a ``collision`` that a better grasp avoids.
  Configs that touch other cans still follow (their trajectories name the blockers).
- ``.cluttered:discard``: carry the held can to the config ``q`` above the tray and drop
  it in the bin: it leaves the scene, so it obstructs nothing afterwards (the generic
  ``.manipulation:discard`` only removes the object, without moving the arm).
"""

from __future__ import annotations

from typing import Iterable, Iterator, TypeVar

from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.pybullet import manipulation
from stampc.worlds.pybullet.manipulation import _arg, _budget, _check_object, _world
from stampc.worlds.pybullet.values import Config, Grasp, Pose, as_config, interpolate
from stampc.worlds.pybullet.world import PyBulletWorld

T = TypeVar("T", bound=tuple)
APPROACH_STEP = 0.05  # rad between checked configs of the straight approach


def movable_hits(world: PyBulletWorld, config: Config, ignore: str) -> frozenset[str]:
    """Cans the arm (and the held can) touch at ``config`` and on its straight approach
    from ``config.pre``, besides ``ignore`` (the can being grasped or placed)."""
    configs = [config.q] if config.pre is None else interpolate(config.pre, config.q,
                                                                APPROACH_STEP)
    hit: set[str] = set()
    try:
        for q in configs:
            robot, held = world.hits(q)
            hit |= world.names((robot | held) & world.movable_ids)
    finally:
        world.set_arm(world.state.q)
    hit.discard(ignore)
    if world.state.held is not None:
        hit.discard(world.state.held)
    return frozenset(hit)


def _clear_first(ctx: Context, samples: Iterable[T], config_index: int, o: str) -> Iterator[T]:
    """Yield the samples whose config is clear of other cans first, then the rest, up
    to the generator's budget."""
    world = _world(ctx)
    budget = _budget(ctx)
    deferred: list[T] = []
    yielded = 0
    for sample in samples:
        if movable_hits(world, sample[config_index], o):
            deferred.append(sample)
            continue
        yield sample
        yielded += 1
        if yielded >= budget:
            return
    for sample in deferred[: budget - yielded]:
        yield sample


def _unbudgeted(ctx: Context) -> Context:
    options = {k: v for k, v in ctx.options.items() if k != "budget"}
    return Context(world=ctx.world, rng=ctx.rng, options=options, cache=ctx.cache,
                   values=ctx.values, deadline=ctx.deadline)


def grasp(ctx: Context, o: str, p: Pose) -> Iterator[tuple[Grasp, Config]]:
    """Grasps of ``o`` at ``p`` (as ``.manipulation:grasp``), clear ones first."""
    return _clear_first(ctx, manipulation.grasp(_unbudgeted(ctx), o, p), 1, o)


def placement(ctx: Context, o: str, s: str) -> Iterator[tuple[Pose, Config]]:
    """Placements of ``o`` on ``s`` (as ``.manipulation:placement``), clear ones first."""
    return _clear_first(ctx, manipulation.placement(_unbudgeted(ctx), o, s), 1, o)


def discard(ctx: Context, action: ConcreteAction) -> None:
    """Move to ``q`` (over the tray) and take ``o`` out of the scene."""
    world = _world(ctx)
    o, q = str(_arg(action, "o")), as_config(_arg(action, "q"))
    _check_object(world, o)
    world.update(q=q.q, retreat=None, released=None)
    changes: dict = {"removed": world.state.removed | {o}, "retreat": q.pre}
    if world.state.held == o:
        changes.update(held=None, grip=None)
    world.update(**changes)
