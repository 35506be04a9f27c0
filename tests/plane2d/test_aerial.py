"""UAV bound functions on the aircraft scene."""

from __future__ import annotations

import math

import pytest

from stampc.diagnostics import StampcError
from stampc.worlds.base import ConcreteAction
from stampc.worlds.plane2d import Pose2, Traj2, open_world
from stampc.worlds.plane2d import aerial as a
from stampc.worlds.plane2d.geometry import Disc, distance
from stampc.worlds.plane2d.scenes import aircraft

from .conftest import corridor_scene, make_ctx


@pytest.fixture
def hangar():
    return open_world(aircraft(seed=3, obstacles=6, battery=5.0), seed=0)


def _clear_of_obstacles(w, t: Traj2, r: float, samples: int = 60) -> bool:
    for p, q in zip(t.points, t.points[1:]):
        for k in range(samples + 1):
            x, y = p[0] + (q[0] - p[0]) * k / samples, p[1] + (q[1] - p[1]) * k / samples
            if any(distance(Disc(x, y, r), s) < -1e-9 for s in w.scene.static_shapes()):
                return False
    return True


@pytest.mark.parametrize("region", ["left_wing", "right_wing", "fuselage", "tail"])
def test_fly_yields_poses_in_region_and_clear_paths(hangar, region):
    ctx = make_ctx(hangar, 1, budget=3)
    rect = hangar.region(region)
    r = hangar.scene.uav.radius
    results = list(a.fly(ctx, region))
    assert len(results) == 3
    for pose, t in results:
        assert rect.contains(pose.x, pose.y, margin=r - 1e-12)
        assert t.points[0] == hangar.uav and t.points[-1] == pose.xy and t.target == region
        assert _clear_of_obstacles(hangar, t, r)


def test_fly_detours_around_an_obstacle_in_the_way():
    scene = aircraft(seed=0, obstacles=0)
    # a wall between the charger and the tail: the straight flight is impossible
    scene["obstacles"] = [{"name": "wall", "shape": "box", "size": [0.1, 3.0],
                           "x": 2.95, "y": 1.5, "theta": 0.0}]
    w = open_world(scene, seed=0)
    pose, t = next(a.fly(make_ctx(w, 4), "tail"))
    assert len(t.points) > 2 and _clear_of_obstacles(w, t, w.scene.uav.radius)
    assert t.length > math.dist(t.points[0], t.points[-1])


def test_battery_evaluator_executors_and_drift(hangar):
    ctx = make_ctx(hangar, 2)
    pose, t = next(a.fly(ctx, "tail"))
    assert a.has_battery(ctx, t)
    long = Traj2(((0.0, 0.0), (4.0, 0.0), (4.0, 4.0)), None, "tail")   # 8 m > 5 m
    assert not a.has_battery(ctx, long)
    a.fly_to(ctx, ConcreteAction("fly", {"r": "tail", "p": pose, "t": t},
                                 adds=(("uav_at", ("tail",)),), deletes=(("uav_at", ("charger",)),)))
    assert hangar.uav == pose.xy
    assert math.isclose(hangar.battery, 5.0 - t.length)
    # drift: planned for the fuselage, the outcome says right_wing -> its centre
    p2, t2 = next(a.fly(ctx, "fuselage"))
    before = hangar.battery
    a.fly_to(ctx, ConcreteAction("fly", {"r": "fuselage", "p": p2, "t": t2},
                                 adds=(("uav_at", ("right_wing",)),)))
    assert hangar.uav == hangar.region("right_wing").centre
    assert math.isclose(hangar.battery, before - t2.length)
    a.inspect(ctx, ConcreteAction("inspect", {"r": "right_wing"}))
    assert hangar.uav == hangar.region("right_wing").centre
    a.charge(ctx, ConcreteAction("charge", {}))
    assert hangar.battery == 5.0


def test_initial_values_and_same_seed_same_flights(hangar):
    assert hangar.initial_values() == {"pose_uav0": Pose2(*hangar.region("charger").centre)}
    first = list(a.fly(make_ctx(hangar, 9), "left_wing"))
    again = list(a.fly(make_ctx(open_world(aircraft(seed=3, obstacles=6, battery=5.0), seed=0), 9),
                       "left_wing"))
    assert first == again


def test_aerial_functions_need_a_uav_and_known_regions(hangar):
    no_uav = open_world(corridor_scene(), seed=0)
    with pytest.raises(StampcError) as info:
        list(a.fly(make_ctx(no_uav), "tail"))
    assert info.value.diagnostics[0].code == "S275"
    with pytest.raises(StampcError) as info:
        list(a.fly(make_ctx(hangar), "cockpit"))
    assert info.value.diagnostics[0].code == "S271"
