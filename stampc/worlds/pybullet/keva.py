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
- ``.keva:places(a, r)`` — evaluator: arm ``a`` can put a plank at role ``r``'s pose;
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
from stampc.worlds.pybullet.keva_puts import (SYMMETRIES, UPRIGHT_TURNS, open_to_release,
                                               put_configs)
from stampc.worlds.pybullet.kinematics import top_grasp
from stampc.worlds.pybullet.planning import PlanSettings, plan_trajectory
from stampc.worlds.pybullet.values import Config, Grasp, Pose, Traj, as_config, as_pose, as_traj
from stampc.worlds.pybullet.world import PyBulletWorld

GRASP_DEPTH = 0.008  # m the fingertips reach below the plank's top face
HOME_TRIES = 4  # planner seeds for an arm's way home after a put-down
AT_TOL = 0.01  # m: a body within this of a feed or role position is there
BUFFER = "buffer"  # the domain's hand-over spot (a feed both arms reach)
FEED_IK_RESTARTS = 20  # the domain's feed_grasp option (the reaches evaluator matches it)
REACH_ROUNDS = 3  # independent IK rounds before the reaches evaluator says "no" for good
PLACES = "keva.places"  # world.memo key of the places evaluator's verdicts
#: rounds of IK from starts anywhere before the places evaluator says "no" for good
#: (per grip, one try per variant each: 64 tries per grip. On tower-24 seed 2's borderline
#: roles 6-19 % of wide tries are clear: at 6 %, a wrong "no" has probability 4e-4)
PLACES_WIDE_ROUNDS = 16


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


def places(ctx: Context, a: str, r: str) -> bool:
    """Evaluator: whether arm ``a`` can put a plank at role ``r``'s target pose clear of
    the planks under it. A `? predicate`, so the answer must hold in every state, and a
    "no" is for good (the engine bans the arm's put-downs of ``r`` everywhere and plans
    hand-overs instead): at the top of a tall tower one arm may reach the pose only
    through the planks below (Keva tower-24 seed 2: the right arm touched a plank in
    every one of 96 IK configs of the top plank, from random starts). Decided once per
    run (``world.memo``) on a scene of its own: only the planks ``r`` rests on, down to
    the table, at their target poses (they are in place whenever ``r`` can be put; other
    planks only add obstacles), the rest out of the way, the plank held by either top
    grip; "no" only when the put-down generator's IK (keva_puts.put_configs), with
    ``PLACES_WIDE_ROUNDS`` rounds from starts anywhere in the joint ranges, finds no
    clear config for either grip. With 3 rounds from near rest only, the answers for
    three borderline roles of that tower flipped with the draw (1-3 of 6 draws said yes)."""
    world = manipulation._world(ctx, a)
    key = (PLACES, a, r)
    if key not in world.memo:
        world.memo[key] = _places(ctx, world, a, r)
    return bool(world.memo[key])


def _places(ctx: Context, world: PyBulletWorld, a: str, r: str) -> bool:
    role = _meta(world, "roles", r)
    under = _resting_on(world, r)
    in_hands = {arm.held for arm in world.state.arms}  # they stay where they are
    names = [n for n, _ in world.state.poses if n not in in_hands]
    if len(names) <= len(under):
        return False  # no plank left to hold: the structure cannot have r either
    held = names[len(under)]
    placed = {n: role_pose(world, under[i]) if i < len(under) else
              Pose((10.0 + 0.2 * i, 10.0, 0.0)) for i, n in enumerate(names)}
    poses = tuple((n, placed.get(n, pose)) for n, pose in world.state.poses)
    turns = UPRIGHT_TURNS if role["orientation"] == "vertical" else ()
    before = world.snapshot()
    try:
        for yaw in (0.0, math.pi):
            grip = top_grasp(world.geometry[held], yaw, depth=GRASP_DEPTH).hand.inverse()
            world.select(a)
            world.update(poses=poses, q=tuple(world.model.rest), held=held, grip=grip,
                         retreat=None, released=None)
            rounds = (f"keva-places:{r}:{yaw}", ctx.rng)
            if next(put_configs(world, a, role_pose(world, r), rounds, turns,
                                wide=PLACES_WIDE_ROUNDS), None):
                return True
        return False
    finally:
        world.restore(before)


def _resting_on(world: PyBulletWorld, r: str) -> list[str]:
    """The roles ``r`` rests on, directly or not (down to the table), lowest first."""
    out: list[str] = []
    todo = list(_meta(world, "roles", r)["supports"])
    while todo:
        s = todo.pop()
        if s not in out:
            out.append(s)
            todo.extend(_meta(world, "roles", s)["supports"])
    return sorted(out, key=lambda s: (_meta(world, "roles", s)["level"], s))


def aside_place(ctx: Context, a: str) -> Iterator[tuple[Pose, Config]]:
    """The buffer spot (lying flat, either way round) for the plank in arm ``a``."""
    world = manipulation._world(ctx, a)
    return put_configs(world, a, feed_pose(world, BUFFER), ("keva-aside", ctx.rng))


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
    ``a`` that puts the held plank there, letting go ``keva_puts.PLACE_CLEARANCE`` above it."""
    world = manipulation._world(ctx, a)
    role = _meta(world, "roles", r)
    if role["orientation"] != o or sorted(role["supports"]) != sorted(supports):
        return  # the structure puts r elsewhere: no pose in this relation
    if any(body_at(world, role_pose(world, s)) is None for s in supports):
        return  # a support is not where the structure has it
    turns = UPRIGHT_TURNS if o == "vertical" else ()
    for found in put_configs(world, a, role_pose(world, r), (f"keva-place:{r}", ctx.rng), turns):
        # a clear put here is one with only r's supports in place too: ``places`` says yes
        world.memo[(PLACES, a, r)] = True
        yield found


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
    (≤ 4 mm, 0.02 rad, ``keva_puts.PLACE_IK``) is not simulated."""
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
    open_to_release(world)
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
