"""Several robots and mobile bases in the PyBullet world (real PyBullet + OMPL)."""

from __future__ import annotations

import math
import random

import pytest

from stampc.diagnostics import StampcError
from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.pybullet import manipulation as manip
from stampc.worlds.pybullet import open_world, robots
from stampc.worlds.pybullet.scene_check import parse_scene
from stampc.worlds.pybullet.values import Base, Pose, as_config, as_traj

CAN = {"shape": "cylinder", "radius": 0.03, "height": 0.12, "mass": 0.1}
TABLE = {"name": "table", "size": [0.6, 1.4, 0.05], "position": [0.5, 0.0, -0.025]}


def two_pandas() -> dict:
    """Two Pandas facing the same table from its two ends, a can in front of each."""
    return {
        "robots": [{"name": "left", "model": "panda", "base": [0.0, 0.55, 0.0], "yaw": 0.0},
                   {"name": "right", "model": "panda", "base": [0.0, -0.55, 0.0], "yaw": 0.0}],
        "surfaces": [TABLE],
        "objects": [{"name": "a", **CAN, "position": [0.5, 0.55, 0.06]},
                    {"name": "b", **CAN, "position": [0.5, -0.55, 0.06]}],
        "poses": {"pose_a": "a", "pose_b": "b"},
    }


def mobile_panda() -> dict:
    """One Panda with three candidate base poses; a can near the ``near`` one."""
    return {
        "robots": [{"name": "fetch", "model": "panda", "start": "far",
                    "bases": [{"name": "far", "base": [-1.2, 0.0, 0.0], "yaw": 0.0},
                              {"name": "near", "base": [0.0, 0.0, 0.0], "yaw": 0.0},
                              {"name": "side", "base": [0.5, 0.65, 0.0],
                               "yaw": -math.pi / 2}]}],
        "surfaces": [TABLE],
        "objects": [{"name": "a", **CAN, "position": [0.5, 0.05, 0.06]}],
        "poses": {"pose_a": "a"},
    }


def ctx(world, seed=0, **options) -> Context:
    return Context(world=world, rng=random.Random(seed), options=options)


@pytest.fixture(scope="module")
def pair():
    w = open_world(two_pandas(), seed=0)
    yield w
    w.close()


def test_old_robot_key_is_one_robot_named_robot():
    spec = parse_scene({"robot": {"model": "panda", "base": [0.1, 0, 0], "yaw": 0.5}})
    assert [r.name for r in spec.robots] == ["robot"] and spec.robot is spec.robots[0]
    assert spec.robot.base == (0.1, 0.0, 0.0) and spec.robot.bases == ()


@pytest.mark.parametrize("scene, fragment", [
    ({"robot": {}, "robots": [{}]}, "not both"),
    ({"robots": [{"name": "x"}, {"name": "x"}]}, "duplicate name 'x'"),
    ({"robots": [{"bases": [{"name": "n", "base": [0, 0]}]}]}, "'base' must be a list of 3"),
    ({"robots": [{"start": "nowhere", "bases": [{"name": "n", "base": [0, 0, 0]}]}]},
     "start 'nowhere'"),
    ({"robots": {"name": "x"}}, "must be a list"),
    ({"robot": {"grasps": "pinch"}}, "grasps 'pinch' is not a grasp kind"),
])
def test_bad_robot_entries_are_diagnostics(scene, fragment):
    with pytest.raises(StampcError) as exc:
        parse_scene(scene)
    assert any(fragment in d.message and d.code == "PB001" for d in exc.value.diagnostics)


def test_each_robot_reaches_its_own_can_and_values_record_it(pair):
    values = pair.initial_values()
    left = list(robots.grasp(ctx(pair, budget=2), "left", "a", values["pose_a"]))
    right = list(robots.grasp(ctx(pair, budget=2), "right", "b", values["pose_b"]))
    assert left and right
    for (g, q), name, base in ((left[0], "left", 0.55), (right[0], "right", -0.55)):
        assert g.robot == q.robot == name
        assert q.base.pos == pytest.approx((0.0, base, 0.0)) and g.base == q.base
        assert as_config(q.to_json()) == q  # the owner survives the JSON round trip
    # the trajectory is planned for the robot its goal config belongs to
    (traj,) = next(manip.motion(ctx(pair), right[0][1]))
    assert traj.robot == "right" and traj.base == right[0][1].base
    assert as_traj(traj.to_json()) == traj
    assert traj.configs[0] == pair.state.arms[1].q


def test_executing_one_robot_leaves_the_other_alone(pair):
    s0 = pair.snapshot()
    try:
        pose_b = pair.initial_values()["pose_b"]
        g, q = next(robots.grasp(ctx(pair), "right", "b", pose_b))
        (traj,) = next(manip.motion(ctx(pair), q))
        left_before = pair.state.arms[0]
        manip.pick(ctx(pair), ConcreteAction("pick", {"o": "b", "p": pose_b, "g": g, "q": q,
                                                       "t": traj},
                                             adds=(("holding", ("b",)),)))
        assert pair.state.arms[1].held == "b" and pair.state.arms[1].q == q.q
        assert pair.state.arms[0] == left_before
        # the left robot is still selectable and holds nothing
        pair.select("left")
        assert pair.state.held is None
        assert pair.fingerprint(pair.snapshot()) != pair.fingerprint(s0)
    finally:
        pair.restore(s0)
    assert pair.state.arms[1].held is None


def test_the_other_robot_is_an_obstacle(pair):
    s0 = pair.snapshot()
    try:
        # put the right robot's arm straight up next to the left one: left's hits name it
        pair.select("right")
        right_body = pair.arms["right"].body
        pair.update(base=Pose.of((0.0, 0.45, 0.0)))
        pair.select("left")
        robot_hits, _ = pair.hits(pair.state.q)
        assert right_body in robot_hits
    finally:
        pair.restore(s0)


def test_moving_the_base_changes_reachability():
    world = open_world(mobile_panda(), seed=0)
    try:
        pose_a = world.initial_values()["pose_a"]
        assert world.base_pose().pos == (-1.2, 0.0, 0.0)  # starts at "far"
        # from "far" (1.7 m away) no grasp of a has an IK solution
        assert list(manip.grasp(ctx(world), "a", pose_a)) == []
        bases = [b for (b,) in robots.base_pose(ctx(world), "fetch", "a", pose_a)]
        assert [b.name for b in bases] == ["near", "side"]  # reachable ones, nearest first
        assert all(isinstance(b, Base) and b.robot == "fetch" for b in bases)
        s0 = world.snapshot()
        robots.move_base(ctx(world), ConcreteAction("move_base", {"b": bases[0].to_json()}))
        assert world.base_pose() == bases[0].pose and world.state.arm.base_name == "near"
        found = list(manip.grasp(ctx(world, budget=2), "a", pose_a))
        assert found and all(q.base == bases[0].pose for _, q in found)
        q = found[0][1]
        # IK is relative to the moved base: the hand really is at the grasp pose
        world.set_arm(q.q)
        assert world.ee_pose().distance(pose_a.multiply(found[0][0].hand)) < 0.006
        world.set_arm(world.state.q)
        # a config generated at "near" is not usable from "far"
        world.restore(s0)
        assert world.base_pose().pos == (-1.2, 0.0, 0.0)
        assert list(manip.motion(ctx(world), q)) == []
        with pytest.raises(StampcError) as exc:
            manip.pick(ctx(world), ConcreteAction("pick", {"o": "a", "p": pose_a, "g": None,
                                                           "q": q, "t": None}))
        assert exc.value.diagnostics[0].code == "PB016"
    finally:
        world.close()


def test_unknown_robot_is_a_diagnostic(pair):
    with pytest.raises(StampcError) as exc:
        next(robots.grasp(ctx(pair), "middle", "a", pair.initial_values()["pose_a"]))
    assert exc.value.diagnostics[0].code == "PB015"
