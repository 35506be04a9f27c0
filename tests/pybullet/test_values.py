"""Concrete value types: transform math, JSON round trips, coercion of bad values."""

from __future__ import annotations

import json
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from stampc.diagnostics import StampcError
from stampc.worlds.base import to_json
from stampc.worlds.pybullet.values import (Config, Grasp, Pose, Traj, as_config, as_pose,
                                           as_traj, quat_from_axes, quat_from_axis_angle,
                                           quat_rotate)

coord = st.floats(-2, 2, allow_nan=False)
angle = st.floats(-math.pi, math.pi, allow_nan=False)


def pose_strategy():
    return st.builds(lambda x, y, z, ax, ay, az, a: Pose.of(
        (x, y, z), quat_from_axis_angle((ax, ay, az + 1e-3 + abs(az)), a)),
        coord, coord, coord, coord, coord, coord, angle)


@settings(max_examples=60, deadline=None)
@given(pose_strategy(), pose_strategy())
def test_inverse_and_composition(a, b):
    ident = a.multiply(a.inverse())
    assert math.dist(ident.pos, (0, 0, 0)) < 1e-9 and ident.angle(Pose.of((0, 0, 0))) < 1e-6
    back = a.multiply(b).multiply(b.inverse())
    assert back.distance(a) < 1e-9 and back.angle(a) < 1e-6


def test_rotation_of_axes():
    q = quat_from_axis_angle((0, 0, 1), math.pi / 2)
    assert quat_rotate(q, (1, 0, 0)) == pytest.approx((0, 1, 0), abs=1e-12)
    # columns of a rotation matrix: x->y, y->z, z->x
    r = quat_from_axes((0, 1, 0), (0, 0, 1), (1, 0, 0))
    assert quat_rotate(r, (1, 0, 0)) == pytest.approx((0, 1, 0), abs=1e-12)
    assert quat_rotate(r, (0, 0, 1)) == pytest.approx((1, 0, 0), abs=1e-12)


def test_pregrasp_backs_off_against_the_approach():
    g = Grasp(Pose.of((0, 0, 0.05), quat_from_axis_angle((1, 0, 0), math.pi)), (0, 0, -1))
    obj = Pose.of((0.5, 0.1, 0.08))
    assert g.pregrasp(obj).pos == pytest.approx((0.5, 0.1, 0.08 + 0.05 + 0.1))


def test_json_round_trips():
    pose = Pose.of((1, 2, 3), (0, 0, 1, 1))
    config = Config.of([0.1, 0.2], obj="can1", pre=[0.3, 0.4])
    traj = Traj(((0.0, 1.0), (1.0, 2.0), (2.0, 2.0)), held="a", target="b", retreat_end=1,
                approach_start=2)
    for value, coerce in ((pose, as_pose), (config, as_config), (traj, as_traj)):
        data = json.loads(json.dumps(to_json(value)))
        assert coerce(data) == value
        assert coerce(value) is value
    assert traj.length() == pytest.approx(math.sqrt(2) + 1)


@pytest.mark.parametrize("coerce, bad", [
    (as_pose, "here"), (as_pose, {"pos": [1, 2]}), (as_config, 3), (as_traj, {"x": 1}),
    (as_traj, {"configs": [["a"]]}),
])
def test_bad_values_are_diagnostics(coerce, bad):
    with pytest.raises(StampcError) as exc:
        coerce(bad)
    assert exc.value.diagnostics[0].code == "PB014"
