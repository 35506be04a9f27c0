"""Scene validation, seeded scene builders, world state snapshot/restore."""

from __future__ import annotations

import itertools
import math
import random

from stampc.worlds.pybullet._pb import p  # pybullet, without its import banner
import pytest

from stampc.diagnostics import StampcError
from stampc.worlds.base import Context, World
from stampc.worlds.pybullet import open_world
from stampc.worlds.pybullet import manipulation as manip
from stampc.worlds.pybullet.scene_check import parse_scene
from stampc.worlds.pybullet.scenes import TABLE, aircraft, cluttered_table, domino_row
from stampc.worlds.pybullet.values import Pose, quat_from_yaw


@pytest.fixture(scope="module")
def world():
    w = open_world(cluttered_table(8, seed=4), seed=0)
    yield w
    w.close()


# ------------------------------------------------------------------ validation
def _codes_and_lines(scene) -> list[tuple[str, str, int, str]]:
    with pytest.raises(StampcError) as exc:
        parse_scene(scene)
    return [(d.code, d.span.file, d.span.line, d.message) for d in exc.value.diagnostics]


def test_bad_scene_entries_are_located():
    diags = _codes_and_lines({
        "robot": {"model": "panda"},
        "objects": [
            {"name": "a", "shape": "cylinder", "radius": 0.03, "height": 0.1,
             "position": [0, 0, 0]},
            {"name": "b", "shape": "cone", "position": [0, 0, 0]},
            {"name": "a", "shape": "box", "size": [0.1, 0.1, 0.1], "position": [1, 0, 0]},
            {"name": "c", "shape": "box", "size": [0.1, -1, 0.1], "position": [1, 0]},
        ],
        "poses": {"pose_a": "a", "pose_z": "zzz"},
    })
    assert all(code == "PB001" for code, *_ in diags)
    at = {(file, line): msg for _, file, line, msg in diags}
    assert "unknown shape" in at[("<scene objects>", 2)]
    assert "duplicate name 'a'" in at[("<scene objects>", 3)]
    line4 = [msg for _, file, line, msg in diags if (file, line) == ("<scene objects>", 4)]
    assert any("size" in m for m in line4) and any("position" in m for m in line4)
    assert "zzz" in at[("<scene poses>", 2)]
    assert ("<scene objects>", 1) not in at


@pytest.mark.parametrize("scene, fragment", [
    ([1, 2], "JSON object"),
    ({"robot": {"model": "r2d2"}}, "unknown robot model"),
    ({"surfaces": []}, "needs a 'robot' or a 'uav'"),
    ({"robot": {}, "lights": 3}, "unknown scene key"),
    ({"uav": {"position": [0, 0, 1], "bounds": {"low": [0, 0, 0], "high": [1, 1, 0]}}},
     "below 'high'"),
])
def test_scene_errors(scene, fragment):
    assert any(fragment in msg for *_, msg in _codes_and_lines(scene))


def test_missing_urdf_is_a_diagnostic():
    scene = {"robot": {}, "objects": [{"name": "x", "urdf": "no/such.urdf",
                                       "position": [0.5, 0, 0.1]}]}
    with pytest.raises(StampcError) as exc:
        open_world(scene, seed=0)
    assert exc.value.diagnostics[0].code == "PB002"


def test_world_protocol_and_package(world):
    assert isinstance(world, World)
    assert world.package == "stampc.worlds.pybullet"


def test_manipulation_needs_an_arm():
    w = open_world(aircraft(0), seed=0)
    try:
        ctx = Context(world=w, rng=random.Random(0))
        with pytest.raises(StampcError) as exc:
            next(manip.grasp(ctx, "uav", Pose.of((0, 0, 1))))
        assert exc.value.diagnostics[0].code == "PB010"
    finally:
        w.close()


# ------------------------------------------------------------------ scene builders
@pytest.mark.parametrize("builder", [
    lambda s: cluttered_table(15, s), lambda s: domino_row(10, s), lambda s: aircraft(s)])
def test_builders_are_reproducible_and_valid(builder):
    assert builder(3) == builder(3)
    assert builder(3) != builder(4)
    parse_scene(builder(3))


@pytest.mark.parametrize("seed", range(5))
def test_cluttered_table_cans_do_not_overlap_and_stand_on_the_table(seed):
    scene = cluttered_table(25, seed)
    cans = scene["objects"]
    assert len(cans) + scene["meta"]["dropped"] == 25
    assert len(cans) >= 20
    for a, b in itertools.combinations(cans, 2):
        assert math.dist(a["position"][:2], b["position"][:2]) >= a["radius"] + b["radius"]
    (cx, cy, _), (sx, sy, _) = TABLE["position"], TABLE["size"]
    for can in cans:
        x, y, z = can["position"]
        assert abs(x - cx) <= sx / 2 - can["radius"] and abs(y - cy) <= sy / 2 - can["radius"]
        assert z == pytest.approx(can["height"] / 2, abs=1e-4)  # resting on the top (z = 0)
        assert 0.12 <= can["height"] <= 0.2
    assert set(scene["poses"].values()) == {c["name"] for c in cans}


def test_blockers_stand_next_to_the_target_between_it_and_the_robot():
    scene = cluttered_table(10, 7)
    pos = {o["name"]: o["position"] for o in scene["objects"]}
    target = pos[scene["meta"]["target"]]
    assert len(scene["meta"]["blockers"]) == 3
    for name in scene["meta"]["blockers"]:
        assert math.dist(pos[name][:2], target[:2]) < 0.08
        assert math.hypot(*pos[name][:2]) < math.hypot(*target[:2])
    assert cluttered_table(10, 7, obstruct_target=False)["meta"]["blockers"] == []


# ------------------------------------------------------------------ state
def _body_pose(world, name):
    pos, quat = p.getBasePositionAndOrientation(world.body[name], physicsClientId=world.client)
    return pos, quat


def _arm(world):
    return tuple(s[0] for s in p.getJointStates(world.robot, world.model.arm_joints,
                                                 physicsClientId=world.client))


def test_initial_values_are_the_scene_poses(world):
    values = world.initial_values()
    for obj in world.spec.objects:
        pose = values[f"pose_{obj.name}"]
        assert pose.pos == pytest.approx(obj.position)
        assert pose.quat == pytest.approx(quat_from_yaw(obj.yaw))
        assert _body_pose(world, obj.name)[0] == pytest.approx(obj.position)


def test_snapshot_restore_is_exact(world):
    s0 = world.snapshot()
    arm0 = _arm(world)
    poses0 = {n: _body_pose(world, n) for n in world.body}
    # change everything: arm, an object's pose, an attachment
    world.update(q=tuple(v + 0.3 for v in s0.q))
    world.update(poses=world.with_object_pose("can2", Pose.of((0.4, 0.3, 0.1))))
    grip = world.ee_pose().inverse().multiply(world.object_pose("can3"))
    world.update(held="can3", grip=grip)
    world.set_arm(tuple(v - 0.2 for v in s0.q))
    assert _body_pose(world, "can3")[0] != pytest.approx(poses0["can3"][0], abs=1e-3)
    s1 = world.snapshot()
    world.restore(s0)
    assert world.snapshot() == s0
    assert _arm(world) == pytest.approx(arm0, abs=1e-9)
    for name, (pos, quat) in poses0.items():
        got = _body_pose(world, name)
        assert got[0] == pytest.approx(pos, abs=1e-9) and got[1] == pytest.approx(quat, abs=1e-9)
    # and back again: the held object follows the hand in s1
    world.restore(s1)
    assert world.state.held == "can3"
    expected = world.ee_pose().multiply(grip)
    assert _body_pose(world, "can3")[0] == pytest.approx(expected.pos, abs=1e-6)
    world.restore(s0)


def test_scene_from_a_json_file(tmp_path):
    import json

    path = tmp_path / "scene.json"
    path.write_text(json.dumps(cluttered_table(3, seed=1)))
    w = open_world(path, seed=0)
    try:
        assert set(w.initial_values()) == {"pose_can0", "pose_can1", "pose_can2"}
    finally:
        w.close()
    (tmp_path / "bad.json").write_text("{oops")
    for bad in (tmp_path / "bad.json", tmp_path / "missing.json"):
        with pytest.raises(StampcError) as exc:
            open_world(bad, seed=0)
        assert exc.value.diagnostics[0].code == "PB003"
    with pytest.raises(StampcError):
        open_world(cluttered_table(3, seed=1), seed="x")
