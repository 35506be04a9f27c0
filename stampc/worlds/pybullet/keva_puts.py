"""Put-down configs for the Keva bindings (``keva.py``): where an arm can let its plank
go at a target pose, up to the plank's symmetry, clear of the structure's planks, with a
clear vertical approach — ordered so that the arm can go straight home afterwards."""

from __future__ import annotations

import math
import random
from typing import Callable, Iterator

from stampc.worlds.pybullet import manipulation
from stampc.worlds.pybullet.kinematics import IkSettings, solve_ik
from stampc.worlds.pybullet.planning import CHECK_RESOLUTION, counts, interpolate, sweep
from stampc.worlds.pybullet.values import Config, Pose, Traj, quat_from_axis_angle
from stampc.worlds.pybullet.world import CLEARANCE, FINGER_SLACK, RELEASE_SLACK, PyBulletWorld

#: m above the target where the hand lets go (more than the IK tolerance, so the held
#: plank never touches the planks below)
PLACE_CLEARANCE = 0.006
#: m above the place pose where the straight vertical approach may start (first that works)
PRE_PLACE = (0.1, 0.07, 0.04, 0.025, 0.015)
#: accurate IK for put-downs (PyBullet's IK plateaus around 2 mm, often more)
PLACE_IK = IkSettings(restarts=8, refinements=5, pos_tol=0.004, ang_tol=0.02)
RETRY_IK = IkSettings(restarts=24, refinements=5, pos_tol=0.004, ang_tol=0.02)
PRE_IK = IkSettings(restarts=8)  # the approach's start needs no accuracy
#: rounds of IK over the put pose's variants for configs clear of the planks: the first
#: from the rest config, the others from within NEAR_REST rad of it
PUT_TRIES, NEAR_REST = 4, 0.5
#: rounds (one IK try per variant each) from starts anywhere in the joint ranges, after
#: the near-rest ones found nothing
WIDE_ROUNDS = 3
HOME_RESOLUTION = 0.05  # rad: the way-home check that orders put configs
#: m each finger may open past the plank it lets go, widest first (see :func:`open_to_release`)
RELEASE_SLACKS = (RELEASE_SLACK, 0.003, FINGER_SLACK)
#: rotations mapping a box onto itself (identity, half turns about its axes)
SYMMETRIES = (Pose((0.0, 0.0, 0.0)),
              Pose((0.0, 0.0, 0.0), quat_from_axis_angle((0.0, 0.0, 1.0), math.pi)),
              Pose((0.0, 0.0, 0.0), quat_from_axis_angle((1.0, 0.0, 0.0), math.pi)),
              Pose((0.0, 0.0, 0.0), quat_from_axis_angle((0.0, 1.0, 0.0), math.pi)))
#: an upright plank may also stand turned a quarter about its long (local x) axis: its
#: support relation is the same and the hand can reach it from another side
UPRIGHT_TURNS = tuple(Pose((0.0, 0.0, 0.0), quat_from_axis_angle((1.0, 0.0, 0.0), a))
                      for a in (math.pi / 2, -math.pi / 2))


def put_configs(world: PyBulletWorld, a: str, target: Pose, seeds: tuple[str, random.Random],
                turns: tuple[Pose, ...] = (), wide: int = WIDE_ROUNDS
                ) -> Iterator[tuple[Pose, Config]]:
    """Configs of arm ``a`` putting its plank at ``target`` up to the box's symmetry
    (and the extra ``turns``), each touching no plank at the put or along its vertical
    approach. IK first draws from an RNG seeded by ``seeds[0]`` and the arm — same
    inputs, same config (see the module docstring); only if that finds nothing, from
    the call's own RNG ``seeds[1]`` with more restarts (a retry of the engine then draws
    fresh samples). Each RNG first tries IK from the rest config for every variant, and
    only if none is clear, from configs near rest (``PUT_TRIES`` rounds, only for the
    variants IK reached); then ``wide`` rounds from starts anywhere in the joint ranges
    (near the top of a tall tower the configs clear of the planks below may be far from
    rest: 6-19 % of wide starts where the near-rest rounds found none). A round's
    configs come in the order of :func:`_preference`."""
    state = world.state
    if state.held is None or state.grip is None:
        return
    variants = SYMMETRIES + tuple(t.multiply(s) for t in turns for s in SYMMETRIES[:2])
    for rng, ik in ((random.Random(f"{seeds[0]}:{a}"), PLACE_IK), (seeds[1], RETRY_IK)):
        live = variants  # variants IK reached in the last round: only those are retried
        for attempt in range(PUT_TRIES):
            found, reached = _put_round(world, a, target, live, rng, ik,
                                        _near_rest if attempt else None)
            if found:
                yield from found
                return
            live = reached
    for _ in range(wide):
        found, _ = _put_round(world, a, target, variants, seeds[1], PLACE_IK, _anywhere)
        if found:
            yield from found
            return


#: where an IK try starts: a config drawn from the RNG (None in ``_put_round``: at rest)
IkStart = Callable[[PyBulletWorld, random.Random], tuple[float, ...]]


def _put_round(world: PyBulletWorld, a: str, target: Pose, variants: tuple[Pose, ...],
               rng: random.Random, ik: IkSettings, start: IkStart | None
               ) -> tuple[list[tuple[Pose, Config]], tuple[Pose, ...]]:
    """One IK try per variant (from ``start(world, rng)``, else from rest): the clear
    configs found, best first, and the variants IK reached at all."""
    state = world.state
    robot, base = manipulation._owner(world)
    found: list[tuple[tuple[bool, bool, float], Pose, Config]] = []
    reached = []
    for sym in variants:
        p = target.multiply(sym)
        raised = Pose((p.pos[0], p.pos[1], p.pos[2] + PLACE_CLEARANCE), p.quat)
        hand = raised.multiply(state.grip.inverse())
        world.select(a)
        q, pre = _clear_put_config(world, hand, rng, ik, start(world, rng) if start else None)
        world.set_arm(state.q)
        if q is not None:
            reached.append(sym)
        if q is not None and pre is not None:
            c = Config.of(q, obj=state.held, pre=pre, robot=robot, base=base)
            found.append((_preference(world, p, c, sym in SYMMETRIES), p, c))
    return [(p, c) for _, p, c in sorted(found, key=lambda f: f[0])], tuple(reached)


def _preference(world: PyBulletWorld, p: Pose, c: Config, unturned: bool
                ) -> tuple[bool, bool, float]:
    """Sort key of a clear put config: first those from which the arm goes straight
    home (what ``put`` does next; otherwise it may stay in the way of the next pick:
    Keva 3π seed 0), then the role's own pose before a quarter-turned one (a plank put
    turned rests elsewhere, and branches filling the role would no longer merge: 3π
    refined 4x the nodes), then the least bent."""
    return (not _goes_home_straight(world, p, c), not unturned, _bend(world, c.q))


def _goes_home_straight(world: PyBulletWorld, p: Pose, c: Config) -> bool:
    """After letting the plank go at ``p`` from ``c``, the straight retreat and the
    straight joint path to the rest config touch nothing (checked at ``HOME_RESOLUTION``:
    an ordering heuristic; ``put`` itself checks at full resolution)."""
    assert world.model is not None
    before, k = world.snapshot(), world.state.held
    try:
        world.update(q=c.q, held=None, grip=None, retreat=c.pre, released=k,
                     poses=world.with_object_pose(k, p) if k is not None else world.state.poses)
        open_to_release(world)
        home = Traj((c.q, c.pre or c.q, tuple(world.model.rest)), released=k, retreat_end=1)
        return not counts(world, sweep(world, home, HOME_RESOLUTION, stop_on_hit=True), False)
    finally:
        world.restore(before)


def open_to_release(world: PyBulletWorld) -> None:
    """Set how far the fingers of the active arm, which has just let its plank go, open
    for the back-off: the widest of ``RELEASE_SLACKS`` whose straight retreat keeps the
    planning clearance from everything (the plank let go excepted); else the slack they
    held the plank with, along the reverse of the approach the put config was chosen
    for. A fixed 5 mm ran a finger into the level's other plank high in a 24-level
    tower (seed 9, never solved) or within 1 mm of it (seed 2): refused on every
    re-sample, since IK from rest is deterministic."""
    state = world.state
    retreat = Traj((state.q, state.retreat or state.q), released=state.released, retreat_end=1)
    for slack in RELEASE_SLACKS[:-1]:
        world.update(release_slack=slack)
        if not counts(world, sweep(world, retreat, stop_on_hit=True), False):
            return
    world.update(release_slack=RELEASE_SLACKS[-1])


def _bend(world: PyBulletWorld, q: tuple[float, ...]) -> float:
    """How far ``q`` is from the rest config (the largest joint difference, rad)."""
    assert world.model is not None
    return max(abs(v - r) for v, r in zip(q, world.model.rest))


def _anywhere(world: PyBulletWorld, rng: random.Random) -> tuple[float, ...]:
    """An IK start uniform in the joint ranges."""
    return tuple(rng.uniform(lo, hi) for lo, hi in zip(world.lower, world.upper))


def _near_rest(world: PyBulletWorld, rng: random.Random) -> tuple[float, ...]:
    """An IK start within ``NEAR_REST`` rad of the rest config in every joint."""
    assert world.model is not None
    return tuple(min(hi, max(lo, r + rng.uniform(-NEAR_REST, NEAR_REST)))
                 for r, lo, hi in zip(world.model.rest, world.lower, world.upper))


def _clear_put_config(world: PyBulletWorld, hand: Pose, rng: random.Random, ik: IkSettings,
                      seed_q: tuple[float, ...] | None
                      ) -> tuple[tuple[float, ...] | None, tuple[float, ...] | None]:
    """An IK config for ``hand`` (starting at ``seed_q``, else at rest; None: out of
    reach) and its pre-place config (None unless the arm touches no plank at the put
    and along the vertical approach). The planks a put-down can meet are the
    structure's, and no action moves them again: a config in one of them (the hand in
    the neighbouring plank of a tall tower's level, from level 18 of tower-24 up) could
    only be learned as a ``blocked`` trajectory, again on every re-sample, since IK from
    rest is deterministic."""
    q = solve_ik(world, hand, rng, seed_q=seed_q, settings=ik)
    if q is None:
        return None, None
    pre = _pre_place(world, hand, q, rng)
    return q, pre if pre is not None and _clear_of_planks(world, q) else None


def _clear_of_planks(world: PyBulletWorld, q: tuple[float, ...]) -> bool:
    """The arm at ``q`` keeps the planning clearance from every plank (the held one
    excepted), as the trajectory's final sweep will."""
    robot_hits, held_hits = world.hits(q, clearance=CLEARANCE)
    return not (robot_hits | held_hits) & (world.movable_ids - _held_id(world))


def _held_id(world: PyBulletWorld) -> frozenset[int]:
    held = world.state.held
    return frozenset({world.body[held]}) if held is not None else frozenset()


def _pre_place(world: PyBulletWorld, hand: Pose, q: tuple[float, ...],
               rng: random.Random) -> tuple[float, ...] | None:
    """A config ``PRE_PLACE`` (or less) above ``hand`` with a vertical approach free of
    static obstacles and of the planks (the held plank may touch the table)."""
    for height in PRE_PLACE:
        above = Pose((hand.pos[0], hand.pos[1], hand.pos[2] + height), hand.quat)
        pre = solve_ik(world, above, rng, seed_q=q, settings=PRE_IK)
        if (pre is not None and manipulation._approach_ok(world, pre, q, placing=True)
                and _approach_clear_of_planks(world, pre, q)):
            return pre
    return None


def _approach_clear_of_planks(world: PyBulletWorld, pre: tuple[float, ...],
                              q: tuple[float, ...]) -> bool:
    """The straight approach from ``pre`` to ``q`` touches no plank, swept at the
    resolution of the final trajectory check."""
    return all(_clear_of_planks(world, c) for c in interpolate(pre, q, CHECK_RESOLUTION))
