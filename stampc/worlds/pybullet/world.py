"""The PyBullet world: one DIRECT client, the scene's bodies, the concrete state and the
collision-check primitive everything else is built on.

Collision checks follow the fastest measured pattern (see docs/worlds-pybullet.md):
``resetJointStatesMultiDof`` + ``performCollisionDetection`` + ``getContactPoints`` with
penetrating contacts only. The bodies are created in their collision filter groups by
``bodies.py``, which keep the broadphase to the pairs we ask about.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Mapping

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.pybullet._pb import p, pybullet_data, quiet_stdout

from stampc.worlds.pybullet import bodies
from stampc.worlds.pybullet.bodies import G_HELD, G_MOVABLE, G_ROBOT, G_STATIC, G_UAV
from stampc.worlds.pybullet.scene import BoxSpec, ObjectSpec, RobotModel, RobotSpec, SceneSpec
from stampc.worlds.pybullet.state import ARM_FIELDS, Arm, ArmState, Geometry, WorldState
from stampc.worlds.pybullet.values import Pose, quat_from_yaw

__all__ = ["PyBulletWorld", "WorldState", "ArmState", "Arm", "Geometry", "PENETRATION",
           "CLEARANCE", "FINGER_SLACK", "RELEASE_SLACK", "G_ROBOT", "G_HELD", "G_MOVABLE",
           "G_STATIC", "G_UAV"]

#: m each finger stands off the held object's side, and off the one just let go
FINGER_SLACK, RELEASE_SLACK = 0.001, 0.005
_CLOSING = (0.0, 1.0, 0.0)  # the fingers close along the end-effector frame's y axis
#: contacts shallower than this (m) are resting contacts, not collisions
PENETRATION = 1e-4
#: m planning keeps between the robot (or held object) and a movable object. Execution
#: lets objects settle, and Bullet's distance between nearly touching convex shapes is not
#: stable under the tiny pose changes that brings: a hand planned 0.04 mm into a can's
#: rim met it 0.23 mm deep after the can settled 0.01 mm lower, 2e-5 rad tilted
#: (cluttered-20 seed 15). Statics never move, so their planned geometry is executed
#: exactly and needs no margin. The re-check passes 0: any penetration of a movable
#: object counts there, and only :data:`PENETRATION` is tolerated, against statics.
CLEARANCE = 1e-3


class PyBulletWorld:
    """A concrete world on one PyBullet DIRECT client (implements ``World``)."""

    package = "stampc.worlds.pybullet"

    def __init__(self, spec: SceneSpec, *, seed: int, verbose: bool = False,
                 visuals: bool = True):
        self.spec = spec
        self.seed = seed
        self.verbose = verbose
        #: visual shapes loaded (``render`` needs them; planning and execution do not)
        self.visuals = visuals
        with quiet_stdout(not verbose):
            self.client = p.connect(p.DIRECT)
        try:
            self._build(spec)
        except BaseException:
            self.close()  # never leak a client when the scene cannot be built
            raise
        self.checks = 0  # collision checks performed (for benchmarks)
        #: answers bound functions computed once for the whole run: geometry no action
        #: changes (a `? predicate` evaluator's verdict); never part of a snapshot
        self.memo: dict[tuple, object] = {}

    # ------------------------------------------------------------------ building
    def _build(self, spec: SceneSpec) -> None:
        p.setAdditionalSearchPath(pybullet_data.getDataPath(), physicsClientId=self.client)
        self.body: dict[str, int] = {}
        self.name_of: dict[int, str] = {}
        self.geometry: dict[str, Geometry] = {}
        self.surfaces: dict[str, BoxSpec] = {s.name: s for s in spec.surfaces}
        self.regions: dict[str, BoxSpec] = {r.name: r for r in spec.regions}
        self.static_ids: frozenset[int] = frozenset(self._add_box(s) for s in spec.surfaces)
        self.movable_ids: frozenset[int] = frozenset(self._add_object(o) for o in spec.objects)
        self.arms: dict[str, Arm] = {r.name: self._add_robot(r) for r in spec.robots}
        self._arm_order = tuple(self.arms)
        self.uav = self._add_uav() if spec.uav is not None else -1
        self._placed: dict[str, Pose] = {}
        self._bases: dict[str, Pose] = {}
        #: per arm: the finger opening in its state and during its retreat
        self._openings: dict[int, tuple[float, float]] = {}
        #: per arm: the opening its fingers stand at now
        self._fingers: dict[int, float] = {}
        poses = tuple((o.name, Pose.of(o.position, quat_from_yaw(o.yaw))) for o in spec.objects)
        arms = tuple(ArmState(a.model.rest, Pose.of(a.spec.base, quat_from_yaw(a.spec.yaw)),
                              a.spec.start) for a in self.arms.values())
        uav_pose = Pose.of(spec.uav.position) if spec.uav else None
        battery = spec.uav.battery if spec.uav else 0.0
        self._state = WorldState(arms, poses, uav=uav_pose, battery=battery)
        self._sync(self._state, force=True)

    # the active robot (what kinematics, planning and the collision check use)
    @property
    def active_arm(self) -> Arm | None:
        return self.arms[self._arm_order[self._state.active]] if self.arms else None

    @property
    def robot(self) -> int:
        arm = self.active_arm
        return arm.body if arm else -1

    @property
    def model(self) -> RobotModel | None:
        arm = self.active_arm
        return arm.model if arm else None

    @property
    def lower(self) -> tuple[float, ...]:
        return self.active_arm.lower  # type: ignore[union-attr]

    @property
    def upper(self) -> tuple[float, ...]:
        return self.active_arm.upper  # type: ignore[union-attr]

    @property
    def ik_joints(self) -> tuple[int, ...]:
        return self.active_arm.ik_joints  # type: ignore[union-attr]

    @property
    def robot_names(self) -> tuple[str, ...]:
        return self._arm_order

    def select(self, name: str | None = None) -> Arm:
        """Make robot ``name`` (default: the first) the active one; return it.

        Every bound function selects the robot it acts for on entry (from an explicit
        argument or the robot recorded in a config or trajectory), so the selection left
        behind by an earlier call never matters.
        """
        if not self.arms:
            raise StampcError([error("PB010", "this PyBullet world has no robot arm",
                                     Span.point("<world>"))])
        key = self._arm_order[0] if name is None else name
        if key not in self.arms:
            raise StampcError([error("PB015", f"unknown robot {name!r}", Span.point("<world>"),
                                     f"robots: {', '.join(self._arm_order)}")])
        index = self._arm_order.index(key)
        if index != self._state.active:
            self._state = replace(self._state, active=index)
        return self.arms[key]

    def base_pose(self, name: str | None = None) -> Pose:
        """Where robot ``name`` (default: the active one) stands now."""
        index = self._state.active if name is None else self._arm_order.index(name)
        return self._state.arms[index].base

    def candidate_bases(self, name: str | None = None) -> dict[str, Pose]:
        """Robot ``name``'s named base poses (empty for a fixed base)."""
        arm = self.active_arm if name is None else self.arms[name]
        assert arm is not None
        return {b.name: Pose.of(b.base, quat_from_yaw(b.yaw)) for b in arm.spec.bases}

    def grasp_kinds(self, name: str | None = None) -> str:
        """Robot ``name``'s grasp kinds (its scene entry's ``grasps``: top / side / any)."""
        arm = self.active_arm if name is None else self.arms[name]
        assert arm is not None
        return arm.spec.grasps

    def _register(self, name: str, body: int) -> int:
        self.body[name] = body
        self.name_of[body] = name
        return body

    def _add_box(self, s: BoxSpec) -> int:
        return self._register(s.name, bodies.add_box(self.client, s, self.visuals))

    def _add_object(self, o: ObjectSpec) -> int:
        body, self.geometry[o.name] = bodies.add_object(self.client, o, self.verbose,
                                                        self.visuals)
        return self._register(o.name, body)

    def _add_robot(self, spec: RobotSpec) -> Arm:
        arm = bodies.add_robot(self.client, spec, self.verbose, self.visuals)
        self.name_of[arm.body] = spec.name
        return arm

    def _add_uav(self) -> int:
        assert self.spec.uav is not None
        body = bodies.add_uav(self.client, self.spec.uav, self.visuals)
        self.name_of[body] = self.spec.uav.name
        return body

    # ------------------------------------------------------------------ World protocol
    def snapshot(self) -> WorldState:
        return self._state

    def restore(self, state: WorldState) -> None:
        self._sync(state)

    def initial_values(self) -> Mapping[str, Pose]:
        initial = {o.name: Pose.of(o.position, quat_from_yaw(o.yaw)) for o in self.spec.objects}
        return {sym: initial[obj] for sym, obj in self.spec.poses}

    def close(self) -> None:
        if self.client >= 0:
            p.disconnect(physicsClientId=self.client)
            self.client = -1

    def render(self, width: int = 480, height: int = 360, **camera: Any) -> Any:
        """An RGB frame (numpy ``height × width × 3``) of the current state, rendered
        with TinyRenderer; ``camera`` as in :func:`.render.render_frame`."""
        from stampc.worlds.pybullet.render import render_frame  # numpy frames only on demand
        return render_frame(self, width, height, **camera)

    def fingerprint(self, state: WorldState) -> tuple:
        """Hashable key of a snapshot, equal for states equal up to 1e-6 (m, rad, quat
        components): lets the engine merge policy nodes reaching the same concrete state."""
        def r(values: tuple[float, ...] | None) -> tuple[float, ...] | None:
            return None if values is None else tuple(round(v, 6) + 0.0 for v in values)

        def pose(x: Pose | None) -> tuple | None:
            return None if x is None else (r(x.pos), r(x.quat))

        arms = tuple((r(a.q), pose(a.base), a.base_name, a.held, pose(a.grip), r(a.retreat),
                      a.released, a.release_slack) for a in state.arms)
        return (arms, tuple((n, pose(x)) for n, x in state.poses), pose(state.uav),
                round(state.battery, 6), tuple(sorted(state.removed)),
                tuple((n, pose(x)) for n, x in state.resting))

    def __enter__(self) -> "PyBulletWorld":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------------ state
    @property
    def state(self) -> WorldState:
        return self._state

    def _sync(self, state: WorldState, force: bool = False) -> None:
        """Make the bodies match ``state``, touching only what changed."""
        old = self._state
        before, after = old.all_held(), state.all_held()
        for name in (before - after) | (before if force else frozenset()):
            self._set_group(name, G_MOVABLE, G_ROBOT | G_HELD | G_UAV)
        for name in (after - before) | (after if force else frozenset()):
            self._set_group(name, G_HELD, G_MOVABLE | G_STATIC)
        self._regroup_resting(dict(old.resting), dict(state.resting))
        for name, pose in state.poses:
            if name in state.removed:
                pose = self._limbo(name, state)
            if force or self._placed.get(name) != pose:
                self._place_body(name, pose)
        self._state = state
        for index, arm in enumerate(state.arms):
            self._place_base(self._arm_order[index], arm.base, force)
            self._set_joints(index, arm.q)
            self._openings[index] = self._grip_openings(index)
            self._apply_fingers(index, self._openings[index][0], force=True)
        if self.uav >= 0 and state.uav is not None:
            p.resetBasePositionAndOrientation(self.uav, state.uav.pos, state.uav.quat,
                                              physicsClientId=self.client)

    def _place_base(self, name: str, base: Pose, force: bool = False) -> None:
        if force or self._bases.get(name) != base:
            p.resetBasePositionAndOrientation(self.arms[name].body, base.pos, base.quat,
                                              physicsClientId=self.client)
            self._bases[name] = base

    def _limbo(self, name: str, state: WorldState) -> Pose:
        """Where removed objects wait: far below the floor, apart from each other —
        or where physics let them come to rest (``state.resting``)."""
        return dict(state.resting).get(name) or Pose((0.0, 10.0 * self.body[name], -100.0))

    def rest_removed(self, name: str, pose: Pose) -> None:
        """Removed ``name`` lies at ``pose`` (in the tray): drawn, out of the robot's way."""
        resting = {**dict(self._state.resting), name: pose}
        self._sync(replace(self._state, resting=tuple(sorted(resting.items()))))

    def _regroup_resting(self, old: dict[str, Pose], new: dict[str, Pose]) -> None:
        """Resting objects collide with objects and surfaces only, the others as usual."""
        for name in old.keys() - new.keys():
            self._set_group(name, G_MOVABLE, G_ROBOT | G_HELD | G_UAV)
        for name in new.keys() - old.keys():
            self._set_group(name, G_MOVABLE, G_MOVABLE | G_STATIC)

    def _set_group(self, name: str, group: int, mask: int) -> None:
        p.setCollisionFilterGroupMask(self.body[name], -1, group, mask,
                                      physicsClientId=self.client)

    def _place_body(self, name: str, pose: Pose) -> None:
        p.resetBasePositionAndOrientation(self.body[name], pose.pos, pose.quat,
                                          physicsClientId=self.client)
        self._placed[name] = pose

    def update(self, **changes: object) -> None:
        """Replace fields of the current state (and move bodies accordingly); the
        per-robot fields (``q``, ``held``, ``grip``, ``retreat``, ``released``,
        ``release_slack``, ``base``, ``base_name``) change the active robot's. A change of
        ``released`` resets ``release_slack`` to the default unless given too: a stale
        slack would keep equal states from merging."""
        arm_changes = {k: v for k, v in changes.items() if k in ARM_FIELDS}
        if "released" in arm_changes:
            arm_changes.setdefault("release_slack", None)
        state = replace(self._state, **{k: v for k, v in changes.items()
                                        if k not in ARM_FIELDS})
        if arm_changes:
            arms = list(state.arms)
            arms[state.active] = replace(arms[state.active], **arm_changes)
            state = replace(state, arms=tuple(arms))
        self._sync(state)

    def move_base(self, base: Pose, name: str | None = None) -> None:
        """Re-place the active robot's base at ``base`` (candidate ``name``); the arm keeps
        its joints, a held object moves along."""
        self.update(base=base, base_name=name, retreat=None, released=None)

    def with_object_pose(self, name: str, pose: Pose) -> tuple[tuple[str, Pose], ...]:
        return tuple((n, pose if n == name else old) for n, old in self._state.poses)

    def object_pose(self, name: str) -> Pose:
        return self._state.pose(name)

    def movable_names(self) -> list[str]:
        return [self.name_of[b] for b in sorted(self.movable_ids)]

    def present(self, name: str) -> bool:
        return name in self.geometry and name not in self._state.removed

    # ------------------------------------------------------------------ kinematics
    def set_arm(self, q: tuple[float, ...] | list[float]) -> None:
        """Put the active arm at ``q`` (and carry its held object along)."""
        self._set_joints(self._state.active, q)

    def _set_joints(self, index: int, q: tuple[float, ...] | list[float]) -> None:
        arm = self.arms[self._arm_order[index]]
        p.resetJointStatesMultiDof(arm.body, arm.model.arm_joints, [[v] for v in q],
                                   physicsClientId=self.client)
        state = self._state.arms[index]
        if state.held is not None and state.grip is not None:
            obj = self._ee_pose(arm).multiply(state.grip)
            p.resetBasePositionAndOrientation(self.body[state.held], obj.pos, obj.quat,
                                              physicsClientId=self.client)
            self._placed.pop(state.held, None)  # the body left its recorded pose

    def _grip_openings(self, index: int) -> tuple[float, float]:
        """The finger opening of arm ``index`` in its state (closed on the held object,
        ``FINGER_SLACK`` wider; else wide open) and during the retreat that starts
        there (around the object just let go, the state's ``release_slack`` wider, by
        default ``RELEASE_SLACK``). Fully open fingers around a held plank reach 2 cm
        past it: into the next tower's plank on Keva's 3-towers, a collision no real
        hand has."""
        arm, state = self.arms[self._arm_order[index]], self._state.arms[index]
        wide = arm.model.finger_open
        if state.held is not None and state.grip is not None and state.held in self.geometry:
            held = min(wide, self.geometry[state.held].half_extent(state.grip.quat, _CLOSING)
                       + FINGER_SLACK)
            return held, held
        if state.released is not None and state.released in self.geometry:
            turn = self._ee_pose(arm).inverse().multiply(self._state.pose(state.released))
            slack = RELEASE_SLACK if state.release_slack is None else state.release_slack
            return wide, min(wide, self.geometry[state.released].half_extent(turn.quat, _CLOSING)
                             + slack)
        return wide, wide

    def _apply_fingers(self, index: int, opening: float, force: bool = False) -> None:
        """Set the fingers of arm ``index`` unless they stand so already (each state
        change forces it: execution's physics may have pushed them, and every settle
        ends in one). Collision checks call this: resetting unchanged fingers cost
        about 12 % of a check."""
        if not force and self._fingers.get(index) == opening:
            return
        arm = self.arms[self._arm_order[index]]
        for j in arm.model.finger_joints:
            p.resetJointState(arm.body, j, opening, physicsClientId=self.client)
        self._fingers[index] = opening

    def ee_pose(self) -> Pose:
        arm = self.active_arm
        assert arm is not None
        return self._ee_pose(arm)

    def _ee_pose(self, arm: Arm) -> Pose:
        ls = p.getLinkState(arm.body, arm.model.ee_link, computeForwardKinematics=True,
                            physicsClientId=self.client)
        return Pose(tuple(ls[4]), tuple(ls[5]))

    # ------------------------------------------------------------------ collisions
    def hits(self, q: tuple[float, ...] | list[float], stretch: str = "middle",
             clearance: float = 0.0) -> tuple[frozenset[int], frozenset[int]]:
        """Bodies the robot and the held object meet at ``q`` (robot id = self-hit), as
        :meth:`contacts` counts them; in a trajectory's ``"retreat"`` stretch the fingers
        are as they let go."""
        index = self._state.active
        if index in self._openings:
            self._apply_fingers(index, self._openings[index][stretch == "retreat"])
        self.set_arm(q)
        return self.contacts(clearance)

    def contacts(self, clearance: float = 0.0) -> tuple[frozenset[int], frozenset[int]]:
        """Bodies the robot and the held object meet: a static one when penetrated deeper
        than :data:`PENETRATION` (resting contacts), a movable one when nearer than
        ``clearance`` — with the default 0, penetrated to any depth (Bullet reports
        contact points up to about 2 mm apart, so a clearance costs no extra query)."""
        cid = self.client
        self.checks += 1
        p.performCollisionDetection(physicsClientId=cid)
        movable = self.movable_ids

        def hit(c: tuple) -> bool:
            return c[8] < (clearance if c[2] in movable else -PENETRATION)

        robot = frozenset(c[2] for c in p.getContactPoints(bodyA=self.robot, physicsClientId=cid)
                          if hit(c))
        held: frozenset[int] = frozenset()
        if self._state.held is not None:
            held = frozenset(c[2] for c in p.getContactPoints(
                bodyA=self.body[self._state.held], physicsClientId=cid) if hit(c))
        return robot, held

    def names(self, bodies: frozenset[int]) -> frozenset[str]:
        return frozenset(self.name_of[b] for b in bodies if b in self.name_of)
