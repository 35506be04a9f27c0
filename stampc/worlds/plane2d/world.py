"""The plane2d world object: an immutable concrete state plus queries and mutators.

The concrete state (:class:`WorldState`) is a frozen dataclass of tuples, so
``snapshot()`` is O(1) (it returns the current state object) and ``restore()`` just
swaps it back. Mutators build a new state with :func:`dataclasses.replace`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Iterable, Mapping, Sequence

import numpy as np

from stampc.diagnostics import Span, StampcError, error
from stampc.worlds.plane2d.geometry import EPS, Point, Shape, overlaps
from stampc.worlds.plane2d.planning import Checker
from stampc.worlds.plane2d.scene import GRIPPER, UAV, Rect, Scene
from stampc.worlds.plane2d.values import Config2, Pose2, decode


@dataclass(frozen=True)
class WorldState:
    """Poses of the objects still in the scene (scene order), gripper, held object and
    its offset from the gripper centre, UAV position and remaining battery, and where
    the robot's base stands (it moves only for a mobile robot)."""

    poses: tuple[tuple[str, Pose2], ...]
    gripper: Point
    held: str | None = None
    held_offset: Point = (0.0, 0.0)
    uav: Point | None = None
    battery: float = 0.0
    base: Point = (0.0, 0.0)
    #: the last path followed (for rendering only: ignored by ==, hash and fingerprint)
    trace: tuple[Point, ...] = field(default=(), compare=False)


class Plane2DWorld:
    """A top-down table world implementing :class:`stampc.worlds.base.World`."""

    package = "stampc.worlds.plane2d"

    def __init__(self, scene: Scene, *, seed: int, verbose: bool = False):
        self.scene = scene
        self.seed = seed
        self.verbose = verbose
        self._specs = {o.name: o for o in scene.objects}
        uav = scene.region(scene.uav.start).centre if scene.uav else None
        self._state = WorldState(poses=scene.initial_poses, gripper=scene.robot.base,
                                 uav=uav, battery=scene.uav.battery if scene.uav else 0.0,
                                 base=scene.robot.base)
        self._pose_map: dict[str, Pose2] = dict(self._state.poses)

    # ------------------------------------------------------------ protocol
    def snapshot(self) -> WorldState:
        return self._state

    def restore(self, state: Any) -> None:
        if not isinstance(state, WorldState):
            raise StampcError([error("S270", f"plane2d: cannot restore a {type(state).__name__} "
                                     "(not a plane2d snapshot)", Span.point("<plane2d world>"))])
        self._set(state)

    def initial_values(self) -> Mapping[str, Any]:
        initial = dict(self.scene.initial_poses)
        out: dict[str, Any] = {}
        for symbol, name in self.scene.poses:
            if name == GRIPPER:
                out[symbol] = Config2(*self.scene.robot.base)
            elif name == UAV and self.scene.uav is not None:
                out[symbol] = Pose2(*self.scene.region(self.scene.uav.start).centre)
            elif name in initial:
                out[symbol] = initial[name]
        return out

    def fingerprint(self, state: WorldState) -> tuple:
        """Hashable key of a snapshot, equal for states equal up to 1e-9 m (lets the
        engine merge policy nodes that reach the same concrete state)."""
        def r(v: float) -> float:
            return round(v, 9) + 0.0      # + 0.0 folds -0.0 into 0.0

        return (tuple((n, r(p.x), r(p.y), r(p.theta)) for n, p in state.poses),
                (r(state.gripper[0]), r(state.gripper[1])), state.held,
                (r(state.held_offset[0]), r(state.held_offset[1])),
                None if state.uav is None else (r(state.uav[0]), r(state.uav[1])),
                r(state.battery), (r(state.base[0]), r(state.base[1])))

    def decode(self, data: Any) -> Any:
        """Concrete value from its JSON form (used when replaying a policy file)."""
        return decode(data)

    def check_fact(self, predicate: str, args: tuple[str, ...]) -> bool | None:
        """Decide a goal fact from the concrete state when its meaning is unambiguous:
        ``holding(o)``, ``handempty``, ``on(o, s)``/``in(o, s)`` for a surface ``s``
        (centre of ``o`` inside it); ``None`` (unknown) for anything else."""
        st = self._state
        if predicate == "holding" and len(args) == 1:
            return st.held == args[0]
        if predicate == "handempty" and not args:
            return st.held is None
        if predicate in ("on", "in") and len(args) == 2:
            rect = self.scene.surface(args[1])
            pose = self._pose_map.get(args[0])
            if rect is not None and args[0] in self._specs:
                return pose is not None and st.held != args[0] and rect.contains(pose.x, pose.y)
        return None

    def render(self, **kwargs: Any) -> np.ndarray:
        """RGB image (H, W, 3, uint8) of the current state; see :mod:`.render`."""
        from stampc.worlds.plane2d.render import render_array  # matplotlib only on demand
        return render_array(self, **kwargs)

    def close(self) -> None:
        """Nothing external to release (no simulator client); kept for the protocol."""

    def _set(self, state: WorldState) -> None:
        self._state = state
        self._pose_map = dict(state.poses)

    # ------------------------------------------------------------- queries
    @property
    def state(self) -> WorldState:
        return self._state

    @property
    def gripper(self) -> Point:
        return self._state.gripper

    @property
    def held(self) -> str | None:
        return self._state.held

    @property
    def base(self) -> Point:
        """Where the robot's base stands now."""
        return self._state.base

    def base_position(self, name: str) -> Point:
        """The position of candidate base ``name`` of a mobile robot."""
        where = self.scene.robot.base_named(name)
        if where is None:
            raise self.unknown("base", name, [n for n, _ in self.scene.robot.bases])
        return where

    @property
    def battery(self) -> float:
        return self._state.battery

    @property
    def uav(self) -> Point | None:
        return self._state.uav

    def is_movable(self, name: str) -> bool:
        return name in self._specs

    def present(self, name: str) -> bool:
        return name in self._pose_map

    def pose(self, name: str) -> Pose2 | None:
        return self._pose_map.get(name)

    def poses(self) -> Mapping[str, Pose2]:
        return dict(self._pose_map)

    def spec(self, name: str):
        spec = self._specs.get(name)
        if spec is None:
            raise self.unknown("object", name, sorted(self._specs))
        return spec

    def shape(self, name: str, pose: Pose2 | None = None) -> Shape:
        pose = pose or self._pose_map[name]
        return self.spec(name).at(pose)

    def surface(self, name: str) -> Rect:
        rect = self.scene.surface(name)
        if rect is None:
            raise self.unknown("surface", name, [n for n, _ in self.scene.surfaces])
        return rect

    def region(self, name: str) -> Rect:
        rect = self.scene.region(name)
        if rect is None:
            raise self.unknown("region", name, [n for n, _ in self.scene.regions])
        return rect

    @staticmethod
    def unknown(kind: str, name: Any, known: Iterable[str]) -> StampcError:
        return StampcError([error("S271", f"plane2d: unknown {kind} {name!r}",
                                  Span.point("<plane2d world>"),
                                  hint=f"known {kind}s: " + ", ".join(known))])

    def static_overlap(self, shape: Shape, margin: float = 0.0) -> bool:
        return any(overlaps(shape, s, margin) for s in self.scene.static_shapes())

    def movable_overlaps(self, shape: Shape, exclude: Iterable[str] = (),
                         margin: float = 0.0) -> list[str]:
        skip = set(exclude)
        return [n for n, p in self._state.poses
                if n not in skip and overlaps(shape, self.spec(n).at(p), margin)]

    def admissible(self, p: Point, base: Point | None = None) -> bool:
        """Gripper centre inside the workspace and within reach of the robot base (where
        it stands now, or ``base``)."""
        return (self.scene.workspace.contains(p[0], p[1])
                and math.dist(p, base or self._state.base) <= self.scene.robot.reach + EPS)

    def held_footprints(self, held: str | None) -> tuple[tuple[Point, float], ...]:
        """Bounding discs of object ``held`` carried by the gripper, as (offset, radius).

        For an object the world does not currently hold (a trajectory planned in another
        state) the exact offset is unknown: a disc of radius gripper + 2·bounding radius
        centred on the gripper conservatively covers any contact grasp.
        """
        if held is None or held not in self._specs:
            return ()
        r = self._specs[held].bounding_radius
        if held == self._state.held:
            return ((self._state.held_offset, r),)
        return (((0.0, 0.0), self.scene.robot.gripper_radius + 2 * r),)

    def gripper_footprints(self) -> tuple[tuple[Point, float], ...]:
        """The moving footprints of the gripper now: its disc plus what it holds."""
        return (((0.0, 0.0), self.scene.robot.gripper_radius),) \
            + self.held_footprints(self._state.held)

    def checker(self, *, exclude: Iterable[str] = (), movables: bool = True,
                footprints: tuple[tuple[Point, float], ...] | None = None,
                reach: float | None = None) -> Checker:
        """Collision checker against static obstacles and (``movables``) the objects on
        the table except ``exclude`` and the held one. ``footprints`` default to the
        gripper's; a UAV passes its own disc and an infinite ``reach``."""
        skip = set(exclude)
        discs, disc_names, boxes, box_names = [], [], [], []
        shapes = [(spec.name, spec, pose) for spec, pose in self.scene.obstacles]
        if movables:
            shapes += [(n, self._specs[n], p) for n, p in self._state.poses
                       if n not in skip and n != self._state.held]
        for name, spec, pose in shapes:
            if spec.shape == "disc":
                disc_names.append(name)
                discs.append((pose.x, pose.y, spec.radius))
            else:
                box_names.append(name)
                boxes.append((pose.x, pose.y, spec.hx, spec.hy, pose.theta))
        return Checker(tuple(disc_names), np.asarray(discs, dtype=float).reshape(-1, 3),
                       tuple(box_names), np.asarray(boxes, dtype=float).reshape(-1, 5),
                       footprints if footprints is not None else self.gripper_footprints(),
                       self.scene.workspace, self._state.base,
                       reach if reach is not None else self.scene.robot.reach)

    # ------------------------------------------------------------ mutators
    def move_gripper(self, points: Sequence[Point]) -> None:
        """Follow ``points``; a held object moves rigidly with the gripper."""
        if not points:
            return
        end = (float(points[-1][0]), float(points[-1][1]))
        trace = tuple((float(x), float(y)) for x, y in points)
        self._set(replace(self._state, gripper=end, poses=self._carried_to(end), trace=trace))

    def move_base(self, name: str) -> None:
        """Drive to candidate base ``name``: the gripper is tucked in over the base first
        and a held object comes along (base motions are not collision-checked)."""
        to = self.base_position(name)
        # no trace: the base drives around the table, along no path this world models
        self._set(replace(self._state, base=to, gripper=to, poses=self._carried_to(to),
                          trace=()))

    def _carried_to(self, gripper: Point) -> tuple[tuple[str, Pose2], ...]:
        """The poses with the held object (if any) moved along with the gripper."""
        st = self._state
        if st.held is None:
            return st.poses
        ox, oy = st.held_offset
        return self._with_pose(st.held, replace(self._pose_map[st.held],
                                                x=gripper[0] + ox, y=gripper[1] + oy))

    def attach(self, name: str) -> None:
        pose = self._pose_map.get(name)
        if pose is None:
            raise self.unknown("object on the table", name, self._pose_map)
        gx, gy = self._state.gripper
        self._set(replace(self._state, held=name, held_offset=(pose.x - gx, pose.y - gy)))

    def release(self, name: str, pose: Pose2 | None = None) -> None:
        st = self._state
        poses = self._with_pose(name, pose) if pose is not None else st.poses
        held = None if st.held == name else st.held
        self._set(replace(st, poses=poses, held=held,
                          held_offset=(0.0, 0.0) if held is None else st.held_offset))

    def remove(self, name: str) -> None:
        st = self._state
        held = None if st.held == name else st.held
        self._set(replace(st, poses=tuple((n, p) for n, p in st.poses if n != name),
                          held=held, held_offset=(0.0, 0.0) if held is None else st.held_offset))

    def set_uav(self, position: Point, battery: float,
                trace: Sequence[Point] = ()) -> None:
        self._set(replace(self._state, uav=(float(position[0]), float(position[1])),
                          battery=max(0.0, float(battery)), trace=tuple(trace)))

    def _with_pose(self, name: str, pose: Pose2) -> tuple[tuple[str, Pose2], ...]:
        if name not in self._pose_map:
            raise self.unknown("object on the table", name, self._pose_map)
        return tuple((n, pose if n == name else p) for n, p in self._state.poses)

    def describe(self) -> str:
        st = self._state
        objs = ", ".join(f"{n}@({p.x:.3f},{p.y:.3f})" for n, p in st.poses)
        return (f"base=({st.base[0]:.3f},{st.base[1]:.3f}) "
                f"gripper=({st.gripper[0]:.3f},{st.gripper[1]:.3f}) held={st.held} "
                f"objects: {objs}" + (f" uav={st.uav} battery={st.battery:.3f}"
                                      if st.uav else ""))


def angle_to(a: Point, b: Point) -> float:
    return math.atan2(b[1] - a[1], b[0] - a[0])
