"""PyBullet execution: physics settles what actions let go of (a discarded can lands in
the tray), deterministically; frames follow every motion (real PyBullet, DIRECT)."""

from __future__ import annotations

import pytest

from stampc.execute.frames import PER_MOTION, Recorder
from stampc.worlds.base import ConcreteAction
from stampc.worlds.pybullet import open_world
from stampc.worlds.pybullet.physics import Physics
from stampc.worlds.pybullet.values import Pose, Traj

SCENE = {
    "robot": {"model": "panda", "base": [0, 0, 0]},
    "surfaces": [{"name": "table", "size": [0.6, 0.8, 0.04], "position": [0.5, 0, 0.18]},
                 {"name": "tray", "size": [0.2, 0.2, 0.02], "position": [0.2, 0.45, 0.05]}],
    "objects": [{"name": "can", "shape": "cylinder", "radius": 0.03, "height": 0.1,
                 "position": [0.45, 0.0, 0.252], "mass": 0.1},
                {"name": "other", "shape": "cylinder", "radius": 0.03, "height": 0.1,
                 "position": [0.55, 0.1, 0.252], "mass": 0.1}],
}
TRAY_TOP = 0.06


def test_a_discarded_can_lands_in_the_tray() -> None:
    with open_world(SCENE, seed=0) as world:
        physics = Physics(world)
        world.update(poses=world.with_object_pose("can", Pose((0.2, 0.45, 0.3))))
        physics.before_action(world, None)  # thrown away from 0.3 m above the tray
        world.update(removed=world.state.removed | {"can"})
        physics.after_action(world, None)
        rest = physics.resting["can"]
        assert abs(rest.pos[0] - 0.2) < 0.1 and abs(rest.pos[1] - 0.45) < 0.1
        assert rest.pos[2] == pytest.approx(TRAY_TOP + 0.05, abs=0.01)  # upright on it
        assert world.object_pose("other").pos == (0.55, 0.1, 0.252)  # untouched: frozen


def test_a_placed_can_settles_on_the_table_deterministically() -> None:
    finals = []
    for _ in range(2):
        with open_world(SCENE, seed=0) as world:
            physics = Physics(world)
            physics.before_action(world, None)
            world.update(poses=world.with_object_pose("can", Pose((0.4, -0.1, 0.3))))
            physics.after_action(world, None)
            finals.append(world.object_pose("can"))
    assert finals[0] == finals[1]
    assert finals[0].pos[2] == pytest.approx(0.2 + 0.05, abs=0.005)  # on the table top


def test_frames_follow_each_motion(tmp_path) -> None:
    with open_world(SCENE, seed=0) as world:
        recorder = Recorder(tmp_path)
        q0 = world.state.q
        q1 = tuple(v + 0.3 for v in q0)
        traj = Traj((q0, q1))
        recorder.motion(world, ConcreteAction("move", {"t": traj.to_json()}))
        assert len(recorder.frames) >= PER_MOTION
        assert not (recorder.frames[0] == recorder.frames[-1]).all()  # the arm moved
        assert world.state.q == q0


def test_an_object_the_hand_sets_down_turned_is_placed_not_toppled() -> None:
    """A Keva put stands a plank upright: its up axis turns by 90°, but it was held, so
    physics settles it where it was put (it must not fall from where it was picked)."""
    upright = Pose((0.45, 0.0, 0.252), (0.7071067811865476, 0.0, 0.0, 0.7071067811865476))
    with open_world(SCENE, seed=0) as world:
        physics = Physics(world)
        world.update(held="can", grip=world.ee_pose().inverse().multiply(
            world.object_pose("can")))
        physics.before_action(world, None)
        world.update(held=None, grip=None, released="can",
                     poses=world.with_object_pose("can", Pose((0.4, -0.1, 0.231),
                                                              upright.quat)))
        physics.after_action(world, None)
        rest = world.object_pose("can")
        assert abs(rest.pos[0] - 0.4) < 0.01 and abs(rest.pos[1] + 0.1) < 0.01
        assert rest.pos[2] == pytest.approx(0.2 + 0.03, abs=0.005)  # lying on its side
