"""The free-flying UAV: flights into regions, battery evaluator and executors."""

from __future__ import annotations

import math
import random

from stampc.worlds.pybullet._pb import p  # pybullet, without its import banner
import pytest

from stampc.diagnostics import StampcError
from stampc.worlds.base import ConcreteAction, Context
from stampc.worlds.pybullet import open_world
from stampc.worlds.pybullet import aerial
from stampc.worlds.pybullet.scenes import aircraft
from stampc.worlds.pybullet.values import Pose, Traj


@pytest.fixture(scope="module")
def world():
    w = open_world(aircraft(seed=2, battery=40.0), seed=0)
    yield w
    w.close()


def ctx(world, seed=0, **options):
    return Context(world=world, rng=random.Random(seed), options=options)


def clear_of_everything(world, pose7, margin=0.0) -> bool:
    """Independent check with getClosestPoints against every other body."""
    p.resetBasePositionAndOrientation(world.uav, pose7[:3], pose7[3:],
                                      physicsClientId=world.client)
    for body in world.static_ids | world.movable_ids:
        if any(c[8] < -1e-4 for c in p.getClosestPoints(world.uav, body, margin,
                                                        physicsClientId=world.client)):
            return False
    return True


@pytest.mark.parametrize("region", ["left_wing", "tail", "nose"])
def test_flights_end_inside_the_region_without_collisions(world, region):
    flights = list(aerial.fly(ctx(world, budget=2), region))
    assert flights
    box = world.regions[region]
    for goal, traj in flights:
        assert box.contains(goal.pos)
        assert traj.configs[0][:3] == pytest.approx(world.state.uav.pos)
        assert traj.end[:3] == pytest.approx(goal.pos)
        for a, b in zip(traj.configs, traj.configs[1:]):
            n = max(1, math.ceil(math.dist(a[:3], b[:3]) / 0.05))
            for i in range(n + 1):
                pos = tuple(x + (y - x) * i / n for x, y in zip(a[:3], b[:3]))
                assert clear_of_everything(world, pos + tuple((a if i < n / 2 else b)[3:]))
    p.resetBasePositionAndOrientation(world.uav, world.state.uav.pos, world.state.uav.quat,
                                      physicsClientId=world.client)


def test_flight_under_the_wings_goes_around_the_fuselage(world):
    start = Pose.of((0.3, -1.0, 1.0))
    goal = Pose.of((0.3, 1.0, 1.0))  # the fuselage (|y| < 0.5, 1 < z < 2) is in between
    path = aerial.plan_flight(world, start, goal, random.Random(3))
    assert path is not None
    traj = Traj(tuple(path))
    assert traj.start[:3] == pytest.approx(start.pos) and traj.end[:3] == pytest.approx(goal.pos)
    assert aerial.path_length(traj) > math.dist(start.pos, goal.pos) + 0.05
    assert aerial.flight_free(world, traj)
    for a, b in zip(traj.configs, traj.configs[1:]):
        n = max(1, math.ceil(math.dist(a[:3], b[:3]) / 0.05))
        for i in range(n + 1):
            pos = tuple(x + (y - x) * i / n for x, y in zip(a[:3], b[:3]))
            assert clear_of_everything(world, pos + tuple((a if i < n / 2 else b)[3:]))
    world.restore(world.snapshot())


def test_battery_evaluator_and_executors(world):
    s0 = world.snapshot()
    try:
        _, traj = next(aerial.fly(ctx(world), "tail"))
        length = aerial.path_length(traj)
        assert length == pytest.approx(sum(math.dist(a[:3], b[:3])
                                           for a, b in zip(traj.configs, traj.configs[1:])))
        assert aerial.has_battery(ctx(world), traj)
        world.update(battery=length * 0.9)
        assert not aerial.has_battery(ctx(world), traj)
        world.update(battery=40.0)
        aerial.fly_to(ctx(world), ConcreteAction("fly", {"t": traj}))
        assert world.state.battery == pytest.approx(40.0 - length)
        assert world.regions["tail"].contains(world.state.uav.pos)
        got = p.getBasePositionAndOrientation(world.uav, physicsClientId=world.client)[0]
        assert got == pytest.approx(world.state.uav.pos)
        aerial.charge(ctx(world), ConcreteAction("charge", {}))
        assert world.state.battery == 40.0
        # a drift: the outcome says the UAV ended up about the nose instead
        _, to_wing = next(aerial.fly(ctx(world), "left_wing"))
        aerial.fly_to(ctx(world), ConcreteAction("fly", {"t": to_wing},
                                                 adds=(("at", ("uav", "nose")),)))
        assert world.regions["nose"].contains(world.state.uav.pos)
    finally:
        world.restore(s0)


def test_bad_arguments_are_diagnostics(world):
    with pytest.raises(StampcError) as exc:
        next(aerial.fly(ctx(world), "moon"))
    assert exc.value.diagnostics[0].code == "PB031"
    with pytest.raises(StampcError) as exc:
        aerial.fly_to(ctx(world), ConcreteAction("fly", {"t": "nowhere"}))
    assert exc.value.diagnostics[0].code == "PB032"
    assert isinstance(Traj(((0.0,) * 7,)).end, tuple)


def test_inspect_changes_nothing(world):
    s0 = world.snapshot()
    aerial.inspect(ctx(world), ConcreteAction("inspect", {}))
    assert world.snapshot() == s0


def test_planned_flights_are_clear_at_the_execution_recheck_resolution():
    """From the aircraft example's station into ``left_wing`` (RNG seed 3), OMPL's 5 cm
    motion check passes a straight flight that grazes a body between two checked poses;
    ``stampc execute`` sweeps every 5 mm and would count a collision. The planner now
    sweeps each flight at that resolution and offers only clear ones."""
    from examples.aircraft_inspection.scene import build
    from stampc.execute.recheck import REFINE

    assert aerial.EXEC_RESOLUTION == aerial.FLY_RESOLUTION / REFINE
    with open_world(build(0, battery=26, n_scaffolds=3, variant="mid"), seed=0) as w:
        flights = list(aerial.fly(ctx(w, seed=3), "left_wing"))
        assert flights
        for _, traj in flights:
            assert not aerial.flight_contacts(w, traj, aerial.FLY_RESOLUTION / REFINE)
