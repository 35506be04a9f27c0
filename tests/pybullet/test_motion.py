"""Motion planning, the collision evaluator and the pick/place executors."""

from __future__ import annotations

import random

from stampc.worlds.pybullet._pb import p  # pybullet, without its import banner
import pytest

from stampc.diagnostics import StampcError
from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.pybullet import open_world
from stampc.worlds.pybullet import manipulation as manip
from stampc.worlds.pybullet.planning import PlanSettings, plan_path
from stampc.worlds.pybullet.scenes import TABLE, TRAY, cluttered_table
from stampc.worlds.pybullet.values import Pose, interpolate


@pytest.fixture(scope="module")
def clutter():
    w = open_world(cluttered_table(15, seed=1), seed=0)
    yield w
    w.close()


def ctx(world, seed=0, **options):
    return Context(world=world, rng=random.Random(seed), options=options)


def penetrated(world, q, exclude=()) -> set[str]:
    """Names of bodies the robot (or held object) penetrates at ``q`` — raw PyBullet."""
    world.set_arm(q)
    p.performCollisionDetection(physicsClientId=world.client)
    bodies = [world.robot] + ([world.body[world.state.held]] if world.state.held else [])
    hit = set()
    for body in bodies:
        for c in p.getContactPoints(bodyA=body, physicsClientId=world.client):
            if c[8] < -1e-4 and c[2] != world.robot or (c[2] == c[1] == world.robot
                                                          and c[8] < -1e-4):
                hit.add(world.name_of.get(c[2], str(c[2])))
    return hit - set(exclude)


def dense(traj, step=0.004):
    for a, b in zip(traj.configs, traj.configs[1:]):
        yield from interpolate(a, b, step)


def free_grasp_traj(world, objects, seed=0):
    """First (object, grasp config, collision-free trajectory) among ``objects``."""
    values = world.initial_values()
    for obj in objects:
        for _, q in manip.grasp(ctx(world, seed), obj, values[f"pose_{obj}"]):
            traj = next(manip.motion(ctx(world, seed), q))[0]
            if not traj.static_only:
                return obj, q, traj
    raise AssertionError("no collision-free grasp trajectory found")


def test_collision_free_trajectories_are_free_at_fine_resolution(clutter):
    found = 0
    for obj in ("can4", "can6", "can9", "can11", "can13"):
        values = clutter.initial_values()
        for _, q in manip.grasp(ctx(clutter, budget=2), obj, values[f"pose_{obj}"]):
            traj = next(manip.motion(ctx(clutter), q))[0]
            assert traj.start == clutter.state.q and traj.end == q.q
            if traj.static_only:
                continue
            found += 1
            assert traj.target == obj
            for qq in dense(traj):
                assert not penetrated(clutter, qq, exclude=[obj]), obj
            assert manip.blocking_objects(ctx(clutter), traj) == frozenset()
    clutter.set_arm(clutter.state.q)
    assert found >= 3


def test_offered_trajectories_pass_the_execution_recheck(clutter):
    """What refinement accepts, ``stampc execute`` re-sweeps in the same state: the final
    check samples every configuration the re-check does (a graze 0.13 mm deep between
    coarser final-check samples once passed refinement and failed execution)."""
    from stampc.execute.recheck import pybullet_recheck

    checked = 0
    for obj in ("can2", "can4", "can6", "can9", "can11", "can13"):
        values = clutter.initial_values()
        for _, q in manip.grasp(ctx(clutter, budget=3), obj, values[f"pose_{obj}"]):
            traj = next(manip.motion(ctx(clutter), q))[0]
            if traj.static_only:
                continue
            checked += 1
            assert pybullet_recheck(clutter, ConcreteAction("pick", {"t": traj})) == [], obj
    assert checked >= 3


def _nearest(world, a: int, b: int) -> float:
    """Bullet's distance between bodies ``a`` and ``b`` (inf beyond 5 cm)."""
    points = p.getClosestPoints(a, b, 0.05, physicsClientId=world.client)
    return min((c[8] for c in points), default=float("inf"))


def _bisect(put, gap: float) -> None:
    """Call ``put(offset)`` (which moves a body and returns its distance to the robot)
    at the offset in [0, 0.3] m where that distance is just under ``gap``."""
    lo, hi = 0.0, 0.3  # lo nearer than gap, hi farther
    for _ in range(40):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if put(mid) < gap else (lo, mid)
    put(lo)


def _can_near_hand(world, name: str, gap: float) -> None:
    """Stand can ``name`` (in the air, at the hand's height) beside the hand, just under
    ``gap`` (m) from the robot by Bullet's measure."""
    hand = p.getLinkState(world.robot, world.model.ee_link, physicsClientId=world.client)[4]

    def put(offset: float) -> float:
        at = Pose((hand[0], hand[1] - offset, hand[2]), (0.0, 0.0, 0.0, 1.0))
        world.update(poses=tuple((n, at if n == name else x) for n, x in world.state.poses))
        return _nearest(world, world.robot, world.body[name])

    _bisect(put, gap)


def _static_under_hand(world, body: int, gap: float) -> None:
    """Raise static ``body`` (straight up from where it stands) until it is just under
    ``gap`` (m) from the robot: statics are moved by hand here, no state holds them."""
    pos, quat = p.getBasePositionAndOrientation(body, physicsClientId=world.client)
    top = p.getAABB(body, physicsClientId=world.client)[1][2]
    hand = p.getLinkState(world.robot, world.model.ee_link, physicsClientId=world.client)[4]

    def put(offset: float) -> float:
        z = pos[2] + (hand[2] - offset - top)  # its top ``offset`` below the hand's origin
        p.resetBasePositionAndOrientation(body, (pos[0], pos[1], z), quat,
                                          physicsClientId=world.client)
        return _nearest(world, world.robot, body)

    _bisect(put, gap)


def test_planning_keeps_a_clearance_from_movable_objects_and_the_recheck_does_not():
    """A can 0.5 mm from the hand is a hit for planning (1 mm clearance: a settled can
    moves by a hair and Bullet's near-contact distances move more) but not for the
    re-check, which counts penetration of a movable object at any depth."""
    from stampc.execute.recheck import pybullet_recheck
    from stampc.worlds.pybullet.planning import bad_bodies
    from stampc.worlds.pybullet.values import Traj
    from stampc.worlds.pybullet.world import CLEARANCE, PENETRATION

    assert CLEARANCE > 5 * PENETRATION
    with open_world(cluttered_table(15, seed=1), seed=0) as world:
        q = world.state.q
        world.set_arm(q)
        _can_near_hand(world, "can0", CLEARANCE / 2)
        gap = _nearest(world, world.robot, world.body["can0"])
        assert 0 < gap < CLEARANCE
        can = world.body["can0"]
        assert can in bad_bodies(world, q, "middle", None, None, None)
        assert can not in bad_bodies(world, q, "middle", None, None, None, clearance=0.0)
        assert can not in world.hits(q)[0] and can in world.hits(q, clearance=CLEARANCE)[0]
        traj = Traj((q, q), None, None, None)
        assert "can0" not in pybullet_recheck(world, ConcreteAction("move", {"t": traj}))
        _can_near_hand(world, "can0", -PENETRATION / 2)  # in, within statics' tolerance
        assert "can0" in pybullet_recheck(world, ConcreteAction("move", {"t": traj}))
        _can_near_hand(world, "can0", -3 * PENETRATION)  # deeper
        assert "can0" in pybullet_recheck(world, ConcreteAction("move", {"t": traj}))


def test_a_static_body_gets_no_clearance_only_the_resting_tolerance():
    """The table 0.5 mm under the robot is no hit, with or without the clearance
    (statics never move: their planned geometry is what execution meets); 0.05 mm into
    it, within the resting-contact tolerance, neither; 0.3 mm into it, a hit for both."""
    from stampc.worlds.pybullet.world import CLEARANCE, PENETRATION

    with open_world(cluttered_table(15, seed=1), seed=0) as world:
        q = world.state.q
        world.set_arm(q)
        table = next(b for b in world.static_ids if world.name_of.get(b) == "table")
        for gap, hit in ((CLEARANCE / 2, False), (-PENETRATION / 2, False),
                         (-3 * PENETRATION, True)):
            _static_under_hand(world, table, gap)
            assert gap - 1e-4 < _nearest(world, world.robot, table) < gap
            assert (table in world.hits(q, clearance=CLEARANCE)[0]) == hit
            assert (table in world.hits(q)[0]) == hit


def test_blocked_target_falls_back_and_names_blockers(clutter):
    scene = cluttered_table(15, seed=1)
    target, blockers = scene["meta"]["target"], set(scene["meta"]["blockers"])
    s0 = clutter.snapshot()
    try:
        g, q = next(manip.grasp(ctx(clutter), target, clutter.initial_values()["pose_can0"]))
        trajs = [t for (t,) in manip.motion(ctx(clutter, budget=2), q)]
        assert trajs and all(t.static_only for t in trajs)
        c = ctx(clutter)
        blocking = manip.blocking_objects(c, trajs[0])
        assert blocking and blocking & blockers and target not in blocking
        # one sweep answers every collision(x, t) query
        checks = clutter.checks
        answers = {x: manip.collision(c, x, trajs[0]) for x in clutter.movable_names()}
        assert clutter.checks == checks
        assert {x for x, hit in answers.items() if hit} == blocking
        # the engine's reaction: move the blockers away, then a free path exists
        poses = dict(clutter.state.poses)
        for i, name in enumerate(sorted(blocking)):
            poses[name] = Pose.of((-0.6, -0.4 + 0.1 * i, 0.1))
        clutter.update(poses=tuple(poses.items()))
        replanned = next(manip.motion(ctx(clutter), q))[0]
        assert not replanned.static_only
        assert manip.blocking_objects(ctx(clutter), replanned) == frozenset()
    finally:
        clutter.restore(s0)


def test_the_motion_generator_sweep_answers_the_collision_evaluator(clutter):
    """The evaluator takes the bodies the generator's own check of a trajectory met
    (every configuration checked once) instead of sweeping it again: exactly what a
    fresh sweep in the same state finds, for static-only paths through the blockers and
    for free ones."""
    scene = cluttered_table(15, seed=1)
    values = clutter.initial_values()
    kinds = set()
    for obj in (scene["meta"]["target"], "can4", "can9"):
        for _, q in manip.grasp(ctx(clutter, budget=2), obj, values[f"pose_{obj}"]):
            shared = ctx(clutter, budget=2)  # one context: the concretizer's per-node cache
            for (traj,) in manip.motion(shared, q):
                checks = clutter.checks
                remembered = manip.blocking_objects(shared, traj)
                assert clutter.checks == checks  # answered without a sweep
                assert remembered == manip.blocking_objects(ctx(clutter), traj)
                assert clutter.checks > checks  # the fresh context did sweep
                kinds.add((traj.static_only, bool(remembered)))
    assert {(True, True), (False, False)} <= kinds


def _hand_xyz(world, q):
    world.set_arm(q)
    return p.getLinkState(world.robot, 8, computeForwardKinematics=True,
                          physicsClientId=world.client)[4]


def test_obstruction_names_exactly_the_objects_in_the_corridor():
    base = {"robot": {"model": "panda"}, "surfaces": [TABLE, TRAY],
            "objects": [{"name": "goal", "shape": "cylinder", "radius": 0.03,
                         "height": 0.12, "position": [0.6, 0.0, 0.06]}]}
    empty = open_world(base, seed=0)
    try:
        pose = empty.initial_values().get("pose_goal") or Pose.of((0.6, 0.0, 0.06))
        _, q = next(manip.grasp(ctx(empty), "goal", pose))
        traj = next(manip.motion(ctx(empty), q))[0]
        assert not traj.static_only
        pillars = []
        for name, frac in (("pillar_a", 0.3), ("pillar_b", 0.75)):
            i = traj.retreat_end
            a, b = traj.configs[i], traj.configs[i + 1]
            x, y, z = _hand_xyz(empty, [u + frac * (v - u) for u, v in zip(a, b)])
            pillars.append({"name": name, "shape": "box", "size": [0.06, 0.06, z + 0.05],
                            "position": [x, y, (z + 0.05) / 2], "mass": 1.0})
    finally:
        empty.close()
    decoys = [{"name": f"decoy{i}", "shape": "cylinder", "radius": 0.03, "height": 0.15,
               "position": [x, y, 0.075]}
              for i, (x, y) in enumerate([(0.4, 0.3), (0.45, -0.3), (0.72, 0.28)])]
    world = open_world({**base, "objects": base["objects"] + pillars + decoys}, seed=0)
    try:
        # precondition, checked independently: the decoys stay well clear of the arm
        for qq in dense(traj, 0.02):
            world.set_arm(qq)
            for d in decoys:
                assert not p.getClosestPoints(world.robot, world.body[d["name"]], 0.02,
                                              physicsClientId=world.client)
        world.set_arm(world.state.q)
        c = ctx(world)
        assert manip.blocking_objects(c, traj) == {"pillar_a", "pillar_b"}
        assert manip.collision(c, "pillar_a", traj) and not manip.collision(c, "decoy1", traj)
        assert not manip.collision(c, "goal", traj)  # the target never counts
        assert not manip.trajectory_free(c, traj)
        # replanning here either avoids the pillars or blames only them
        other = next(manip.motion(ctx(world), q))[0]
        if other.static_only:
            assert manip.blocking_objects(ctx(world), other) <= {"pillar_a", "pillar_b"}
        else:
            assert manip.trajectory_free(ctx(world), other)
    finally:
        world.close()


def test_pick_move_place_cycle(clutter):
    s0 = clutter.snapshot()
    try:
        obj, q, traj = free_grasp_traj(clutter, ["can5", "can8", "can10", "can12"])
        pose0 = clutter.object_pose(obj)
        args = {"o": obj, "p": pose0, "g": None, "q": q, "t": traj}
        # a slip: the robot moves, the object stays
        manip.pick(ctx(clutter), ConcreteAction("pick", args, outcome=1))
        assert clutter.state.q == q.q and clutter.state.held is None
        assert clutter.object_pose(obj) == pose0
        clutter.restore(s0)
        manip.pick(ctx(clutter), ConcreteAction("pick", args, adds=(("holding", (obj,)),)))
        assert clutter.state.held == obj
        assert clutter.ee_pose().multiply(clutter.state.grip).distance(pose0) < 1e-6
        # the held object follows the hand
        clutter.set_arm(q.pre)
        body_pos = p.getBasePositionAndOrientation(clutter.body[obj],
                                                   physicsClientId=clutter.client)[0]
        assert body_pos[2] > pose0.pos[2] + 0.05
        clutter.set_arm(clutter.state.q)
        pose, qp = next(manip.placement(ctx(clutter, seed=2), obj, "tray"))
        carry = next(manip.motion(ctx(clutter), qp))[0]
        assert carry.held == obj and not carry.static_only
        for qq in dense(carry):
            assert not penetrated(clutter, qq, exclude=["table", "tray"]), qq
        place_args = {"o": obj, "s": "tray", "p": pose, "q": qp, "t": carry}
        manip.place(ctx(clutter), ConcreteAction("place", place_args))  # not added: kept
        assert clutter.state.held == obj
        manip.place(ctx(clutter), ConcreteAction("place", place_args,
                                                 adds=(("at", (obj, pose)),)))
        assert clutter.state.held is None and clutter.object_pose(obj) == pose
        got = p.getBasePositionAndOrientation(clutter.body[obj], physicsClientId=clutter.client)
        assert got[0] == pytest.approx(pose.pos, abs=1e-9)
        # the next motion starts by backing off from the placed object
        nxt_obj, nxt_q, nxt = free_grasp_traj(clutter, ["can7", "can13", "can14"])
        assert nxt.released == obj and nxt.retreat_end == 1 and nxt.configs[1] == qp.pre
    finally:
        clutter.restore(s0)


def test_planning_is_deterministic_and_planner_selectable(clutter):
    rng_q = random.Random(4)
    start = clutter.state.q
    goal = tuple(v + rng_q.uniform(-1.0, 1.0) for v in start)
    assert not penetrated(clutter, goal)
    settings = PlanSettings(straight=False, shortcut=False)
    a = plan_path(clutter, start, goal, random.Random(9), settings)
    b = plan_path(clutter, start, goal, random.Random(9), settings)
    assert a is not None and a == b and len(a) > 2
    k = plan_path(clutter, start, goal, random.Random(9), PlanSettings(planner="KPIECE1",
                                                                       straight=False))
    assert k is not None and k[0] == start and k[-1] == goal
    with pytest.raises(StampcError) as exc:
        plan_path(clutter, start, goal, random.Random(9), PlanSettings(planner="Teleport",
                                                                       straight=False))
    assert exc.value.diagnostics[0].code == "PB020"
    clutter.set_arm(clutter.state.q)


def test_drop_and_discard(clutter):
    s0 = clutter.snapshot()
    try:
        obj, q, traj = free_grasp_traj(clutter, ["can5", "can8", "can10", "can12"])
        manip.pick(ctx(clutter), ConcreteAction("pick", {"o": obj, "q": q, "t": traj},
                                                adds=(("holding", (obj,)),)))
        pose, qp = next(manip.placement(ctx(clutter, seed=4), obj, "table"))
        carried = clutter.ee_pose().multiply(clutter.state.grip)
        # the outcome only deletes holding: let go where the hand is (here: the grasp pose)
        manip.place(ctx(clutter), ConcreteAction("place", {"o": obj, "p": pose, "q": q},
                                                 deletes=(("holding", (obj,)),)))
        assert clutter.state.held is None
        assert clutter.object_pose(obj).distance(carried) < 1e-9
        # discard: the object leaves the scene and no longer blocks anything
        other = next(n for n in ("can0", "can1", "can2") if n != obj)
        before = clutter.object_pose(other)
        manip.discard(ctx(clutter), ConcreteAction("discard", {"o": other}))
        assert not clutter.present(other)
        pos = p.getBasePositionAndOrientation(clutter.body[other],
                                              physicsClientId=clutter.client)[0]
        assert pos[2] < -50
        clutter.restore(s0)
        pos = p.getBasePositionAndOrientation(clutter.body[other],
                                              physicsClientId=clutter.client)[0]
        assert pos == pytest.approx(before.pos) and clutter.present(other)
    finally:
        clutter.restore(s0)


def _link_position(world, link: int) -> tuple[float, ...]:
    return tuple(p.getLinkState(world.robot, link, physicsClientId=world.client)[0])


def test_the_arm_folded_into_what_it_puts_down_is_noticed(clutter):
    """``arm_meets``: a can standing where an arm link is, at the current config, meets
    the arm; one between the fingertips (where a held can is) does not, and one far away
    does not; the can's own pose is left as it was. The placement generator refuses
    configs that meet it (manipulation._place_config)."""
    from stampc.worlds.pybullet.kinematics import arm_meets
    from stampc.worlds.pybullet.world import CLEARANCE

    world = clutter
    world.select()
    world.set_arm(world.model.rest)
    name = world.movable_names()[0]
    before = world.object_pose(name)
    elbow = Pose(_link_position(world, 3))  # panda_link4: the elbow
    between_fingers = Pose(_link_position(world, world.model.ee_link))
    far = Pose((before.pos[0], before.pos[1], before.pos[2] + 3.0))
    assert arm_meets(world, name, elbow, CLEARANCE)
    assert not arm_meets(world, name, between_fingers, 0.0)
    assert not arm_meets(world, name, far, CLEARANCE)
    actual = p.getBasePositionAndOrientation(world.body[name], physicsClientId=world.client)
    assert actual[0] == pytest.approx(before.pos, abs=1e-9)
    # every placement the generator offers stands clear of the arm at its config
    offered = list(manip.placement(ctx(world, 3, budget=6), name, TABLE["name"]))
    assert offered
    for rest, q in offered:
        world.set_arm(q.q)
        assert not arm_meets(world, name, rest, CLEARANCE)
    world.set_arm(world.state.q)
