"""The plane2d mobile base: scene keys, where the base stands, and the mobile
cluttered-table bindings (grasp_at, reaches, bin_drop, move_base)."""

from __future__ import annotations

import math
import random

import pytest

from stampc.diagnostics import StampcError
from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.plane2d import Pose2, open_world
from stampc.worlds.plane2d import cluttered as c
from stampc.worlds.plane2d.scenes import MOBILE_REACH, cluttered_mobile


def _ctx(world, seed: int = 0) -> Context:
    return Context(world, random.Random(seed))


def _action(name: str, **args) -> ConcreteAction:
    return ConcreteAction(name=name, args=args, adds=(), deletes=())


@pytest.fixture
def world():
    return open_world(cluttered_mobile(15, 1), seed=0)


def test_scene_bases_and_start(world):
    scene = cluttered_mobile(15, 1)
    start = scene["robot"]["start"]
    assert world.base == tuple(dict((b["name"], b["base"]) for b in scene["robot"]["bases"])[start])
    assert world.gripper == world.base
    # the default workspace covers every base, not only the start
    ws = world.scene.workspace
    assert all(ws.contains(x, y) for _, (x, y) in world.scene.robot.bases)
    assert cluttered_mobile(15, 1) == scene != cluttered_mobile(15, 2)


@pytest.mark.parametrize("robot, fragment", [
    ({"bases": [], "gripper_radius": 0.02, "reach": 0.5}, "robot.bases"),
    ({"bases": [{"name": "b0", "base": [0, 0]}], "start": "b9", "gripper_radius": 0.02,
      "reach": 0.5}, "robot.start"),
    ({"bases": [{"name": "b0", "base": [0, 0]}, {"name": "b0", "base": [1, 0]}],
      "gripper_radius": 0.02, "reach": 0.5}, "robot.bases[1].name"),
    ({"bases": [{"name": "b0", "base": "here"}], "gripper_radius": 0.02, "reach": 0.5},
     "robot.bases[0].base"),
])
def test_bad_bases_are_located(robot, fragment):
    scene = cluttered_mobile(3, 0)
    scene["robot"] = robot
    with pytest.raises(StampcError) as info:
        open_world(scene, seed=0)
    assert any(d.code == "S201" and fragment in d.message for d in info.value.diagnostics)


def test_reach_follows_the_base(world):
    far, point = "b3", (0.97, 0.3)    # the right edge: only the right base reaches it
    target = world.scene.robot.base_named(far)
    assert world.base != target and not world.admissible(point)
    before = world.fingerprint(world.snapshot())
    c.move_base(_ctx(world), _action("move_base", a="?", b=far))
    assert world.base == target and world.gripper == target
    assert world.admissible(point)
    assert world.fingerprint(world.snapshot()) != before
    with pytest.raises(StampcError) as info:
        c.move_base(_ctx(world), _action("move_base", a=far, b="b99"))
    assert info.value.diagnostics[0].code == "S271"


def test_grasps_only_from_where_the_robot_stands(world):
    here = next(n for n, xy in world.scene.robot.bases if xy == world.base)
    reachable = [(o.name, p) for o, (_, p) in zip(world.scene.objects, world.scene.initial_poses)
                 if c.reaches(_ctx(world), here, o.name, p)]
    assert reachable
    o, p = reachable[0]
    assert list(c.grasp_at(_ctx(world), here, o, p))
    other = next(n for n, xy in world.scene.robot.bases if xy != world.base)
    assert list(c.grasp_at(_ctx(world), other, o, p)) == []
    for g, q in c.grasp_at(_ctx(world), here, o, p):
        assert math.dist(q.xy, world.base) <= MOBILE_REACH + 1e-9


def test_reaches_is_geometric(world):
    for name, (x, y) in world.scene.robot.bases:
        halfway = Pose2((x + 0.5) / 2, (y + 0.3) / 2, 0.0)   # towards the table centre
        assert c.reaches(_ctx(world), name, "can0", halfway)
    # a can at the right edge is out of reach from the left base, not from the right one
    assert not c.reaches(_ctx(world), "b2", "can0", Pose2(0.97, 0.3, 0.0))
    assert c.reaches(_ctx(world), "b3", "can0", Pose2(0.97, 0.3, 0.0))


def test_bin_drop_needs_the_can_in_hand(world):
    o = world.scene.objects[0].name
    assert list(c.bin_drop(_ctx(world), o)) == []
    world.move_gripper([world.pose(o).xy])
    world.attach(o)
    (q,), = list(c.bin_drop(_ctx(world), o))
    assert q.xy == world.base and q.target == o
    c.discard(_ctx(world), _action("discard", o=o, q=q))
    assert not world.present(o) and world.held is None
