"""Bound functions of the keva domain on the PyBullet world (two arms, ``left``/``right``).

The scene's ``meta`` carries the target structure (``roles``: role name -> target pose,
orientation, supports) and the feed locations (``feeds``), see ``examples/keva/scene.py``.
Planks are identical bodies ``k0, k1, ...`` that the person brings from the supply in
that order; a put-down gives the body in the hand a *role* of the structure.

- ``.keva:feed_grasp(a, f)`` — top grasps of the plank waiting at feed ``f`` (closing
  across its width) for arm ``a``, in a fixed order;
- ``.keva:table_place(a, r, o)``, ``.keva:plank_place(a, r, o, j)``,
  ``.keva:span_place(a, r, o, j, j2)`` — the put-down pose generator: the role's target
  pose from the structure (or one of its symmetric equivalents: a plank is a box) when
  the put-down (support, orientation) is the one the structure gives role ``r`` and its
  supports are in place, and an accurate IK config of arm ``a`` putting the held plank
  there. Computed deterministically from the role, arm and grip (same inputs → same
  config), so policy branches that fill the same role share their concrete state;
- ``.keva:motion(a, q)`` — the stdlib motion generator for arm ``a``;
- ``.keva:blocked(t)`` — evaluator: trajectory ``t`` hits a plank;
- ``.keva:reaches(a, f)`` — evaluator: arm ``a`` has a top grasp of a plank at feed ``f``;
- ``.keva:bring`` — the next supply plank arrives at the outcome's feed;
- ``.keva:pick`` — hold the plank at its grasp's nominal grip;
- ``.keva:put`` — let go: the plank is set at its role's pose (the IK error of the hand,
  ≤ 4 mm / 0.02 rad, is not simulated); then the arm backs off and returns to its rest
  config along a planned collision-free path (out of the other arm's way).
"""

from __future__ import annotations

import dataclasses
import math
import random
from typing import Any, Iterator, Mapping

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.pybullet import manipulation
from stampc.worlds.pybullet.kinematics import IkSettings, solve_ik, top_grasp
from stampc.worlds.pybullet.planning import (CHECK_RESOLUTION, PlanSettings, counts,
                                             interpolate, plan_trajectory, sweep)
from stampc.worlds.pybullet.values import (Config, Grasp, Pose, Traj, as_config, as_pose,
                                           as_traj, quat_from_axis_angle)
from stampc.worlds.pybullet.world import PyBulletWorld

GRASP_DEPTH = 0.008  # m the fingertips reach below the plank's top face
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
HOME_RESOLUTION = 0.05  # rad: the way-home check that orders put configs
HOME_TRIES = 4  # planner seeds for an arm's way home after a put-down
AT_TOL = 0.01  # m: a body within this of a feed or role position is there
BUFFER = "buffer"  # the domain's hand-over spot (a feed both arms reach)
FEED_IK_RESTARTS = 20  # the domain's feed_grasp option (the reaches evaluator matches it)
REACH_ROUNDS = 3  # independent IK rounds before the reaches evaluator says "no" for good
#: rotations mapping a box onto itself (identity, half turns about its axes)
SYMMETRIES = (Pose((0.0, 0.0, 0.0)),
              Pose((0.0, 0.0, 0.0), quat_from_axis_angle((0.0, 0.0, 1.0), math.pi)),
              Pose((0.0, 0.0, 0.0), quat_from_axis_angle((1.0, 0.0, 0.0), math.pi)),
              Pose((0.0, 0.0, 0.0), quat_from_axis_angle((0.0, 1.0, 0.0), math.pi)))
#: an upright plank may also stand turned a quarter about its long (local x) axis: its
#: support relation is the same and the hand can reach it from another side
UPRIGHT_TURNS = tuple(Pose((0.0, 0.0, 0.0), quat_from_axis_angle((1.0, 0.0, 0.0), a))
                      for a in (math.pi / 2, -math.pi / 2))


def _meta(world: PyBulletWorld, section: str, name: str) -> Any:
    table: Mapping[str, Any] = world.spec.meta.get(section, {})
    if name not in table:
        raise StampcError([error("PB050", f"scene meta has no {section[:-1]} {name!r}",
                                 Span.point("<scene meta>"),
                                 f"build the scene with examples/keva/scene.py; known: "
                                 f"{', '.join(sorted(table)) or 'none'}")])
    return table[name]


def role_pose(world: PyBulletWorld, r: str) -> Pose:
    return as_pose(_meta(world, "roles", r)["pose"])


def feed_pose(world: PyBulletWorld, f: str) -> Pose:
    return as_pose(_meta(world, "feeds", f))


def body_at(world: PyBulletWorld, target: Pose) -> str | None:
    """The plank body whose position is within ``AT_TOL`` of ``target``'s."""
    for name, pose in world.state.poses:
        if math.dist(pose.pos, target.pos) <= AT_TOL:
            return name
    return None


# ------------------------------------------------------------------ generators
def feed_grasp(ctx: Context, a: str, f: str) -> Iterator[tuple[Grasp, Config]]:
    """Top grasps by arm ``a`` of the plank waiting at feed ``f``, yaw 0 then π."""
    world = manipulation._world(ctx, a)
    k = body_at(world, feed_pose(world, f))
    if k is None:
        return
    p = world.object_pose(k)
    for yaw in (0.0, math.pi):
        world.select(a)
        g = top_grasp(world.geometry[k], yaw, depth=GRASP_DEPTH)
        config = manipulation._grasp_config(world, ctx, k, p, g)
        world.set_arm(world.state.q)
        if config is not None:
            yield g, config


def reaches(ctx: Context, a: str, f: str) -> bool:
    """Evaluator: whether arm ``a`` has a top grasp of a plank at feed ``f``'s nominal
    pose. A `? predicate`, so the answer must be the same in every state, and a "no" is
    for good (the engine bans the arm's picks there everywhere):
    - the buffer is the hand-over spot the scene places for both arms: yes. IK reaches
      it in only 9-10 of 12 random draws, so a "no" there would be a bad draw; whether a
      plank as it was put aside can be grasped is the generator's per-state business;
    - a feed: decided on the plank waiting there (else the next supply plank set there),
      "no" only when ``REACH_ROUNDS`` independent IK rounds (the restarts of the domain's
      ``feed_grasp``) all fail (measured: 12 of 12 draws or 0 of 12 per arm and feed).
    The world is left as it was."""
    if f == BUFFER:
        return True
    world = manipulation._world(ctx, a)
    before = world.snapshot()
    try:
        k = body_at(world, feed_pose(world, f)) or _next_supply_plank(world)
        if k is None:
            return False  # nothing there and nothing left to bring: nothing to reach
        world.update(poses=world.with_object_pose(k, feed_pose(world, f)))
        seeds = [ctx.rng.random() for _ in range(REACH_ROUNDS)]
        for i, seed in enumerate(seeds):
            # the first round shares the node's cache (a grasp the generator found there
            # is a yes); later ones start afresh (a cached miss would repeat itself)
            sure = dataclasses.replace(ctx, rng=random.Random(seed), cache=ctx.cache if i == 0
                                       else {}, options={**ctx.options,
                                                         "ik_restarts": FEED_IK_RESTARTS})
            if next(feed_grasp(sure, a, f), None) is not None:
                return True
        return False
    finally:
        world.restore(before)


def aside_place(ctx: Context, a: str) -> Iterator[tuple[Pose, Config]]:
    """The buffer spot (lying flat, either way round) for the plank in arm ``a``."""
    world = manipulation._world(ctx, a)
    return _put_at(world, a, feed_pose(world, BUFFER), ("keva-aside", ctx.rng))


def table_place(ctx: Context, a: str, r: str, o: str) -> Iterator[tuple[Pose, Config]]:
    return _put(ctx, a, r, o, ())


def plank_place(ctx: Context, a: str, r: str, o: str, j: str) -> Iterator[tuple[Pose, Config]]:
    return _put(ctx, a, r, o, (j,))


def span_place(ctx: Context, a: str, r: str, o: str, j: str,
               j2: str) -> Iterator[tuple[Pose, Config]]:
    return _put(ctx, a, r, o, (j, j2))


def _put(ctx: Context, a: str, r: str, o: str,
         supports: tuple[str, ...]) -> Iterator[tuple[Pose, Config]]:
    """The target pose of role ``r`` (up to the plank's symmetry) and the config of arm
    ``a`` that puts the held plank there, letting go ``PLACE_CLEARANCE`` above it."""
    world = manipulation._world(ctx, a)
    role = _meta(world, "roles", r)
    if role["orientation"] != o or sorted(role["supports"]) != sorted(supports):
        return  # the structure puts r elsewhere: no pose in this relation
    if any(body_at(world, role_pose(world, s)) is None for s in supports):
        return  # a support is not where the structure has it
    turns = UPRIGHT_TURNS if o == "vertical" else ()
    yield from _put_at(world, a, role_pose(world, r), (f"keva-place:{r}", ctx.rng), turns)


def _put_at(world: PyBulletWorld, a: str, target: Pose, seeds: tuple[str, random.Random],
            turns: tuple[Pose, ...] = ()) -> Iterator[tuple[Pose, Config]]:
    """Configs of arm ``a`` putting its plank at ``target`` up to the box's symmetry
    (and the extra ``turns``), each touching no plank at the put or along its vertical
    approach. IK first draws from an RNG seeded by ``seeds[0]`` and the arm — same
    inputs, same config (see the module docstring); only if that finds nothing, from
    the call's own RNG ``seeds[1]`` with more restarts (a retry of the engine then draws
    fresh samples). Each RNG first tries IK from the rest config for every variant, and
    only if none is clear, from configs near rest (``PUT_TRIES`` rounds, only for the
    variants IK reached); a round's configs come in the order of :func:`_preference`."""
    state = world.state
    if state.held is None or state.grip is None:
        return
    variants = SYMMETRIES + tuple(t.multiply(s) for t in turns for s in SYMMETRIES[:2])
    robot, base = manipulation._owner(world)
    for rng, ik in ((random.Random(f"{seeds[0]}:{a}"), PLACE_IK), (seeds[1], RETRY_IK)):
        live = variants  # variants IK reached in the last round: only those are retried
        for attempt in range(PUT_TRIES):
            found: list[tuple[tuple[bool, bool, float], Pose, Config]] = []
            reached = []
            for sym in live:
                p = target.multiply(sym)
                raised = Pose((p.pos[0], p.pos[1], p.pos[2] + PLACE_CLEARANCE), p.quat)
                hand = raised.multiply(state.grip.inverse())
                world.select(a)
                seed_q = _near_rest(world, rng) if attempt else None
                q, pre = _clear_put_config(world, hand, rng, ik, seed_q)
                world.set_arm(state.q)
                if q is not None:
                    reached.append(sym)
                if q is not None and pre is not None:
                    c = Config.of(q, obj=state.held, pre=pre, robot=robot, base=base)
                    found.append((_preference(world, p, c, sym in SYMMETRIES), p, c))
            if found:
                yield from ((p, c) for _, p, c in sorted(found, key=lambda f: f[0]))
                return
            live = tuple(reached)


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
        home = Traj((c.q, c.pre or c.q, tuple(world.model.rest)), released=k, retreat_end=1)
        return not counts(world, sweep(world, home, HOME_RESOLUTION, stop_on_hit=True), False)
    finally:
        world.restore(before)


def _bend(world: PyBulletWorld, q: tuple[float, ...]) -> float:
    """How far ``q`` is from the rest config (the largest joint difference, rad)."""
    assert world.model is not None
    return max(abs(v - r) for v, r in zip(q, world.model.rest))


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
    """The arm at ``q`` touches no plank (the held one excepted)."""
    robot_hits, held_hits = world.hits(q)
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


def motion(ctx: Context, a: str, q: Config) -> Iterator[tuple[Traj]]:
    """Trajectories of arm ``a`` to ``q`` (``q`` must be one of ``a``'s configs): the
    stdlib's, without fallback paths that hit no plank (they hit the other arm, which
    the ``blocked`` evaluator could not report)."""
    q = as_config(q)
    if q.robot is not None and q.robot != a:
        return
    for (t,) in manipulation.motion(ctx, q):
        if not t.static_only or blocked(ctx, t):
            yield (t,)


def blocked(ctx: Context, t: Traj) -> bool:
    """Whether trajectory ``t`` (its arm and held plank) hits a plank or the other arm,
    where they are in the state it is checked in."""
    t = as_traj(t)
    return bool(manipulation.blocking_objects(ctx, t) or manipulation.robots_hit(ctx, t))


# ------------------------------------------------------------------ executors
def bring(ctx: Context, action: ConcreteAction) -> None:
    """The person puts the next supply plank (lowest index) at the outcome's feed."""
    world = manipulation._world(ctx)
    feeds = [str(args[0]) for name, args in action.adds if name == "waiting"]
    for f in feeds:
        k = _next_supply_plank(world)
        if k is None:
            raise StampcError([error("PB051", "the supply has no plank left to bring",
                                     Span.point("<scene meta>"),
                                     "give the scene one plank per role")])
        world.update(poses=world.with_object_pose(k, feed_pose(world, f)))


def _next_supply_plank(world: PyBulletWorld) -> str | None:
    """The plank the person brings next: the first still where the supply started it."""
    supply = _meta_supply(world)
    return next((n for n, pose in world.state.poses if n in supply
                 and math.dist(pose.pos, supply[n]) <= AT_TOL), None)


def _meta_supply(world: PyBulletWorld) -> dict[str, tuple[float, ...]]:
    """Where each plank body starts (on the supply table)."""
    return {o.name: tuple(o.position) for o in world.spec.objects}


def pick(ctx: Context, action: ConcreteAction) -> None:
    """Move arm ``a`` to the grasp config; hold the plank at the grasp's nominal grip."""
    q = as_config(manipulation._arg(action, "q"))
    a = str(manipulation._arg(action, "a"))
    world = manipulation._world(ctx, a)
    g = manipulation._arg(action, "g")
    k = q.obj
    if k is None:
        raise StampcError([error("PB052", "the grasp config names no plank",
                                 Span.point("<world>"), "use .keva:feed_grasp")])
    manipulation._check_object(world, k)
    world.update(q=q.q, retreat=None, released=None)
    hand = g.hand if isinstance(g, Grasp) else as_pose(g["hand"])  # type: ignore[index]
    world.update(held=k, grip=hand.inverse(), retreat=q.pre)


def put(ctx: Context, action: ConcreteAction) -> None:
    """Let go of the held plank at config ``q``: it is set at ``p`` — at the role's (or
    buffer's) canonical pose when ``p`` is one of its box-symmetric equivalents, so every
    branch that fills a role reaches the same concrete state; the IK error of the hand
    (≤ 4 mm, 0.02 rad, ``PLACE_IK``) is not simulated."""
    q = as_config(manipulation._arg(action, "q"))
    p = as_pose(manipulation._arg(action, "p"))
    a = str(manipulation._arg(action, "a"))
    world = manipulation._world(ctx, a)
    world.update(q=q.q, retreat=None, released=None)
    k = world.state.held
    if k is None:
        world.update(retreat=q.pre)
        return
    r = action.args.get("r")
    target = role_pose(world, str(r)) if r is not None else feed_pose(world, BUFFER)
    settled = target if any(target.multiply(s).distance(p) < 1e-6
                            and target.multiply(s).angle(p) < 1e-6 for s in SYMMETRIES) else p
    world.update(held=None, grip=None, retreat=q.pre, released=k,
                 poses=world.with_object_pose(k, settled))
    _go_home(ctx, world, a)


def _go_home(ctx: Context, world: PyBulletWorld, a: str) -> None:
    """Back off and return arm ``a`` to its rest config, out of the other arm's way:
    straight in joint space when that is collision-free (deterministic, so branches
    still merge), else along an OMPL path (``HOME_TRIES`` planner seeds); if none is
    found it stays where it let go. The seeds come from the state, not the caller, and
    there is no run deadline: the arm must end where refinement saw it end when
    ``stampc execute`` replays the step (with the caller's stream, execution once left
    an arm in the other's path). One seed was not enough: Keva 3π seed 7's left arm
    stayed amid the structure after 1 of 8 seeds failed there, in the right arm's way
    to feed 2 in every later state."""
    assert world.model is not None
    robot, base = manipulation._owner(world)
    state = world.state
    home = tuple(world.model.rest)
    start = state.retreat or state.q
    straight = Traj((state.q, start, home), released=state.released, retreat_end=1,
                    robot=robot, base=base)
    goal = Config.of(home, pre=home, robot=robot, base=base)
    if manipulation.trajectory_free(ctx, straight) or _plans_home(world, a, goal):
        world.select(a)
        world.update(q=home, retreat=None, released=None)


def _plans_home(world: PyBulletWorld, a: str, goal: Config) -> bool:
    """Whether the planner finds a collision-free way home for arm ``a`` with one of
    ``HOME_TRIES`` seeds drawn from the state."""
    q = world.state.q
    for i in range(HOME_TRIES):
        rng = random.Random(f"home:{a}:{q}" + (f":{i}" if i else ""))
        world.select(a)
        traj = plan_trajectory(world, goal, rng, PlanSettings(straight=False))
        world.set_arm(q)
        if traj is not None:
            return True
    return False
