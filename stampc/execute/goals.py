"""Concrete goal checks: does the world's concrete state at a goal leaf show the goal?

A goal check is ``check(world, leaf) -> list[str]``: the reasons the concrete goal does
not hold (empty when it does); ``leaf`` is the policy's goal node (its abstract ``state``
and ``goal_facts``). A scene binds its own with ``meta.goal_check =
"package.module:function"`` (found like a scene builder: importable, or a file beside the
problem); otherwise the world's default applies:

* plane2d — every goal fact the world can decide (``holding``, ``handempty``,
  ``on``/``in`` a surface) holds;
* PyBullet —
  ``holding(o)``: ``o`` is in the gripper and rises with it when the arm backs off
  (lifted at least :data:`LIFT` m, off every surface);
  ``filled(s)`` with ``meta.slots``: a plank lies within :data:`SLOT_POS_TOL` m and
  :data:`SLOT_ANGLE_TOL` rad of the slot's pose (up to the box's symmetry);
  with ``meta.roles`` (Keva): every role a goal fact names has a plank within the same
  tolerances of the role's pose (an upright role also turned a quarter about the
  plank's long axis, as the Keva put-down may stand it);
  every object lying tilted more than 45° from how it stood (a toppled domino) has
  ``notified(o)`` in the leaf state, when the domain has a ``notified`` predicate;
  a ``notified`` goal (aircraft): exactly one part was found faulty, one of
  ``meta.suspects``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable, Mapping

from stampc.diagnostics import Span, StampcError, error

GoalCheck = Callable[[Any, Mapping[str, Any]], list[str]]
LIFT = 0.02            # m the held object must rise when the arm backs off
SLOT_POS_TOL = 0.01    # m
SLOT_ANGLE_TOL = 0.05  # rad
TOPPLED_TILT = math.pi / 4


def goal_check_for(world: Any, scene: Mapping[str, Any], base_dir: Path) -> GoalCheck:
    meta = scene.get("meta") if isinstance(scene.get("meta"), Mapping) else {}
    bound = meta.get("goal_check")
    if isinstance(bound, str):
        return _bound(bound, base_dir)
    from stampc.worlds.plane2d.world import Plane2DWorld

    if isinstance(world, Plane2DWorld):
        return plane2d_goal
    return pybullet_goal


def _bound(target: str, base_dir: Path) -> GoalCheck:
    from stampc.worlds.modules import import_bound_module

    module_name, _, func = target.partition(":")
    where = Span.point("<scene meta.goal_check>")
    try:
        module = import_bound_module(module_name, base_dir) if module_name else None
    except Exception as exc:  # user code failing at import is reported, not raised
        raise StampcError([error("X001", f"goal check module {module_name!r} failed to load: "
                                 f"{type(exc).__name__}: {exc}", where)]) from None
    fn = getattr(module, func, None) if module is not None else None
    if not callable(fn):
        raise StampcError([error("X001", f"cannot find goal check {target!r}", where,
                                 hint='write "package.module:function" taking (world, leaf)')])
    return fn


def _facts(leaf: Mapping[str, Any]) -> list[tuple[str, tuple[str, ...]]]:
    return [(f["predicate"], tuple(f["args"])) for f in leaf.get("goal_facts", ())]


# ------------------------------------------------------------------ plane2d
def plane2d_goal(world: Any, leaf: Mapping[str, Any]) -> list[str]:
    return [f"{pred}({', '.join(args)}) does not hold concretely"
            for pred, args in _facts(leaf) if world.check_fact(pred, args) is False]


# ------------------------------------------------------------------ PyBullet
def pybullet_goal(world: Any, leaf: Mapping[str, Any]) -> list[str]:
    from stampc.worlds.pybullet.values import as_pose

    reasons: list[str] = []
    state = set(leaf.get("state", ()))
    for pred, args in _facts(leaf):
        if pred == "holding" and len(args) == 1:
            reasons += _held_and_lifted(world, args[0])
        elif pred == "filled" and len(args) == 1 and "slots" in world.spec.meta:
            reasons += _pose_filled(world, f"slot {args[0]}",
                                    (as_pose(world.spec.meta["slots"][args[0]]),))
    reasons += _roles_filled(world, leaf)
    if any(f.startswith("notified(") for f in state) or "toppled" in str(leaf.get("state")):
        reasons += _toppled_notified(world, state)
    if "notified" in {pred for pred, _ in _facts(leaf)}:
        reasons += _fault_alerted(world, state)
    return reasons


def _fault_alerted(world: Any, state: set[str]) -> list[str]:
    """Aircraft: the alert is about one part found faulty, a suspect of the scene. (The
    scene's ``meta.fault`` is not compared: the truth model samples detections with the
    model's probabilities, which average over where the fault is.)"""
    found = sorted(f[len("fault_found("):-1] for f in state if f.startswith("fault_found("))
    suspects = world.spec.meta.get("suspects")
    if len(found) != 1:
        return [f"the alert is about {len(found)} parts found faulty, not one"]
    if isinstance(suspects, list) and found[0] not in suspects:
        return [f"the alert names {found[0]}, which is not a suspect ({', '.join(suspects)})"]
    return []


def _held_and_lifted(world: Any, name: str) -> list[str]:
    state = world.state
    if state.held != name:
        return [f"{name} is not in the gripper (holding {state.held or 'nothing'})"]
    before = _body_pose(world, name)
    try:
        if state.retreat is not None:
            world.set_arm(state.retreat)
        after = _body_pose(world, name)
        robot, held = world.hits(state.retreat or state.q)
        on_surface = bool(held & world.static_ids)
    finally:
        world.set_arm(state.q)
    rise = after[2] - before[2]
    if state.retreat is not None and rise < LIFT:
        return [f"{name} rose only {rise * 1000:.1f} mm when the arm backed off"]
    if on_surface:
        return [f"{name} still touches a surface after the lift"]
    return []


def _body_pose(world: Any, name: str) -> tuple[float, ...]:
    from stampc.worlds.pybullet._pb import p

    pos, _ = p.getBasePositionAndOrientation(world.body[name], physicsClientId=world.client)
    return tuple(pos)


def _roles_filled(world: Any, leaf: Mapping[str, Any]) -> list[str]:
    """Keva: each role named first by a goal fact (``on_table(r)``, ``on(r, j)``,
    ``oriented(r, o)``) holds a plank at the structure's pose for it."""
    from stampc.worlds.pybullet.keva import UPRIGHT_TURNS
    from stampc.worlds.pybullet.values import as_pose

    roles = world.spec.meta.get("roles")
    if not isinstance(roles, Mapping):
        return []
    reasons = []
    for r in dict.fromkeys(args[0] for _, args in _facts(leaf) if args and args[0] in roles):
        target = as_pose(roles[r]["pose"])
        turns = UPRIGHT_TURNS if roles[r].get("orientation") == "vertical" else ()
        reasons += _pose_filled(world, f"role {r}",
                                (target,) + tuple(target.multiply(t) for t in turns))
    return reasons


def _pose_filled(world: Any, what: str, targets: tuple[Any, ...]) -> list[str]:
    """A plank lies at one of ``targets`` (up to the box's symmetry), within tolerance."""
    from stampc.worlds.pybullet.values import Pose

    best = (math.inf, math.inf, "")
    for name, pose in world.state.poses:
        if name in world.state.removed or name == world.state.held:
            continue
        pose = Pose.of(*_actual(world, name))  # where the body is, not where it was put
        d = pose.distance(targets[0])
        angle = min(min(_box_angle(pose.quat, t.quat) for t in targets), math.pi)
        if (d, angle) < best[:2]:
            best = (d, angle, name)
    d, angle, name = best
    if d > SLOT_POS_TOL or angle > SLOT_ANGLE_TOL:
        return [f"{what}: nearest plank {name or '-'} is {d * 1000:.1f} mm and "
                f"{math.degrees(angle):.1f}° off (tolerance {SLOT_POS_TOL * 1000:.0f} mm, "
                f"{math.degrees(SLOT_ANGLE_TOL):.1f}°)"]
    return []


def _actual(world: Any, name: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
    from stampc.worlds.pybullet._pb import p

    pos, quat = p.getBasePositionAndOrientation(world.body[name], physicsClientId=world.client)
    return tuple(pos), tuple(quat)


def _box_angle(a, b) -> float:
    """Rotation angle between two box orientations, up to the box's half-turn symmetries."""
    from stampc.worlds.pybullet.values import quat_angle, quat_multiply

    flips = ((0, 0, 0, 1), (0, 0, 1, 0), (1, 0, 0, 0), (0, 1, 0, 0))
    return min(quat_angle(quat_multiply(a, f), b) for f in flips)


def _toppled_notified(world: Any, state: set[str]) -> list[str]:
    from stampc.worlds.pybullet.values import quat_from_yaw

    reasons = []
    standing = {o.name: quat_from_yaw(o.yaw) for o in world.spec.objects}
    for name, pose in world.state.poses:
        if name in world.state.removed or name == world.state.held or name not in standing:
            continue
        _, quat = _actual(world, name)
        if _tilt(quat, standing[name]) > TOPPLED_TILT and f"notified({name})" not in state:
            reasons.append(f"{name} has toppled but was not notified")
    return reasons


def _tilt(quat, standing) -> float:
    """Angle between the body's up axis now and when it stood."""
    from stampc.worlds.pybullet.values import quat_rotate

    up_now = quat_rotate(quat, (0.0, 0.0, 1.0))
    up_then = quat_rotate(standing, (0.0, 0.0, 1.0))
    dot = sum(a * b for a, b in zip(up_now, up_then))
    return math.acos(max(-1.0, min(1.0, dot)))
