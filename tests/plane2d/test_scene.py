"""Scene parsing diagnostics, open_world, and the seeded scene generators."""

from __future__ import annotations

import itertools
import json
import math
import random

import pytest

from stampc.diagnostics import StampcError
from stampc.worlds.base import Context, World
from stampc.worlds.plane2d import Pose2, open_world
from stampc.worlds.plane2d import manipulation as m
from stampc.worlds.plane2d.geometry import distance
from stampc.worlds.plane2d.scenes import aircraft, cluttered, domino_row

from .conftest import corridor_scene


def _codes_and_messages(exc: StampcError) -> list[tuple[str, str]]:
    return [(d.code, d.message) for d in exc.diagnostics]


def test_world_satisfies_protocol(world):
    assert isinstance(world, World)
    assert world.package == "stampc.worlds.plane2d"
    assert world.initial_values() == {"pose_can0": Pose2(0.5, 0.5, 0.0),
                                      "pose_can1": Pose2(0.5, 0.25, 0.0)}
    assert world.gripper == (0.5, -0.1)
    assert world.scene.surface("table") is not None   # the table is always a surface


def test_bad_scene_reports_every_problem_with_paths():
    scene = corridor_scene()
    scene["objects"][1]["radius"] = -1
    scene["objects"][2]["shape"] = "triangle"
    scene["objects"][3]["name"] = "can0"
    scene["poses"]["pose_x"] = "nope"
    scene["poses"]["pose_u"] = "uav"          # no "uav" section in this scene
    del scene["robot"]["reach"]
    with pytest.raises(StampcError) as info:
        open_world(scene, seed=0)
    found = _codes_and_messages(info.value)
    assert all(code == "S201" for code, _ in found)
    text = "\n".join(msg for _, msg in found)
    for fragment in ("objects[1].radius", "objects[2].shape", "duplicate object name 'can0'",
                     "poses.pose_x", "poses.pose_u", "robot.reach"):
        assert fragment in text


@pytest.mark.parametrize("bad", [None, [], "table", {"table": {"x0": 1, "y0": 0, "x1": 0, "y1": 1}}])
def test_malformed_scenes_raise_stampc_error(bad):
    with pytest.raises(StampcError):
        open_world(bad, seed=0)


def test_open_world_from_json_file(tmp_path):
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(corridor_scene()))
    assert open_world(str(path), seed=1).pose("can3") == Pose2(0.444, 0.40, 0.0)
    broken = tmp_path / "broken.json"
    broken.write_text('{"table": ')
    with pytest.raises(StampcError) as info:
        open_world(broken, seed=1)
    assert info.value.diagnostics[0].code == "S200"
    assert info.value.diagnostics[0].span.file == str(broken)


def _objects_clear(scene: dict, gap: float) -> bool:
    """Movable objects keep ``gap`` from each other and from static obstacles (walls of
    a shelf may touch each other)."""
    w = open_world(scene, seed=0)
    movable = [w.shape(n) for n in w.poses()]
    pairs = itertools.chain(itertools.combinations(movable, 2),
                            itertools.product(movable, w.scene.static_shapes()))
    return all(distance(a, b) >= gap - 1e-9 for a, b in pairs)


@pytest.mark.parametrize("seed", range(6))
def test_cluttered_reproducible_and_overlap_free(seed):
    a, b = cluttered(9, seed, blockers=2), cluttered(9, seed, blockers=2)
    assert a == b
    assert json.loads(json.dumps(a)) == a          # JSON-friendly
    assert _objects_clear(a, 0.01)
    for o in a["objects"]:
        assert 0 <= o["x"] - o["radius"] and o["x"] + o["radius"] <= 1.0
        assert 0 <= o["y"] - o["radius"] and o["y"] + o["radius"] <= 0.6
    assert cluttered(9, seed + 100) != a


@pytest.mark.parametrize("seed", range(4))
def test_cluttered_blockers_sit_in_the_approach_corridor(seed):
    w = open_world(cluttered(7, seed, blockers=2), seed=0)
    ctx = Context(w, random.Random(0))
    g, q = next(m.grasp(ctx, "can0", w.pose("can0")))
    straight = m.Traj2((w.gripper, q.xy), None, "can0")
    assert {"can1", "can2"} <= m.blocking_objects(ctx, straight)


@pytest.mark.parametrize("seed", range(3))
def test_shelf_scene_forces_the_blockers_to_be_moved(seed):
    scene = cluttered(6, seed, blockers=2, shelf=True)
    assert _objects_clear(scene, 0.01)
    w = open_world(scene, seed=0)
    ctx = Context(w, random.Random(seed), options={"budget": 2})
    _, q = next(m.grasp(ctx, "can0", w.pose("can0")))
    (t,), = list(m.motion(ctx, q))        # only the fallback exists
    assert m.blocking_objects(ctx, t) == {"can1", "can2"}


def test_generator_rejects_impossible_requests():
    with pytest.raises(StampcError) as info:
        cluttered(60, 0, radius=0.06)
    assert info.value.diagnostics[0].code == "S210"
    with pytest.raises(StampcError):
        cluttered(3, 0, target="can9")
    with pytest.raises(StampcError):
        domino_row(40, spacing=0.05)


def test_domino_row_regular_spacing():
    scene = domino_row(5, spacing=0.07)
    xs = [o["x"] for o in scene["objects"]]
    assert all(math.isclose(b - a, 0.07) for a, b in zip(xs, xs[1:]))
    assert _objects_clear(scene, 0.0)
    jittered = domino_row(5, seed=3, jitter=0.005)
    assert jittered == domino_row(5, seed=3, jitter=0.005) and _objects_clear(jittered, 0.0)


@pytest.mark.parametrize("seed", range(3))
def test_aircraft_obstacles_avoid_regions(seed):
    scene = aircraft(seed=seed, obstacles=5)
    assert scene == aircraft(seed=seed, obstacles=5)
    assert {"left_wing", "right_wing", "fuselage", "tail", "charger"} <= set(scene["regions"])
    w = open_world(scene, seed=0)
    for name, rect in w.scene.regions:
        cx, cy = rect.centre
        for shape in w.scene.static_shapes():
            assert distance(shape, m.Disc(cx, cy, 0.0)) > 0
    statics = w.scene.static_shapes()
    assert all(distance(a, b) > 0 for a, b in itertools.combinations(statics, 2))


def test_gripper_pose_symbol_and_value_json_round_trip():
    from hypothesis import given, strategies as st

    from stampc.worlds.base import to_json
    from stampc.worlds.plane2d.values import Config2, Grasp2, Traj2, as_config, as_grasp, \
        as_pose, as_traj

    scene = corridor_scene()
    scene["poses"]["q0"] = "gripper"
    assert open_world(scene, seed=0).initial_values()["q0"] == Config2(0.5, -0.1)

    f = st.floats(-10, 10, allow_nan=False)
    name = st.one_of(st.none(), st.text(min_size=1, max_size=5))

    @given(f, f, f, st.lists(st.tuples(f, f), min_size=1, max_size=4), name, name)
    def round_trip(x, y, a, pts, held, target):
        values = [(Pose2(x, y, a), as_pose), (Grasp2(a), as_grasp),
                  (Config2(x, y, target), as_config), (Traj2(tuple(pts), held, target), as_traj)]
        for v, conv in values:
            assert conv(json.loads(json.dumps(to_json(v)))) == v

    round_trip()
