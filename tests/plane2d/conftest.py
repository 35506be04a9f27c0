"""Shared fixtures: a small hand-built scene whose blocking sets are known by hand."""

from __future__ import annotations

import random

import pytest

from stampc.worlds.base import Context
from stampc.worlds.plane2d import open_world

GRIPPER_R = 0.02
BASE = (0.5, -0.1)


def corridor_scene() -> dict:
    """Target can0 at (0.5, 0.5), radius 0.03; the facing grasp puts the gripper at
    (0.5, 0.45), so the straight reach from the base runs along x = 0.5, and the
    gripper capsule (radius 0.02) covers |x - 0.5| < 0.02.

    - can1 on the line: blocks; can2 centre 0.045 off the line (< 0.02 + 0.03): blocks
    - can3 centre 0.056 off the line (> 0.05): clear by 6 mm
    - box1 near edge at x = 0.519 (< 0.52): blocks; box2 near edge at 0.521: clear
    - can4 far away; mug (x = 0.6) only matters when a held object sweeps to the right
    """
    return {
        "table": {"x0": 0.0, "y0": 0.0, "x1": 1.0, "y1": 0.6},
        "robot": {"base": list(BASE), "gripper_radius": GRIPPER_R, "reach": 0.9},
        "surfaces": {"tray": {"x0": 0.75, "y0": 0.05, "x1": 0.95, "y1": 0.25}},
        "objects": [
            {"name": "can0", "shape": "disc", "radius": 0.03, "x": 0.5, "y": 0.5},
            {"name": "can1", "shape": "disc", "radius": 0.03, "x": 0.5, "y": 0.25},
            {"name": "can2", "shape": "disc", "radius": 0.03, "x": 0.545, "y": 0.33},
            {"name": "can3", "shape": "disc", "radius": 0.03, "x": 0.444, "y": 0.40},
            {"name": "box1", "shape": "box", "size": [0.02, 0.04], "x": 0.529, "y": 0.12},
            {"name": "box2", "shape": "box", "size": [0.02, 0.04], "x": 0.469, "y": 0.05},
            {"name": "can4", "shape": "disc", "radius": 0.03, "x": 0.1, "y": 0.5},
        ],
        "poses": {"pose_can0": "can0", "pose_can1": "can1"},
    }


@pytest.fixture
def world():
    w = open_world(corridor_scene(), seed=0)
    yield w
    w.close()


def make_ctx(w, seed: int = 0, **options) -> Context:
    return Context(w, random.Random(seed), options=options)
