"""Cluttered-table bindings for the PyBullet world (``examples/cluttered_table``).

Fixed-base domain (``domain_fixed.stamp``):
- ``.cluttered:grasp`` / ``.cluttered:placement``: the manipulation generators, reordered
  so that configs whose hand (and held can) is clear of the other cans come first. In a
  packed table most top grasps of a can close a finger on a neighbour; taking such a
  sample first would make refinement learn a ``collision`` that a better grasp avoids.
  Configs that touch other cans still follow (their trajectories name the blockers).
- ``.cluttered:discard``: carry the held can to the config ``q`` (over the tray or the
  bin) and take it out of the scene, so it obstructs nothing afterwards.

Mobile-base domain (``domain.stamp``; the robot stands at one of the scene's named base
poses, ``b`` arguments are their names):
- ``.cluttered:grasp_at(b, o, p)``: the robot's grasps from base ``b``, clear first: the
  scene's robot ``grasps`` (top: from above at 4 yaws; side: horizontal approaches
  from 8 directions, the paper's scenario, where the cans around the target are in
  the way);
- ``.cluttered:placement_here(o, s)``: placements within reach of the robot's current
  base, clear first;
- ``.cluttered:bin_drop(o)``: the config holding ``o`` over the bin the robot carries
  beside its base (:data:`BIN`, in the base frame);
- ``.cluttered:reaches(b, o, p)`` (evaluator): one of those grasps of ``o`` at ``p`` has
  an IK solution from ``b`` (collisions ignored);
- ``.cluttered:move_base`` (executor, arguments ``a``, ``b``): tuck the arm in (rest
  config), then re-place the base at ``b`` (base motions are not collision-checked).
"""

from __future__ import annotations

import random
from typing import Iterable, Iterator, TypeVar

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.pybullet import manipulation, robots
from stampc.worlds.pybullet.kinematics import grasps_of_kind, solve_ik, top_grasp
from stampc.worlds.pybullet.manipulation import _arg, _budget, _check_object, _world
from stampc.worlds.pybullet.values import Config, Grasp, Pose, as_config, as_pose, interpolate
from stampc.worlds.pybullet.world import CLEARANCE, PyBulletWorld

T = TypeVar("T", bound=tuple)
APPROACH_STEP = 0.05  # rad between checked configs of the straight approach
REACH = 0.8  # m: the Panda's top-grasp reach over a table at base height (measured)
#: the bin the robot carries: where the held can is let go, in the base frame (m)
BIN = (-0.15, 0.45, 0.35)


def movable_hits(world: PyBulletWorld, config: Config, ignore: str) -> frozenset[str]:
    """Cans the arm (and the held can) touch at ``config`` and on its straight approach
    from ``config.pre``, besides ``ignore`` (the can being grasped or placed)."""
    world.select(config.robot)
    configs = [config.q] if config.pre is None else interpolate(config.pre, config.q,
                                                                APPROACH_STEP)
    hit: set[str] = set()
    try:
        for q in configs:
            robot, held = world.hits(q, clearance=CLEARANCE)  # as the final sweep will
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
    world = ctx.world
    assert isinstance(world, PyBulletWorld)
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


def _unbudgeted(ctx: Context, **options: object) -> Context:
    kept = {k: v for k, v in ctx.options.items() if k != "budget"}
    return Context(world=ctx.world, rng=ctx.rng, options={**kept, **options},
                   cache=ctx.cache, values=ctx.values, deadline=ctx.deadline)


def grasp(ctx: Context, o: str, p: Pose) -> Iterator[tuple[Grasp, Config]]:
    """Grasps of ``o`` at ``p`` (as ``.manipulation:grasp``), clear ones first."""
    return _clear_first(ctx, manipulation.grasp(_unbudgeted(ctx), o, p), 1, o)


def placement(ctx: Context, o: str, s: str) -> Iterator[tuple[Pose, Config]]:
    """Placements of ``o`` on ``s`` (as ``.manipulation:placement``), clear ones first."""
    return _clear_first(ctx, manipulation.placement(_unbudgeted(ctx), o, s), 1, o)


def discard(ctx: Context, action: ConcreteAction) -> None:
    """Move to ``q`` (over the tray or bin) and take ``o`` out of the scene."""
    o, q = str(_arg(action, "o")), as_config(_arg(action, "q"))
    world = _world(ctx, q.robot)
    _check_object(world, o)
    world.update(q=q.q, retreat=None, released=None)
    changes: dict = {"removed": world.state.removed | {o}, "retreat": q.pre}
    if world.state.held == o:
        changes.update(held=None, grip=None)
    world.update(**changes)


# ------------------------------------------------------------------ mobile base
def _at_base(ctx: Context, b: str) -> PyBulletWorld | None:
    """The world with its (first) robot selected, if that robot stands at base ``b``."""
    world = _world(ctx)
    if b not in world.candidate_bases():
        raise StampcError([error("PB017", f"unknown base pose {b!r}", Span.point("<world>"),
                                 f"the robot's bases: {', '.join(world.candidate_bases())}")])
    return world if world.state.arm is not None and world.state.arm.base_name == b else None


def _grasps(ctx: Context, o: str, p: Pose) -> Iterator[tuple[Grasp, Config]]:
    """The robot's grasps of its kind (scene ``grasps``) with a config from where it
    stands, in a seeded random order."""
    world = _world(ctx)
    robot, base = manipulation._owner(world)
    grasps = grasps_of_kind(world.geometry[o], world.grasp_kinds())
    ctx.rng.shuffle(grasps)
    for g in grasps:
        config = manipulation._grasp_config(world, ctx, o, p, g)
        world.set_arm(world.state.q)
        if config is not None:
            yield Grasp(g.hand, g.approach, g.kind, g.standoff, robot, base), config


def grasp_at(ctx: Context, b: str, o: str, p: Pose) -> Iterator[tuple[Grasp, Config]]:
    """The robot's grasps of ``o`` at ``p`` from base ``b``, clear of other cans first;
    nothing unless the robot stands at ``b``."""
    world = _at_base(ctx, b)
    _check_object(_world(ctx), o)
    if world is None:
        return iter(())
    return _clear_first(ctx, _grasps(ctx, o, as_pose(p)), 1, o)


def placement_here(ctx: Context, o: str, s: str) -> Iterator[tuple[Pose, Config]]:
    """Placements of ``o`` on ``s`` within reach of the robot's base, clear ones first."""
    _world(ctx)
    samples = manipulation.placement(_unbudgeted(ctx, reach=REACH), o, s)
    return _clear_first(ctx, samples, 1, o)


def bin_drop(ctx: Context, o: str) -> Iterator[tuple[Config]]:
    """The config holding ``o`` (with its grip) over the bin beside the robot's base."""
    world = _world(ctx)
    _check_object(world, o)
    if world.state.held != o or world.state.grip is None:
        return
    base = world.base_pose()
    drop = base.multiply(Pose(BIN))
    hand = Pose(drop.pos, base.multiply(top_grasp(world.geometry[o], 0.0).hand).quat)
    rng = random.Random(f"bin:{o}")  # deterministic: the bin does not move on the base
    q = solve_ik(world, hand, rng)
    above = Pose((hand.pos[0], hand.pos[1], hand.pos[2] + 0.05), hand.quat)
    pre = solve_ik(world, above, rng, seed_q=q) if q is not None else None
    world.set_arm(world.state.q)
    if q is not None and pre is not None:
        robot, where = manipulation._owner(world)
        yield (Config.of(q, obj=o, pre=pre, robot=robot, base=where),)


def reaches(ctx: Context, b: str, o: str, p: Pose) -> bool:
    """Whether one of the robot's grasps of ``o`` at ``p`` has IK from base ``b``."""
    world = _world(ctx)
    _check_object(world, o)
    bases = world.candidate_bases()
    if b not in bases:
        _at_base(ctx, b)  # raises the located error
    return robots.reaches(world, ctx, o, as_pose(p), bases[b])


def move_base(ctx: Context, action: ConcreteAction) -> None:
    """Tuck the arm in (its rest config; a held can comes along), then drive to base
    ``b``: the next motion starts from the rest config, clear of the table."""
    b = str(_arg(action, "b"))
    world = _world(ctx)
    bases = world.candidate_bases()
    if b not in bases:
        _at_base(ctx, b)
    assert world.model is not None
    world.update(q=world.model.rest)
    world.move_base(bases[b], b)
