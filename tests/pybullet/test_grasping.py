"""IK, grasp and placement generators, the reachable evaluator."""

from __future__ import annotations

import inspect
import math
import random

from stampc.worlds.pybullet._pb import p  # pybullet, without its import banner
import pytest

from stampc.diagnostics import StampcError
from stampc.worlds.base import Context
from stampc.worlds.pybullet import open_world
from stampc.worlds.pybullet import manipulation as manip
from stampc.worlds.pybullet.kinematics import solve_ik
from stampc.worlds.pybullet.scenes import cluttered_table, domino_row
from stampc.worlds.pybullet.values import Pose, quat_rotate

POS_TOL, ANG_TOL = 0.005, 0.05


@pytest.fixture(scope="module")
def world():
    w = open_world(cluttered_table(15, seed=2), seed=0)
    yield w
    w.close()


def ctx(world, seed=0, **options):
    return Context(world=world, rng=random.Random(seed), options=options)


def fk(world, q) -> Pose:
    """Forward kinematics straight from PyBullet (independent of the world helpers)."""
    for j, v in zip(world.model.arm_joints, q):
        p.resetJointState(world.robot, j, v, physicsClientId=world.client)
    ls = p.getLinkState(world.robot, world.model.ee_link, computeForwardKinematics=True,
                        physicsClientId=world.client)
    pose = Pose(tuple(ls[4]), tuple(ls[5]))
    world.set_arm(world.state.q)
    return pose


def static_contacts(world, q) -> set[int]:
    """Bodies other than movable objects that the robot penetrates at ``q``."""
    world.set_arm(q)
    p.performCollisionDetection(physicsClientId=world.client)
    hit = {c[2] for c in p.getContactPoints(bodyA=world.robot, physicsClientId=world.client)
           if c[8] < -1e-4}
    world.set_arm(world.state.q)
    return hit - set(world.movable_ids)


def test_ik_reaches_reachable_targets(world):
    """Targets made by forward kinematics of random configs are reachable by design
    (anywhere in the workspace, so harder than tabletop grasps: ~87 % measured)."""
    rng = random.Random(11)
    solved = 0
    for _ in range(40):
        q = [rng.uniform(lo, hi) for lo, hi in zip(world.lower, world.upper)]
        target = fk(world, q)
        sol = solve_ik(world, target, rng)
        if sol is not None:
            solved += 1
            got = fk(world, sol)
            assert got.distance(target) <= POS_TOL and got.angle(target) <= ANG_TOL
            assert all(lo - 1e-9 <= v <= hi + 1e-9
                       for v, lo, hi in zip(sol, world.lower, world.upper))
    world.set_arm(world.state.q)
    assert solved >= 28  # >= 70 %


def _arm_q(world) -> tuple[float, ...]:
    return tuple(p.getJointState(world.robot, j, physicsClientId=world.client)[0]
                 for j in world.model.arm_joints)


def _ik_effects(world, target, rng_seed, seed_q=None):
    """What one IK query does: its answer, where it leaves the arm, and the next draw
    of its RNG (the draws its restarts made show there)."""
    rng = random.Random(rng_seed)
    rng.random()
    q = solve_ik(world, target, rng, seed_q=seed_q)
    return q, _arm_q(world), rng.random()


@pytest.mark.parametrize("reachable", [True, False])
def test_ik_answers_again_with_the_same_effects(reachable, monkeypatch):
    """A repeated IK query is answered from the world's memo with the effects of a
    fresh solve: the same answer, the arm left at the same config, the RNG advanced by
    the same draws. The fresh solve runs in a second world of the same scene whose memo
    is emptied before each query."""
    fresh_world = open_world(cluttered_table(15, seed=2), seed=0)
    memo_world = open_world(cluttered_table(15, seed=2), seed=0)
    calls = {fresh_world.client: 0, memo_world.client: 0}
    real = p.calculateInverseKinematics

    def counted(*args, **kwargs):
        calls[kwargs["physicsClientId"]] += 1
        return real(*args, **kwargs)
    monkeypatch.setattr(p, "calculateInverseKinematics", counted)
    try:
        q = [0.3, 0.2, -0.1, -1.9, 0.1, 2.0, 0.6]
        target = fk(memo_world, q) if reachable else Pose((2.5, 0.0, 0.4))  # out of reach
        first = _ik_effects(memo_world, target, 5)
        assert (first[0] is not None) == reachable
        assert calls[memo_world.client] > 0
        for rng_seed in (5, 6, 5, 6):  # once IK draws restarts, the RNG's state counts
            fresh_world.memo.clear()
            fresh = _ik_effects(fresh_world, target, rng_seed)
            before = calls[memo_world.client]
            assert _ik_effects(memo_world, target, rng_seed) == fresh
            memo_world.set_arm(memo_world.state.q)  # elsewhere: the answer must move it
            fresh_world.set_arm(fresh_world.state.q)
        assert calls[memo_world.client] == before  # the last query: from the memo
    finally:
        fresh_world.close()
        memo_world.close()


def test_grasps_reach_their_target_and_avoid_static_obstacles(world):
    values = world.initial_values()
    for obj in ("can0", "can5", "can9"):
        pose = values[f"pose_{obj}"]
        found = list(manip.grasp(ctx(world), obj, pose))
        assert len(found) >= 3, obj
        assert {g.kind for g, _ in found} >= {"top"}
        for g, q in found:
            assert q.obj == obj and q.pre is not None
            hand = pose.multiply(g.hand)
            got = fk(world, q.q)
            assert got.distance(hand) <= POS_TOL and got.angle(hand) <= ANG_TOL
            pre = fk(world, q.pre)
            assert pre.distance(g.pregrasp(pose)) <= POS_TOL
            # the pre-grasp backs off against the approach direction by the standoff
            assert math.dist(pre.pos, got.pos) == pytest.approx(g.standoff, abs=2 * POS_TOL)
            assert not static_contacts(world, q.q) and not static_contacts(world, q.pre)
            if g.kind == "top":  # hand z axis points down
                assert quat_rotate(got.quat, (0, 0, 1))[2] < -0.99


def test_grasp_is_lazy_and_honours_budget(world):
    pose = world.initial_values()["pose_can4"]
    gen = manip.grasp(ctx(world, budget=2), "can4", pose)
    assert inspect.isgenerator(gen)
    assert len(list(gen)) == 2
    tops = list(manip.grasp(ctx(world, grasps="top"), "can4", pose))
    assert tops and all(g.kind == "top" for g, _ in tops)


def test_grasp_is_deterministic(world):
    pose = world.initial_values()["pose_can6"]
    first = list(manip.grasp(ctx(world, seed=3), "can6", pose))
    again = list(manip.grasp(ctx(world, seed=3), "can6", pose))
    assert first == again


def test_unknown_object_is_a_diagnostic(world):
    with pytest.raises(StampcError) as exc:
        next(manip.grasp(ctx(world), "teapot", Pose.of((0.5, 0, 0.1))))
    assert exc.value.diagnostics[0].code == "PB011"
    with pytest.raises(StampcError) as exc:
        next(manip.placement(ctx(world), "can1", "floor"))
    assert exc.value.diagnostics[0].code == "PB012"


def test_reachable(world):
    near = world.initial_values()["pose_can3"]
    far = Pose.of((2.0, 0.0, 0.1))
    assert manip.reachable(ctx(world), "can3", near)
    assert not manip.reachable(ctx(world), "can3", far)


def test_placements_are_on_the_surface_and_clear_of_other_objects(world):
    surface = world.surfaces["table"]
    geom = world.geometry["can7"]
    c = ctx(world, seed=5, budget=5)
    found = list(manip.placement(c, "can7", "table"))
    assert len(found) == 5
    for pose, q in found:
        x, y, z = pose.pos
        assert abs(x - surface.position[0]) <= surface.size[0] / 2 - geom.footprint
        assert abs(y - surface.position[1]) <= surface.size[1] / 2 - geom.footprint
        # resting on the top: within the IK tolerance plus the placement clearance
        assert z - geom.height / 2 - surface.top == pytest.approx(0.002, abs=POS_TOL)
        for name, other in world.state.poses:
            if name != "can7":
                gap = math.dist(other.pos[:2], pose.pos[:2])
                assert gap >= geom.footprint + world.geometry[name].footprint
        assert q.obj == "can7" and not static_contacts(world, q.q)


def test_placement_uses_the_current_grip(world):
    s0 = world.snapshot()
    try:
        g, q = next(manip.grasp(ctx(world), "can8", world.initial_values()["pose_can8"]))
        world.update(q=q.q)
        grip = world.ee_pose().inverse().multiply(world.object_pose("can8"))
        world.update(held="can8", grip=grip)
        tray, height = world.surfaces["tray"], world.geometry["can8"].height
        for pose, qp in manip.placement(ctx(world, seed=1, budget=3), "can8", "tray"):
            # the pose is where the can comes to rest when the hand at qp lets go: under
            # the hand, upright on the tray, with the heading it is held at
            carried = fk(world, qp.q).multiply(grip)
            assert math.dist(carried.pos[:2], pose.pos[:2]) < 1e-6
            assert pose.pos[2] == pytest.approx(tray.top + height / 2, abs=1e-9)
            assert abs(carried.pos[2] - pose.pos[2]) <= manip.PLACE_CLEARANCE + 0.005
            assert pose.quat[:2] == pytest.approx((0.0, 0.0), abs=1e-12)  # upright
            assert carried.angle(pose) < 0.05  # IK's tolerance: only the tilt differs
            assert all(abs(v - c) <= s / 2 for v, c, s in zip(pose.pos[:2], tray.position,
                                                               tray.size))
    finally:
        world.restore(s0)


def test_dominoes_get_grasps():
    w = open_world(domino_row(6, seed=1), seed=0)
    try:
        pose = w.initial_values()["pose_d2"]
        found = list(manip.grasp(ctx(w), "d2", pose))
        assert found
        for g, q in found:
            got = fk(w, q.q)
            assert got.distance(pose.multiply(g.hand)) <= POS_TOL
    finally:
        w.close()


def test_json_values_are_accepted_and_garbage_is_a_diagnostic(world):
    pose = world.initial_values()["pose_can4"]
    from_json = list(manip.grasp(ctx(world, seed=3, budget=1), "can4", pose.to_json()))
    assert from_json == list(manip.grasp(ctx(world, seed=3, budget=1), "can4", pose))
    with pytest.raises(StampcError) as exc:
        next(manip.grasp(ctx(world), "can4", [1, 2, 3]))
    assert exc.value.diagnostics[0].code == "PB014"


def test_kuka_model_from_the_robot_table():
    w = open_world(cluttered_table(4, seed=0, robot="kuka_iiwa"), seed=0)
    try:
        assert w.model.urdf == "kuka_iiwa/model.urdf" and len(w.lower) == 7
        pose = w.initial_values()["pose_can3"]
        found = list(manip.grasp(ctx(w, budget=2), "can3", pose))
        assert found
        for g, q in found:
            assert fk(w, q.q).distance(pose.multiply(g.hand)) <= POS_TOL
    finally:
        w.close()


def _finger_opening(world) -> list[float]:
    return [p.getJointState(world.robot, j, physicsClientId=world.client)[0]
            for j in world.model.finger_joints]


def test_fingers_close_on_the_held_object_and_open_a_little_to_let_go(world):
    """Holding a can, the fingers stand at its radius (+ FINGER_SLACK) along the closing
    axis; in the retreat from letting it go, at its radius + RELEASE_SLACK; otherwise
    wide open. Wide-open fingers around a held object made collisions no real hand has
    (a Keva plank's neighbour in the next tower)."""
    from stampc.worlds.pybullet.world import FINGER_SLACK, RELEASE_SLACK
    s0 = world.snapshot()
    try:
        radius = world.geometry["can8"].dims[0]
        g, q = next(manip.grasp(ctx(world), "can8", world.initial_values()["pose_can8"]))
        world.update(q=q.q)
        assert _finger_opening(world) == pytest.approx([world.model.finger_open] * 2)
        grip = world.ee_pose().inverse().multiply(world.object_pose("can8"))
        world.update(held="can8", grip=grip)
        assert _finger_opening(world) == pytest.approx([radius + FINGER_SLACK] * 2, abs=3e-3)  # tilt
        world.hits(q.q, "retreat")  # holding: the retreat keeps the grip
        assert _finger_opening(world) == pytest.approx([radius + FINGER_SLACK] * 2, abs=3e-3)  # tilt
        held = _finger_opening(world)[0]
        world.update(held=None, grip=None, released="can8")
        world.hits(q.q, "retreat")
        assert _finger_opening(world)[0] - held == pytest.approx(RELEASE_SLACK - FINGER_SLACK,
                                                                 abs=1e-6)
        assert _finger_opening(world) == pytest.approx([radius + RELEASE_SLACK] * 2, abs=3e-3)
        world.hits(q.q)
        assert _finger_opening(world) == pytest.approx([world.model.finger_open] * 2)
    finally:
        world.restore(s0)
