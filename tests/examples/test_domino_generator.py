"""The domino generator: seeded, a different instance per seed, and a row whose
geometry matters (a grasp closing along the row touches the neighbours). Real PyBullet."""

from __future__ import annotations

import math
import random

from examples.domino import scene as dom
from stampc.worlds.base import Context
from stampc.worlds.pybullet import cluttered, manipulation, open_world
from stampc.worlds.pybullet.kinematics import top_grasp
from stampc.worlds.pybullet.values import quat_rotate


def test_seeded_and_a_different_instance_per_seed():
    assert dom.build(20, 3) == dom.build(20, 3)
    layouts = {tuple(tuple(o["position"]) for o in dom.build(20, s)["objects"])
               for s in range(10)}
    assert len(layouts) == 10
    targets = [dom.instance(20, 3, s).target for s in range(10)]
    assert len(set(targets)) >= 4 and all(3 <= t <= 16 for t in targets)
    assert len({dom.problem_text(20, 3, s) for s in range(10)}) == 10


def test_row_spacing_and_topple_reach():
    scene = dom.build(15, 0)
    ys = [o["position"][1] for o in scene["objects"]]
    gaps = [b - a for a, b in zip(ys, ys[1:])]
    assert all(abs(g - dom.SPACING) < 1e-9 for g in gaps)
    inst = dom.instance(15, 3, 0)
    text = dom.problem_text(15, 3, 0)
    t = inst.target
    for d in (1, 2, 3):
        assert f"near{d}(d{t}, d{t - d})" in text and f"near{d}(d{t}, d{t + d})" in text
    assert "near3" not in dom.problem_text(15, 2, 0)


def test_grasps_are_checked_against_the_neighbours():
    """Fingers closing along the row land on the neighbours (3 cm away): that grasp is
    in collision, the one closing across the row is clear."""
    scene = dom.build(10, 0)
    world = open_world(scene, seed=0)
    try:
        ctx = Context(world=world, rng=random.Random(0), options={})
        pose = world.initial_values()["pose_d5"]
        geom = world.geometry["d5"]
        along = across = None
        for yaw in (0.0, math.pi / 2):
            g = top_grasp(geom, yaw)
            config = manipulation._grasp_config(world, ctx, "d5", pose, g)
            if config is None:
                continue
            hits = cluttered.movable_hits(world, config, "d5")
            closing = quat_rotate(pose.multiply(g.hand).quat, (0.0, 1.0, 0.0))
            if abs(closing[1]) > 0.9:  # the fingers close along world y: along the row
                along = hits
            else:
                across = hits
        assert across == frozenset()
        # the open fingers straddle d4 and d6 and land on the next ones out
        assert along and along <= {"d3", "d4", "d6", "d7"}
    finally:
        world.close()
