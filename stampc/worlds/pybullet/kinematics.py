"""Inverse kinematics and grasp geometry.

PyBullet's damped-least-squares IK rarely lands within 5 mm / 0.05 rad in one call; with
joint limits, the rest pose as null-space target, repeated calls from its own answer and
a few random restarts it succeeds in ~94 % of reachable top grasps (measured).
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass

from stampc.worlds.pybullet._pb import p
from stampc.worlds.pybullet.values import (Grasp, Pose, quat_from_axes, quat_from_axis_angle,
                                           quat_multiply)
from stampc.worlds.pybullet.world import Geometry, PyBulletWorld

POS_TOL = 0.005  # m
ANG_TOL = 0.05  # rad
STANDOFF = 0.10  # pre-grasp distance along the approach (m)
FINGER_SPAN = 0.075  # widest object the open Panda fingers close around (m)


@dataclass(frozen=True)
class IkSettings:
    restarts: int = 5
    refinements: int = 5
    iterations: int = 100
    pos_tol: float = POS_TOL
    ang_tol: float = ANG_TOL


def _null_space(world: PyBulletWorld) -> tuple[list[float], list[float], list[float], list[float]]:
    """Limits, ranges and rest pose over *all* movable joints (IK wants every DOF)."""
    assert world.model is not None
    lo, hi, rest = [], [], []
    arm = dict(zip(world.model.arm_joints, world.model.rest))
    for j in world.ik_joints:
        info = p.getJointInfo(world.robot, j, physicsClientId=world.client)
        lo.append(info[8])
        hi.append(info[9])
        rest.append(arm.get(j, world.model.finger_open))
    return lo, hi, [h - l for l, h in zip(lo, hi)], rest


def pose_error(world: PyBulletWorld, target: Pose) -> tuple[float, float]:
    ee = world.ee_pose()
    return ee.distance(target), ee.angle(target)


#: at most this many IK answers that drew restarts are kept per world (~0.3 KB each)
DRAWN_MEMO_LIMIT = 50_000


def solve_ik(world: PyBulletWorld, target: Pose, rng: random.Random,
             seed_q: tuple[float, ...] | None = None,
             settings: IkSettings = IkSettings()) -> tuple[float, ...] | None:
    """An arm configuration putting the end effector at ``target`` (within tolerance).

    Leaves the arm at the returned configuration (or wherever the last try ended).

    IK is a function of the arm's state and, for its restarts, of ``rng``'s state, so
    answers are kept in ``world.memo`` and given again, with the same effects: the arm
    where the last try left it, and ``rng`` advanced by the draws the restarts made. A
    first try that succeeds draws nothing and holds for any ``rng`` state; the others
    are kept under ``rng``'s state too (generators seeded per query repeat it). A Keva
    3π run asked 1,538 IK queries, 887 of them again after a first-try success, and
    its 121 unreachable put variants cost 45 solver calls each (67 % of the calls).
    """
    assert world.model is not None
    key = _ik_key(world, target, seed_q, settings)
    first = world.memo.get(key)
    if first is not None:
        world.set_arm(first)  # type: ignore[arg-type]
        return first  # type: ignore[return-value]
    drawn: dict = world.memo.setdefault(("ik-drawn",), {})  # type: ignore[assignment]
    drawn_key = (key, hash(rng.getstate()))  # 64 bits: a collision needs ~2^32 entries
    known = drawn.get(drawn_key)
    if known is None:
        known = _solve_ik(world, target, rng, seed_q, settings)
        if known[0] is not None and known[1] == 0:
            world.memo[key] = known[0]
        elif len(drawn) < DRAWN_MEMO_LIMIT:
            drawn[drawn_key] = known
        return known[0]
    q, draws, last = known
    for _ in range(draws):  # uniform() draws one random() each
        rng.random()
    world.set_arm(last)
    return q


def _ik_key(world: PyBulletWorld, target: Pose, seed_q: tuple[float, ...] | None,
            settings: IkSettings) -> tuple:
    """Everything IK depends on besides ``rng``: the robot and where it stands, the
    target, the start, and the joints IK moves that the start does not set (fingers)."""
    cid = world.client
    base = p.getBasePositionAndOrientation(world.robot, physicsClientId=cid)
    fingers = tuple(p.getJointState(world.robot, j, physicsClientId=cid)[0]
                    for j in world.model.finger_joints)  # type: ignore[union-attr]
    return ("ik", world.robot, base, target, seed_q, settings, fingers)


def _solve_ik(world: PyBulletWorld, target: Pose, rng: random.Random,
              seed_q: tuple[float, ...] | None, settings: IkSettings
              ) -> tuple[tuple[float, ...] | None, int, tuple[float, ...]]:
    """:func:`solve_ik` without the memo: (the configuration or None, how many numbers
    the restarts drew from ``rng``, the configuration the arm was left at)."""
    assert world.model is not None
    lo, hi, ranges, rest = _null_space(world)
    arm_idx = [world.ik_joints.index(j) for j in world.model.arm_joints]
    q: tuple[float, ...] = ()
    for attempt in range(settings.restarts + 1):
        if attempt == 0:
            start = seed_q if seed_q is not None else world.model.rest
        else:
            start = tuple(rng.uniform(a, b) for a, b in zip(world.lower, world.upper))
        world.set_arm(start)
        q = tuple(start)
        for _ in range(settings.refinements):
            sol = p.calculateInverseKinematics(
                world.robot, world.model.ee_link, target.pos, target.quat,
                lowerLimits=lo, upperLimits=hi, jointRanges=ranges, restPoses=rest,
                maxNumIterations=settings.iterations, residualThreshold=1e-5,
                physicsClientId=world.client)
            q = tuple(min(max(sol[i], a), b)
                      for i, a, b in zip(arm_idx, world.lower, world.upper))
            world.set_arm(q)
            dist, ang = pose_error(world, target)
            if dist <= settings.pos_tol and ang <= settings.ang_tol:
                return q, attempt * len(world.lower), q
    return None, settings.restarts * len(world.lower), q


# ------------------------------------------------------------------ grasp geometry
_DOWN = quat_from_axis_angle((1.0, 0.0, 0.0), math.pi)  # hand z pointing down


def top_grasp(geom: Geometry, yaw: float, depth: float = 0.03) -> Grasp:
    """Hand above the object's top face, fingers ``depth`` below the top, rotated by yaw."""
    z = geom.height / 2.0 - min(depth, geom.height / 2.0)
    quat = quat_multiply(quat_from_axis_angle((0.0, 0.0, 1.0), yaw), _DOWN)
    return Grasp(Pose((0.0, 0.0, z), quat), (0.0, 0.0, -1.0), "top", STANDOFF)


def side_grasp(geom: Geometry, angle: float, clearance: float = 0.05) -> Grasp:
    """Hand approaching horizontally towards the axis from direction ``angle``."""
    z = max(0.0, -geom.height / 2.0 + clearance)  # keep the hand above the support
    approach = (-math.cos(angle), -math.sin(angle), 0.0)  # from outside towards the centre
    closing = (-math.sin(angle), math.cos(angle), 0.0)
    x_axis = (closing[1] * approach[2] - closing[2] * approach[1],
              closing[2] * approach[0] - closing[0] * approach[2],
              closing[0] * approach[1] - closing[1] * approach[0])
    quat = quat_from_axes(x_axis, closing, approach)
    return Grasp(Pose((0.0, 0.0, z), quat), approach, "side", STANDOFF)


def fits(geom: Geometry, angle: float) -> bool:
    """Whether the open fingers span the object when they close along
    ``(sin angle, cos angle)`` in the object's horizontal plane (up to sign)."""
    if geom.kind == "cylinder":
        return 2 * geom.dims[0] <= FINGER_SPAN
    width = abs(math.sin(angle)) * geom.dims[0] + abs(math.cos(angle)) * geom.dims[1]
    return width <= FINGER_SPAN


def grasp_candidates(geom: Geometry, rng: random.Random, kinds: str = "any") -> list[Grasp]:
    """Top grasps at several yaws first (they clear neighbours best), then side grasps."""
    step = math.pi / 4 if geom.kind == "cylinder" else math.pi / 2
    angles = [k * step for k in range(round(2 * math.pi / step))]
    out: list[Grasp] = []
    if kinds in ("any", "top"):
        yaws = [a for a in angles if fits(geom, a)]
        rng.shuffle(yaws)
        out += [top_grasp(geom, y) for y in yaws]
    if kinds in ("any", "side"):
        sides = [a for a in angles if fits(geom, a)]
        rng.shuffle(sides)
        out += [side_grasp(geom, a) for a in sides]
    return out


TOP_YAWS = tuple(k * math.pi / 4 for k in range(4))  # 4 distinct closing directions
SIDE_ANGLES = tuple(k * math.pi / 4 for k in range(8))  # 8 approach directions


def grasps_of_kind(geom: Geometry, kinds: str) -> list[Grasp]:
    """A robot's grasp set by kind (its scene entry's ``grasps``): ``top``: from above at
    4 yaws; ``side``: horizontal approaches from 8 directions; ``any``: both, top first."""
    out: list[Grasp] = []
    if kinds in ("top", "any"):
        out += [top_grasp(geom, yaw) for yaw in TOP_YAWS]
    if kinds in ("side", "any"):
        out += [side_grasp(geom, a) for a in SIDE_ANGLES if fits(geom, a)]
    return out


def arm_meets(world: PyBulletWorld, o: str, pose: Pose, clearance: float) -> bool:
    """Whether the selected arm's links, hand and fingers excluded, come within
    ``clearance`` of object ``o`` were it at ``pose``, at the current config. The held
    object never collides with its robot in the planning world (it would touch the
    fingers), so nothing else notices an arm folded into it: a cluttered-20 place
    config had panda_link5 (the forearm) 5.5 mm into the can's rest pose, and on
    release physics pushed the can 5.6 mm aside and tilted it 3°, into the next
    trajectory."""
    assert world.model is not None
    body, cid = world.body[o], world.client
    before = p.getBasePositionAndOrientation(body, physicsClientId=cid)
    p.resetBasePositionAndOrientation(body, pose.pos, pose.quat, physicsClientId=cid)
    try:
        return any(p.getClosestPoints(world.robot, body, clearance, linkIndexA=link,
                                      physicsClientId=cid)
                   for link in range(-1, max(world.model.arm_joints) + 1))
    finally:
        p.resetBasePositionAndOrientation(body, *before, physicsClientId=cid)
