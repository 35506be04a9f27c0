"""Manipulation bound functions: generators yield valid values, obstruction evaluation is
exact on a hand-built scene, executors apply effects, snapshots restore exactly, and
everything is reproducible from the seed."""

from __future__ import annotations

import dataclasses
import math

import pytest

from stampc.diagnostics import StampcError
from stampc.worlds.base import ConcreteAction
from stampc.worlds.plane2d import Config2, Pose2, Traj2, open_world
from stampc.worlds.plane2d import manipulation as m
from stampc.worlds.plane2d.geometry import Disc, distance
from stampc.worlds.plane2d.scenes import cluttered

from .conftest import BASE, GRIPPER_R, corridor_scene, make_ctx


def _path_clear(w, t: Traj2, ignore: set[str], samples: int = 40) -> bool:
    """Independent check by sampling: the gripper disc (and held footprint) at many points
    of every segment overlaps no object except ``ignore``."""
    held = w.held
    offset = w.state.held_offset if held else None
    held_r = w.spec(held).bounding_radius if held else 0.0
    shapes = [w.shape(n) for n in w.poses() if n not in ignore and n != held]
    shapes += list(w.scene.static_shapes())
    for a, b in zip(t.points, t.points[1:]):
        for k in range(samples + 1):
            x = a[0] + (b[0] - a[0]) * k / samples
            y = a[1] + (b[1] - a[1]) * k / samples
            discs = [Disc(x, y, w.scene.robot.gripper_radius)]
            if held:
                discs.append(Disc(x + offset[0], y + offset[1], held_r))
            if any(distance(d, s) < -1e-9 for d in discs for s in shapes):
                return False
    return True


# ------------------------------------------------------------------ grasping
@pytest.mark.parametrize("obj", ["can0", "can3", "box1"])
def test_grasp_configs_touch_the_object_and_are_reachable(world, obj):
    ctx = make_ctx(world)
    pose = world.pose(obj)
    grasps = list(m.grasp(ctx, obj, pose))
    assert len(grasps) >= 4
    for g, q in grasps:
        assert q.target == obj
        touching = distance(Disc(q.x, q.y, GRIPPER_R), world.shape(obj))
        assert abs(touching) < 1e-9
        assert math.dist(q.xy, BASE) <= world.scene.robot.reach
        assert world.scene.workspace.contains(q.x, q.y)
    # the first grasp faces the robot base: the gripper is closer to it than the object
    q0 = grasps[0][1]
    assert math.dist(q0.xy, BASE) < math.dist(pose.xy, BASE)


def test_grasp_angles_distinct_and_out_of_reach_object_has_none(world):
    ctx = make_ctx(world)
    angles = [round(g.angle, 9) for g, _ in m.grasp(ctx, "can0", world.pose("can0"))]
    assert len(set(angles)) == len(angles)
    far = Pose2(0.5, 5.0, 0.0)
    assert list(m.grasp(ctx, "can0", far)) == []
    assert not m.reachable(ctx, "can0", far)
    assert m.reachable(ctx, "can0", world.pose("can0"))


def test_grasp_accepts_json_pose(world):
    ctx = make_ctx(world)
    from_json = list(m.grasp(ctx, "can0", {"x": 0.5, "y": 0.5, "theta": 0.0}))
    assert from_json == list(m.grasp(make_ctx(world), "can0", world.pose("can0")))


# ----------------------------------------------------------------- placement
@pytest.mark.parametrize("surface", ["tray", "table"])
def test_placements_inside_surface_and_clear(world, surface):
    ctx = make_ctx(world, 3, budget=6)
    rect = world.surface(surface)
    places = list(m.placement(ctx, "can4", surface))
    assert len(places) == 6
    for pose, q in places:
        shape = world.shape("can4", pose)
        assert rect.x0 <= pose.x - shape.radius and pose.x + shape.radius <= rect.x1
        assert rect.y0 <= pose.y - shape.radius and pose.y + shape.radius <= rect.y1
        for other in world.poses():
            if other != "can4":
                assert distance(shape, world.shape(other)) > 0
        assert math.dist(q.xy, BASE) <= world.scene.robot.reach
        # config holds the object: the gripper touches it
        assert abs(distance(Disc(q.x, q.y, GRIPPER_R), shape)) < 1e-9


def test_placement_of_box_keeps_its_footprint_inside(world):
    ctx = make_ctx(world, 5, budget=5)
    rect = world.surface("tray")
    for pose, _ in m.placement(ctx, "box1", "tray"):
        for cx, cy in world.shape("box1", pose).corners():
            assert rect.contains(cx, cy)


def test_placement_on_too_small_surface_yields_nothing():
    scene = corridor_scene()
    scene["surfaces"]["coaster"] = {"x0": 0.1, "y0": 0.1, "x1": 0.14, "y1": 0.14}
    w = open_world(scene, seed=0)
    assert list(m.placement(make_ctx(w), "can4", "coaster")) == []


# --------------------------------------------------------------- obstruction
def _straight_to_can0(world) -> Traj2:
    q = m.grasp_config(world, "can0", world.pose("can0"), m.facing_angle(world, world.pose("can0")))
    assert math.isclose(q.x, 0.5) and math.isclose(q.y, 0.45)
    return Traj2((world.gripper, q.xy), None, "can0")


def test_blocking_objects_exact_on_constructed_scene(world):
    ctx = make_ctx(world)
    t = _straight_to_can0(world)
    assert m.blocking_objects(ctx, t) == {"can1", "can2", "box1"}
    for x, expected in [("can1", True), ("can2", True), ("box1", True), ("can3", False),
                        ("box2", False), ("can4", False), ("can0", False), ("ghost", False)]:
        assert m.collision(ctx, x, t) is expected, x
    assert any(k[1] == t for k in ctx.cache)       # memoised per trajectory


def test_held_object_sweeps_too(world):
    ctx = make_ctx(world)
    # grasp can4 from its left so it is carried 0.05 to the right of the gripper
    q = Config2(0.1 - 0.05, 0.5, "can4")
    m.pick(ctx, ConcreteAction("pick", {"o": "can4", "p": world.pose("can4"), "q": q,
                                        "t": Traj2((world.gripper, q.xy))},
                               adds=(("holding", ("can4",)),)))
    assert world.held == "can4"
    # gripper along y = 0.40 from x=0.05 to x=0.35: the gripper alone stays clear of can3
    # (x=0.444) but the carried can (x up to 0.43) reaches it
    t = Traj2((world.gripper, (0.35, 0.40)), "can4", None)
    assert m.blocking_objects(make_ctx(world), t) == {"can3"}
    bare = Traj2((world.gripper, (0.35, 0.40)), None, None)
    assert m.blocking_objects(make_ctx(world), bare) == frozenset()


# -------------------------------------------------------------------- motion
def test_motion_straight_when_free(world):
    ctx = make_ctx(world)
    q = Config2(0.2, 0.2, None)
    (t,), = list(m.motion(ctx, q))
    assert t.points == (world.gripper, (0.2, 0.2))


def test_motion_rrt_paths_are_collision_free(world):
    ctx = make_ctx(world, 7, budget=3)
    _, q = next(m.grasp(ctx, "can0", world.pose("can0")))
    paths = [t for (t,) in m.motion(ctx, q)]
    assert paths, "the corridor scene has room to go around the blockers"
    for t in paths:
        assert t.points[0] == world.gripper and t.points[-1] == q.xy
        assert len(t.points) > 2                       # not the blocked straight line
        assert _path_clear(world, t, ignore={"can0"})
        assert m.blocking_objects(ctx, t) == frozenset()


def test_motion_falls_back_to_the_blocked_straight_line():
    scene = corridor_scene()
    # walls 35 mm from can1 on both sides (< a 40 mm gripper) and behind can0 leave
    # no way around the blocker
    scene["obstacles"] = [
        {"name": "wall_l", "shape": "box", "size": [0.02, 0.7], "x": 0.425, "y": 0.25},
        {"name": "wall_r", "shape": "box", "size": [0.02, 0.7], "x": 0.575, "y": 0.25},
        {"name": "wall_b", "shape": "box", "size": [0.17, 0.02], "x": 0.5, "y": 0.59}]
    scene["objects"] = [o for o in scene["objects"] if o["name"] in ("can0", "can1", "can4")]
    w = open_world(scene, seed=0)
    ctx = make_ctx(w, 1, budget=2, iterations=200)
    _, q = next(m.grasp(ctx, "can0", w.pose("can0")))
    (t,), = list(m.motion(ctx, q))
    assert t.points == (w.gripper, q.xy)
    assert m.blocking_objects(ctx, t) == {"can1"}


def test_motion_carrying_avoids_with_held_footprint(world):
    ctx = make_ctx(world, 2)
    q = Config2(0.05, 0.5, "can4")
    m.pick(ctx, ConcreteAction("pick", {"o": "can4", "p": world.pose("can4"), "q": q,
                                        "t": Traj2((world.gripper, q.xy))},
                               adds=(("holding", ("can4",)),)))
    pose, place_q = next(m.placement(make_ctx(world, 4), "can4", "tray"))
    for (t,) in m.motion(make_ctx(world, 5), place_q):
        assert t.held == "can4" and t.target == "can4"
        assert _path_clear(world, t, ignore=set())


# -------------------------------------------------------- executors, states
def test_pick_place_discard_effects_and_snapshot_restore(world):
    ctx = make_ctx(world)
    start = world.snapshot()
    g, q = next(m.grasp(ctx, "can3", world.pose("can3")))
    (t,) = next(m.motion(ctx, q))
    slip = ConcreteAction("pick", {"o": "can3", "p": world.pose("can3"), "g": g, "q": q, "t": t})
    m.pick(ctx, slip)
    assert world.held is None and world.gripper == q.xy and world.pose("can3") == Pose2(0.444, 0.4)
    after_slip = world.snapshot()
    m.pick(ctx, dataclasses.replace(slip, adds=(("holding", ("can3",)),)))
    assert world.held == "can3"
    pose, pq = next(m.placement(make_ctx(world, 1), "can3", "tray"))
    (t2,) = next(m.motion(make_ctx(world, 1), pq))
    m.place(ctx, ConcreteAction("place", {"o": "can3", "s": "tray", "p": pose, "q": pq, "t": t2},
                                adds=(("at", ("can3", pose)),), deletes=(("holding", ("can3",)),)))
    assert world.held is None and world.pose("can3") == pose and world.gripper == pq.xy
    m.discard(ctx, ConcreteAction("discard", {"o": "can1"}))
    assert not world.present("can1") and "can1" not in world.poses()
    world.restore(after_slip)
    assert world.snapshot() == after_slip and world.held is None and world.present("can1")
    world.restore(start)
    assert world.snapshot() == start and world.poses() == dict(start.poses)
    with pytest.raises(dataclasses.FrozenInstanceError):
        start.gripper = (0.0, 0.0)


def test_place_slip_keeps_object_in_hand_and_drop_releases_in_place(world):
    ctx = make_ctx(world)
    q = Config2(0.05, 0.5, "can4")
    m.pick(ctx, ConcreteAction("pick", {"o": "can4", "q": q}, adds=(("holding", ("can4",)),)))
    moved = Config2(0.3, 0.5, "can4")
    m.place(ctx, ConcreteAction("place", {"o": "can4", "q": moved, "p": Pose2(0.9, 0.1)}))
    assert world.held == "can4" and math.isclose(world.pose("can4").x, 0.35)
    m.place(ctx, ConcreteAction("place", {"o": "can4", "q": moved, "p": Pose2(0.9, 0.1)},
                                deletes=(("holding", ("can4",)),)))
    assert world.held is None and math.isclose(world.pose("can4").x, 0.35)


# ------------------------------------------------------------- determinism
def test_same_seed_same_yields():
    def run(seed):
        w = open_world(cluttered(8, 4), seed=0)
        ctx = make_ctx(w, seed, budget=3)
        grasps = list(m.grasp(ctx, "can0", w.pose("can0")))
        motions = list(m.motion(ctx, grasps[0][1]))
        places = list(m.placement(ctx, "can5", "tray"))
        return grasps, motions, places

    first = run(11)
    assert first == run(11)
    assert len(first[1]) == 3 and all(len(t.points) > 2 for (t,) in first[1])
    assert any(run(s)[1] != first[1] for s in (12, 13))


# --------------------------------------------------------------- bad input
def test_bad_inputs_raise_located_diagnostics(world):
    ctx = make_ctx(world)
    cases = [
        (lambda: list(m.grasp(ctx, "nothing", Pose2(0, 0))), "S271"),
        (lambda: list(m.grasp(ctx, "can0", "not a pose")), "S260"),
        (lambda: list(m.motion(ctx, {"x": "a", "y": 1})), "S260"),
        (lambda: list(m.placement(ctx, "can0", "floor")), "S271"),
        (lambda: list(m.grasp(make_ctx(world, budget=0), "can0", Pose2(0.5, 0.5))), "S273"),
        (lambda: m.pick(ctx, ConcreteAction("pick", {"o": "can0"})), "S274"),
        (lambda: world.restore("junk"), "S270"),
        (lambda: m.collision(dataclasses.replace(ctx, world=object()), "can0",
                             _straight_to_can0(world)), "S272"),
    ]
    for call, code in cases:
        with pytest.raises(StampcError) as info:
            call()
        assert info.value.diagnostics[0].code == code


def test_fingerprint_merges_equal_states_only(world):
    ctx = make_ctx(world)
    start = world.snapshot()
    q = Config2(0.3, 0.3, None)
    m.pick(ctx, ConcreteAction("pick", {"o": "can4", "q": q}))           # a slip: moves only
    once = world.snapshot()
    m.pick(ctx, ConcreteAction("pick", {"o": "can4", "q": q,
                                        "t": Traj2(((0.3, 0.3), (0.31, 0.3), (0.3, 0.3)))}))
    twice = world.snapshot()
    assert once.trace != twice.trace                       # different paths followed...
    assert once == twice                                   # ...same concrete state
    assert world.fingerprint(once) == world.fingerprint(twice)
    assert world.fingerprint(start) != world.fingerprint(once)
    nudged = dataclasses.replace(once, gripper=(0.3 + 1e-12, 0.3))
    assert world.fingerprint(nudged) == world.fingerprint(once)
    hash(world.fingerprint(once))


def test_trajectory_free_counts_static_and_movable(world):
    ctx = make_ctx(world, 7)
    assert not m.trajectory_free(ctx, _straight_to_can0(world))
    _, q = next(m.grasp(ctx, "can0", world.pose("can0")))
    (t,) = next(m.motion(ctx, q))
    assert m.trajectory_free(ctx, t)
    scene = corridor_scene()
    scene["obstacles"] = [{"name": "post", "shape": "disc", "radius": 0.02, "x": 0.2, "y": 0.2}]
    walled = open_world(scene, seed=0)
    through_post = Traj2((walled.gripper, (0.15, 0.25)), None, None)   # crosses (0.2, 0.2)
    assert m.blocking_objects(make_ctx(walled), through_post) == frozenset()
    assert not m.trajectory_free(make_ctx(walled), through_post)


def test_decode_and_goal_fact_checks(world):
    from stampc.worlds.base import to_json

    ctx = make_ctx(world)
    g, q = next(m.grasp(ctx, "can4", world.pose("can4")))
    (t,) = next(m.motion(ctx, q))
    for v in (world.pose("can4"), g, q, t):
        assert world.decode(to_json(v)) == v
    assert world.decode("can4") == "can4" and world.decode({"x": 1}) == {"x": 1}
    assert world.check_fact("handempty", ()) is True
    assert world.check_fact("on", ("can4", "tray")) is False
    assert world.check_fact("on", ("can4", "table")) is True
    assert world.check_fact("at", ("can4", "pose_can4")) is None
    m.pick(ctx, ConcreteAction("pick", {"o": "can4", "q": q, "t": t},
                               adds=(("holding", ("can4",)),)))
    assert world.check_fact("holding", ("can4",)) is True
    assert world.check_fact("handempty", ()) is False
    assert world.check_fact("on", ("can4", "table")) is False     # in the hand, not on it
