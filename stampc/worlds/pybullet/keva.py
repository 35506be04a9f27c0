"""Bound functions of the keva domain on the PyBullet world.

The scene's ``meta`` carries the structure (``slots``: slot name -> target pose) and the
feed locations (``feeds``: feed name -> pose), see ``examples/keva/scene.py``.

- ``.keva:feed_grasp(k, f)`` — top grasps of plank ``k`` lying at feed ``f``, closing
  across its width, in a fixed order;
- ``.keva:slot_placement(k, s)`` — the slot's target pose (or one of its symmetric
  equivalents: a plank is a box) and an accurate IK config putting the held plank there,
  computed deterministically from the slot and the grip (same inputs → same config, so
  policy branches that reach the same slot share their concrete state);
- ``.keva:pick`` — grasp: the plank is held at the *nominal* grip of its grasp;
- ``.keva:place`` — put the plank exactly at its slot pose, then the outcome's next plank
  arrives at its feed location (taken from the supply).

After a placement the concrete state depends only on the slot filled and the feed used
by the next plank, not on where the placed plank came from, so the engine merges the
branches and refines each repeated sub-policy once.
"""

from __future__ import annotations

import math
import random
from typing import Any, Iterator, Mapping

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.pybullet import manipulation
from stampc.worlds.pybullet.kinematics import IkSettings, solve_ik, top_grasp
from stampc.worlds.pybullet.values import (Config, Grasp, Pose, as_config, as_pose,
                                           quat_from_axis_angle)
from stampc.worlds.pybullet.world import PyBulletWorld

GRASP_DEPTH = 0.008  # m the fingertips reach below the plank's top face
#: m above the slot where the hand lets go (more than the IK tolerance, so the held
#: plank never touches the planks below; the executor sets it down exactly)
PLACE_CLEARANCE = 0.006
#: m above the place pose where the straight vertical approach may start (first that works)
PRE_PLACE = (0.1, 0.07, 0.04)
#: accurate IK for placements (PyBullet's IK plateaus around 2 mm, often more)
PLACE_IK = IkSettings(restarts=8, refinements=5, pos_tol=0.004, ang_tol=0.02)
PRE_IK = IkSettings(restarts=8)  # the approach's start needs no accuracy
#: rotations mapping a box onto itself (identity, half turns about its axes)
SYMMETRIES = (Pose((0.0, 0.0, 0.0)),
              Pose((0.0, 0.0, 0.0), quat_from_axis_angle((0.0, 0.0, 1.0), math.pi)),
              Pose((0.0, 0.0, 0.0), quat_from_axis_angle((1.0, 0.0, 0.0), math.pi)),
              Pose((0.0, 0.0, 0.0), quat_from_axis_angle((0.0, 1.0, 0.0), math.pi)))


def _meta_pose(world: PyBulletWorld, section: str, name: str) -> Pose:
    table: Mapping[str, Any] = world.spec.meta.get(section, {})
    if name not in table:
        raise StampcError([error("PB050", f"scene meta has no {section[:-1]} {name!r}",
                                 Span.point("<scene meta>"),
                                 f"build the scene with examples/keva/scene.py; known: "
                                 f"{', '.join(sorted(table)) or 'none'}")])
    return as_pose(table[name])


def slot_pose(world: PyBulletWorld, s: str) -> Pose:
    return _meta_pose(world, "slots", s)


def feed_pose(world: PyBulletWorld, f: str) -> Pose:
    return _meta_pose(world, "feeds", f)


def _world(ctx: Context) -> PyBulletWorld:
    return manipulation._world(ctx)


# ------------------------------------------------------------------ generators
def feed_grasp(ctx: Context, k: str, f: str) -> Iterator[tuple[Grasp, Config]]:
    """Top grasps of ``k`` (lying at feed ``f``) closing across its width, yaw 0 then π."""
    world = _world(ctx)
    manipulation._check_object(world, k)
    feed_pose(world, f)  # a bad feed name is a located error
    p = world.object_pose(k)
    for yaw in (0.0, math.pi):
        g = top_grasp(world.geometry[k], yaw, depth=GRASP_DEPTH)
        config = manipulation._grasp_config(world, ctx, k, p, g)
        world.set_arm(world.state.q)
        if config is not None:
            yield g, config


def slot_placement(ctx: Context, k: str, s: str) -> Iterator[tuple[Pose, Config]]:
    """The target pose of slot ``s`` (up to the plank's symmetry) and the config that
    puts the held plank ``k`` there, then lets go ``PLACE_CLEARANCE`` above it."""
    world = _world(ctx)
    manipulation._check_object(world, k)
    target = slot_pose(world, s)
    state = world.state
    if state.held != k or state.grip is None:
        return
    rng = random.Random(f"keva-place:{s}")  # deterministic: see the module docstring
    for sym in SYMMETRIES:
        p = target.multiply(sym)
        raised = Pose((p.pos[0], p.pos[1], p.pos[2] + PLACE_CLEARANCE), p.quat)
        hand = raised.multiply(state.grip.inverse())
        q = solve_ik(world, hand, rng, settings=PLACE_IK)
        pre = _pre_place(world, hand, q, rng) if q is not None else None
        world.set_arm(state.q)
        if q is not None and pre is not None:
            yield p, Config.of(q, obj=k, pre=pre)


def _pre_place(world: PyBulletWorld, hand: Pose, q: tuple[float, ...],
               rng: random.Random) -> tuple[float, ...] | None:
    """A config ``PRE_PLACE`` (or less) above ``hand`` with a free vertical approach."""
    for height in PRE_PLACE:
        above = Pose((hand.pos[0], hand.pos[1], hand.pos[2] + height), hand.quat)
        pre = solve_ik(world, above, rng, seed_q=q, settings=PRE_IK)
        if pre is not None and manipulation._approach_ok(world, pre, q, placing=True):
            return pre
    return None


# ------------------------------------------------------------------ executors
def pick(ctx: Context, action: ConcreteAction) -> None:
    """Move to the grasp config; hold ``k`` at the grasp's nominal grip."""
    world = _world(ctx)
    k = str(manipulation._arg(action, "k"))
    q = as_config(manipulation._arg(action, "q"))
    g = manipulation._arg(action, "g")
    manipulation._check_object(world, k)
    world.update(q=q.q, retreat=None, released=None)
    if any(name == "holding" and k in args for name, args in action.adds):
        hand = g.hand if isinstance(g, Grasp) else as_pose(g["hand"])  # type: ignore[index]
        world.update(held=k, grip=hand.inverse(), retreat=q.pre)
    else:
        world.update(retreat=q.pre, released=k)


def place(ctx: Context, action: ConcreteAction) -> None:
    """Put ``k`` exactly at ``p``; the outcome's next plank arrives at its feed."""
    world = _world(ctx)
    k = str(manipulation._arg(action, "k"))
    p = as_pose(manipulation._arg(action, "p"))
    q = as_config(manipulation._arg(action, "q"))
    manipulation._check_object(world, k)
    world.update(q=q.q, retreat=None, released=None)
    if world.state.held != k:
        world.update(retreat=q.pre)
        return
    poses = dict(world.state.poses)
    poses[k] = p
    for name, args in action.adds:
        if name == "at_feed":
            plank, feed = str(args[0]), str(args[1])
            manipulation._check_object(world, plank)
            poses[plank] = feed_pose(world, feed)
    world.update(held=None, grip=None, retreat=q.pre, released=k,
                 poses=tuple((n, poses[n]) for n, _ in world.state.poses))
