"""Geometry unit and property tests: exact distances checked against independent
closed forms and brute-force sampling."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from stampc.worlds.plane2d.geometry import (EPS, Box, Capsule, Disc, contains_point, distance,
                                            overlaps, point_segment_distance,
                                            ray_exit_rounded_box, segment_box_distance,
                                            segment_segment_distance, segments_boxes_distance,
                                            segments_intersect, segments_points_distance,
                                            swept_area)

coord = st.floats(-2.0, 2.0, allow_nan=False, allow_infinity=False)
point = st.tuples(coord, coord)
radius = st.floats(0.01, 0.5)
angle = st.floats(-math.pi, math.pi)
boxes = st.builds(Box, coord, coord, st.floats(0.01, 0.6), st.floats(0.01, 0.6), angle)


def test_point_segment_distance_closed_forms():
    # perpendicular foot inside the segment: the distance is the height
    assert math.isclose(point_segment_distance((0.5, 0.3), (0, 0), (1, 0)), 0.3)
    # foot beyond the end: distance to the endpoint (3-4-5 triangle)
    assert math.isclose(point_segment_distance((4.0, 4.0), (0, 0), (1, 0)), 5.0)
    # degenerate segment = point
    assert math.isclose(point_segment_distance((3, 4), (0, 0), (0, 0)), 5.0)


def test_segments_intersect_cases():
    assert segments_intersect((0, 0), (1, 1), (0, 1), (1, 0))          # crossing
    assert segments_intersect((0, 0), (1, 0), (1, 0), (2, 1))          # shared endpoint
    assert segments_intersect((0, 0), (2, 0), (1, 0), (3, 0))          # collinear overlap
    assert not segments_intersect((0, 0), (1, 0), (2, 0), (3, 0))      # collinear, apart
    assert not segments_intersect((0, 0), (1, 0), (0, 1), (1, 1))      # parallel
    assert math.isclose(segment_segment_distance((0, 0), (1, 0), (0, 1), (1, 1)), 1.0)


def test_disc_and_box_distances():
    assert math.isclose(distance(Disc(0, 0, 1), Disc(3, 4, 1)), 3.0)
    # axis-aligned boxes 1 apart along x
    assert math.isclose(distance(Box(0, 0, 0.5, 0.5), Box(2, 0, 0.5, 0.5)), 1.0)
    # a box rotated 45° reaches sqrt(2)/2 from its centre along x
    rotated = Box(0, 0, 0.5, 0.5, math.pi / 4)
    assert math.isclose(distance(rotated, Disc(2, 0, 0.1)), 2 - math.sqrt(0.5) - 0.1)
    assert overlaps(Box(0, 0, 1, 1), Disc(0, 0, 0.1))                  # disc inside box
    assert not overlaps(Disc(0, 0, 1), Disc(2, 0, 1))                   # touching only
    assert overlaps(Disc(0, 0, 1), Disc(2 - 1e-6, 0, 1))


@given(point, point, radius, point, radius)
def test_capsule_distance_symmetric(a, b, r, c, rc):
    d1 = distance(Capsule(a, b, r), Disc(*c, rc))
    assert math.isclose(d1, distance(Capsule(b, a, r), Disc(*c, rc)), abs_tol=1e-12)
    assert math.isclose(d1, distance(Disc(*c, rc), Capsule(a, b, r)), abs_tol=1e-12)


@given(boxes, boxes)
def test_box_distance_symmetric(b1, b2):
    assert math.isclose(distance(b1, b2), distance(b2, b1), abs_tol=1e-12)


@given(point, point, boxes)
@settings(max_examples=150)
def test_segment_box_distance_matches_sampling(a, b, box):
    d = segment_box_distance(a, b, box)
    # brute force: densely sample both the segment and the box (interior included)
    ts = np.linspace(0, 1, 60)
    seg = np.array(a)[None, :] + ts[:, None] * (np.array(b) - np.array(a))[None, :]
    u, v = np.meshgrid(np.linspace(-1, 1, 30), np.linspace(-1, 1, 30))
    c, s = math.cos(box.theta), math.sin(box.theta)
    lx, ly = (u * box.hx).ravel(), (v * box.hy).ravel()
    pts = np.stack([box.x + c * lx - s * ly, box.y + s * lx + c * ly], axis=1)
    brute = np.min(np.linalg.norm(seg[:, None, :] - pts[None, :, :], axis=2))
    spacing = math.dist(a, b) / 59 + 2 * max(box.hx, box.hy) / 29
    assert d <= brute + 1e-9
    assert d >= brute - spacing


@given(st.lists(st.tuples(point, point), min_size=1, max_size=5), st.lists(boxes, min_size=1, max_size=4))
def test_vectorised_box_distances_agree_with_scalar(segs, bxs):
    a = np.array([s[0] for s in segs])
    b = np.array([s[1] for s in segs])
    rows = np.array([[x.x, x.y, x.hx, x.hy, x.theta] for x in bxs])
    mat = segments_boxes_distance(a, b, rows)
    for i, (p, q) in enumerate(segs):
        for j, box in enumerate(bxs):
            assert math.isclose(mat[i, j], segment_box_distance(p, q, box), abs_tol=1e-9)
            # and with the generic convex-core distance
            assert math.isclose(mat[i, j], distance(Capsule(p, q, 0.0), box), abs_tol=1e-9)


@given(st.lists(st.tuples(point, point), min_size=1, max_size=5), st.lists(point, min_size=1, max_size=5))
def test_vectorised_point_distances_agree_with_scalar(segs, pts):
    mat = segments_points_distance(np.array([s[0] for s in segs]), np.array([s[1] for s in segs]),
                                   np.array(pts))
    for i, (p, q) in enumerate(segs):
        for j, c in enumerate(pts):
            assert math.isclose(mat[i, j], point_segment_distance(c, p, q), abs_tol=1e-9)


@given(st.lists(point, min_size=1, max_size=6), radius, st.floats(0, 1), st.integers(0, 4),
       angle, st.floats(0, 1))
def test_swept_area_contains_sampled_path_points(path, r, t, k, direction, frac):
    held_offset, held_r = (0.2, -0.1), 0.05
    area = swept_area(path, r, held=[(held_offset, held_r)])
    i = k % max(1, len(path) - 1)
    a, b = path[i], path[min(i + 1, len(path) - 1)]
    centre = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
    inside = frac * r * 0.999
    p = (centre[0] + inside * math.cos(direction), centre[1] + inside * math.sin(direction))
    assert area.contains(p)
    held_p = (centre[0] + held_offset[0] + frac * held_r * 0.999 * math.cos(direction),
              centre[1] + held_offset[1] + frac * held_r * 0.999 * math.sin(direction))
    assert area.contains(held_p)
    # a disc centred on a path point with radius beyond r + held reach is not contained
    assert not area.contains((centre[0] + 10.0, centre[1]))


@given(st.floats(0.01, 0.5), st.floats(0.01, 0.5), st.floats(0.005, 0.2), angle)
def test_ray_exit_rounded_box_touches_box(hx, hy, r, a):
    d = ray_exit_rounded_box(hx, hy, r, a)
    p = (d * math.cos(a), d * math.sin(a))
    assert math.isclose(distance(Box(0, 0, hx, hy), Disc(*p, 0.0)), r, abs_tol=1e-9)


def test_contains_point_tolerance():
    assert contains_point(Disc(0, 0, 1), (1 + EPS / 2, 0))
    assert not contains_point(Disc(0, 0, 1), (1 + 1e-6, 0))
