"""Exact 2-D geometry for the plane2d world: discs, oriented boxes, capsules, swept areas.

Every shape is a convex *core* (a point, a segment or a polygon) inflated by a radius:
a disc is a point + radius, a capsule a segment + radius, a box a polygon + 0. The
distance between two shapes is the distance between their cores minus both radii, which
is exact for all pairs (no sampling, no approximation).

Tolerance: two shapes *overlap* iff their distance is below ``-EPS`` (``EPS = 1e-9``
metres), so shapes that merely touch (a gripper at a grasp contact, an object placed
against another) are not in collision despite floating-point round-off.

Hot paths (a trajectory against every object of a scene) are vectorised with numpy:
:func:`segments_points_distance` and :func:`segments_boxes_distance` return full
segment × obstacle distance matrices.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterable, Sequence, Union

import numpy as np

EPS = 1e-9

Point = tuple[float, float]


@dataclass(frozen=True)
class Disc:
    x: float
    y: float
    radius: float

    @property
    def bounding_radius(self) -> float:
        return self.radius


@dataclass(frozen=True)
class Box:
    """An oriented rectangle: centre, half extents ``hx``/``hy``, rotation ``theta``."""

    x: float
    y: float
    hx: float
    hy: float
    theta: float = 0.0

    @property
    def bounding_radius(self) -> float:
        return math.hypot(self.hx, self.hy)

    def corners(self) -> tuple[Point, ...]:
        c, s = math.cos(self.theta), math.sin(self.theta)
        out = []
        for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1)):
            lx, ly = sx * self.hx, sy * self.hy
            out.append((self.x + c * lx - s * ly, self.y + s * lx + c * ly))
        return tuple(out)

    def to_local(self, px: float, py: float) -> Point:
        c, s = math.cos(self.theta), math.sin(self.theta)
        dx, dy = px - self.x, py - self.y
        return (c * dx + s * dy, -s * dx + c * dy)


@dataclass(frozen=True)
class Capsule:
    """The set of points within ``radius`` of segment ``a``–``b``."""

    a: Point
    b: Point
    radius: float


Shape = Union[Disc, Box, Capsule]


# ------------------------------------------------------------ scalar primitives
def point_segment_distance(p: Point, a: Point, b: Point) -> float:
    ax, ay = a
    dx, dy = b[0] - ax, b[1] - ay
    den = dx * dx + dy * dy
    t = 0.0 if den == 0.0 else max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / den))
    return math.hypot(p[0] - (ax + t * dx), p[1] - (ay + t * dy))


def _cross(o: Point, a: Point, b: Point) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _on_segment(p: Point, a: Point, b: Point) -> bool:
    return (min(a[0], b[0]) <= p[0] <= max(a[0], b[0])
            and min(a[1], b[1]) <= p[1] <= max(a[1], b[1]))


def segments_intersect(a: Point, b: Point, c: Point, d: Point) -> bool:
    """Closed-segment intersection with exact orientation tests (touching counts)."""
    d1, d2 = _cross(c, d, a), _cross(c, d, b)
    d3, d4 = _cross(a, b, c), _cross(a, b, d)
    if ((d1 > 0) != (d2 > 0)) and d1 != 0 and d2 != 0 and \
            ((d3 > 0) != (d4 > 0)) and d3 != 0 and d4 != 0:
        return True
    return ((d1 == 0 and _on_segment(a, c, d)) or (d2 == 0 and _on_segment(b, c, d))
            or (d3 == 0 and _on_segment(c, a, b)) or (d4 == 0 and _on_segment(d, a, b)))


def segment_segment_distance(a: Point, b: Point, c: Point, d: Point) -> float:
    # In 2-D the closest pair of two disjoint segments always involves an endpoint.
    if segments_intersect(a, b, c, d):
        return 0.0
    return min(point_segment_distance(a, c, d), point_segment_distance(b, c, d),
               point_segment_distance(c, a, b), point_segment_distance(d, a, b))


def point_in_convex(p: Point, poly: Sequence[Point]) -> bool:
    """``p`` inside or on a convex polygon given counter-clockwise (≥ 3 vertices)."""
    n = len(poly)
    return n >= 3 and all(_cross(poly[i], poly[(i + 1) % n], p) >= 0 for i in range(n))


def _edges(core: Sequence[Point]) -> list[tuple[Point, Point]]:
    if len(core) == 1:
        return [(core[0], core[0])]
    if len(core) == 2:
        return [(core[0], core[1])]
    return [(core[i], core[(i + 1) % len(core)]) for i in range(len(core))]


def core_distance(p: Sequence[Point], q: Sequence[Point]) -> float:
    """Distance between two convex cores (1 vertex = point, 2 = segment, ≥ 3 = CCW polygon)."""
    if point_in_convex(q[0], p) or point_in_convex(p[0], q):
        return 0.0
    return min(segment_segment_distance(a, b, c, d)
               for a, b in _edges(p) for c, d in _edges(q))


def core_of(shape: Shape) -> tuple[tuple[Point, ...], float]:
    if isinstance(shape, Disc):
        return ((shape.x, shape.y),), shape.radius
    if isinstance(shape, Box):
        return shape.corners(), 0.0
    return (shape.a, shape.b), shape.radius


def distance(s1: Shape, s2: Shape) -> float:
    """Distance between two shapes; ≤ 0 when they touch or overlap. Negative values
    measure penetration only for the round parts (never below ``-(r1 + r2)``)."""
    c1, r1 = core_of(s1)
    c2, r2 = core_of(s2)
    return core_distance(c1, c2) - r1 - r2


def overlaps(s1: Shape, s2: Shape, margin: float = 0.0) -> bool:
    """True iff the shapes come closer than ``margin`` (beyond the ``EPS`` tolerance)."""
    return distance(s1, s2) < margin - EPS


def contains_point(shape: Shape, p: Point) -> bool:
    c, r = core_of(shape)
    return core_distance(c, (p,)) <= r + EPS


def segment_box_distance(a: Point, b: Point, box: Box) -> float:
    """Scalar twin of :func:`segments_boxes_distance` (faster for a single segment)."""
    la, lb = box.to_local(*a), box.to_local(*b)
    if _segment_hits_aabb(la, lb, box.hx, box.hy):
        return 0.0
    best = min(_point_aabb_distance(la, box.hx, box.hy), _point_aabb_distance(lb, box.hx, box.hy))
    for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1)):
        best = min(best, point_segment_distance((sx * box.hx, sy * box.hy), la, lb))
    return best


def _point_aabb_distance(p: Point, hx: float, hy: float) -> float:
    return math.hypot(max(abs(p[0]) - hx, 0.0), max(abs(p[1]) - hy, 0.0))


def _segment_hits_aabb(a: Point, b: Point, hx: float, hy: float) -> bool:
    t0, t1 = 0.0, 1.0
    for da, dd, h in ((a[0], b[0] - a[0], hx), (a[1], b[1] - a[1], hy)):
        if abs(dd) < 1e-300:
            if abs(da) > h:
                return False
            continue
        lo, hi = (-h - da) / dd, (h - da) / dd
        if lo > hi:
            lo, hi = hi, lo
        t0, t1 = max(t0, lo), min(t1, hi)
        if t0 > t1:
            return False
    return True


# ------------------------------------------------------------- vectorised paths
def segments_points_distance(a: np.ndarray, b: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Distances between M segments ``a[i]``–``b[i]`` and N points: an (M, N) matrix."""
    d = (b - a)[:, None, :]                                   # (M,1,2)
    ap = p[None, :, :] - a[:, None, :]                        # (M,N,2)
    den = np.sum(d * d, axis=2)                               # (M,1)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(den > 0, np.sum(ap * d, axis=2) / np.where(den > 0, den, 1.0), 0.0)
    t = np.clip(t, 0.0, 1.0)
    return np.linalg.norm(ap - t[:, :, None] * d, axis=2)


def _segments_hit_aabbs(a: np.ndarray, b: np.ndarray, h: np.ndarray) -> np.ndarray:
    """Liang–Barsky slab test. ``a``, ``b``: (M,K,2) local endpoints; ``h``: (K,2)."""
    d = b - a
    t0 = np.zeros(a.shape[:2])
    t1 = np.ones(a.shape[:2])
    ok = np.ones(a.shape[:2], dtype=bool)
    for axis in (0, 1):
        da, dd, hh = a[..., axis], d[..., axis], h[None, :, axis]
        flat = np.abs(dd) < 1e-300
        ok &= ~(flat & (np.abs(da) > hh))
        with np.errstate(divide="ignore", invalid="ignore"):
            lo = (-hh - da) / np.where(flat, 1.0, dd)
            hi = (hh - da) / np.where(flat, 1.0, dd)
        near, far = np.minimum(lo, hi), np.maximum(lo, hi)
        t0 = np.where(flat, t0, np.maximum(t0, near))
        t1 = np.where(flat, t1, np.minimum(t1, far))
    return ok & (t0 <= t1)


def segments_boxes_distance(a: np.ndarray, b: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """Distances between M segments and K boxes (rows ``x, y, hx, hy, theta``): (M, K).

    Exact: 0 when a segment meets a box, else the minimum of the segment endpoints'
    distances to the box and the box corners' distances to the segment (the closest
    pair of a segment and a disjoint convex polygon always involves one of those).
    """
    m, k = len(a), len(boxes)
    if m == 0 or k == 0:
        return np.zeros((m, k))
    c, s = np.cos(boxes[:, 4]), np.sin(boxes[:, 4])
    centre, h = boxes[:, :2], boxes[:, 2:4]

    def local(p: np.ndarray) -> np.ndarray:                   # (M,2) -> (M,K,2)
        dp = p[:, None, :] - centre[None, :, :]
        return np.stack([c * dp[..., 0] + s * dp[..., 1], -s * dp[..., 0] + c * dp[..., 1]], axis=2)

    la, lb = local(a), local(b)
    hit = _segments_hit_aabbs(la, lb, h)
    ends = np.minimum(_point_aabb(la, h), _point_aabb(lb, h))
    best = ends
    for sx, sy in ((1, 1), (-1, 1), (-1, -1), (1, -1)):
        corner = h * np.array([sx, sy])                       # (K,2) local corner
        cd = _point_segment_local(corner, la, lb)
        best = np.minimum(best, cd)
    return np.where(hit, 0.0, best)


def _point_aabb(p: np.ndarray, h: np.ndarray) -> np.ndarray:
    q = np.maximum(np.abs(p) - h[None, :, :], 0.0)
    return np.linalg.norm(q, axis=2)


def _point_segment_local(corner: np.ndarray, la: np.ndarray, lb: np.ndarray) -> np.ndarray:
    d = lb - la
    ap = corner[None, :, :] - la
    den = np.sum(d * d, axis=2)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(den > 0, np.sum(ap * d, axis=2) / np.where(den > 0, den, 1.0), 0.0)
    t = np.clip(t, 0.0, 1.0)
    return np.linalg.norm(ap - t[..., None] * d, axis=2)


# ------------------------------------------------------------------ swept areas
@dataclass(frozen=True)
class SweptArea:
    """Union of capsules: the area a disc of radius ``radius`` covers while its centre
    follows each polyline in ``paths`` (one polyline for the gripper, one per held
    footprint)."""

    paths: tuple[tuple[Point, ...], ...]
    radii: tuple[float, ...]

    def capsules(self) -> Iterable[Capsule]:
        for path, r in zip(self.paths, self.radii):
            if len(path) == 1:
                yield Capsule(path[0], path[0], r)
            for a, b in zip(path, path[1:]):
                yield Capsule(a, b, r)

    def segment_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Stacked segment start points, end points and radii (single points repeat)."""
        starts, ends, radii = [], [], []
        for path, r in zip(self.paths, self.radii):
            pts = path if len(path) > 1 else (path[0], path[0])
            starts.extend(pts[:-1])
            ends.extend(pts[1:])
            radii.extend([r] * (len(pts) - 1))
        return (np.asarray(starts, dtype=float).reshape(-1, 2),
                np.asarray(ends, dtype=float).reshape(-1, 2), np.asarray(radii, dtype=float))

    def contains(self, p: Point) -> bool:
        return any(contains_point(c, p) for c in self.capsules())

    def hits(self, shape: Shape, margin: float = 0.0) -> bool:
        return any(overlaps(c, shape, margin) for c in self.capsules())


def swept_area(points: Sequence[Point], radius: float,
               held: Sequence[tuple[Point, float]] = ()) -> SweptArea:
    """Swept area of a gripper disc along ``points`` carrying footprints ``held``.

    Each held footprint is ``(offset from the gripper centre, bounding radius)``; a held
    box is conservatively replaced by its bounding disc (it does not rotate in transit).
    """
    base = tuple((float(x), float(y)) for x, y in points)
    paths, radii = [base], [float(radius)]
    for (ox, oy), r in held:
        paths.append(tuple((x + ox, y + oy) for x, y in base))
        radii.append(float(r))
    return SweptArea(tuple(paths), tuple(radii))


def polyline_length(points: Sequence[Point]) -> float:
    return sum(math.dist(a, b) for a, b in zip(points, points[1:]))


def ray_exit_rounded_box(hx: float, hy: float, r: float, angle: float) -> float:
    """Distance from a box centre along local direction ``angle`` to the point at exactly
    distance ``r`` from the box (exit of the box Minkowski-inflated by a disc of radius r)."""
    ux, uy = abs(math.cos(angle)), abs(math.sin(angle))
    if ux > 1e-12:
        t = (hx + r) / ux
        if t * uy <= hy:
            return t
    if uy > 1e-12:
        t = (hy + r) / uy
        if t * ux <= hx:
            return t
    # exits through the rounded corner centred at (hx, hy): |t u - c| = r, larger root
    b = ux * hx + uy * hy
    disc = b * b - (hx * hx + hy * hy - r * r)
    return b + math.sqrt(max(disc, 0.0))
