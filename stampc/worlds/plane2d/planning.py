"""Collision checking of gripper (or UAV) paths and a small seeded RRT-Connect in 2-D.

A :class:`Checker` is a frozen snapshot of the obstacles relevant to one query: discs
and boxes as numpy arrays, the moving footprints (the gripper disc plus held objects'
bounding discs at fixed offsets) and the admissible region for the gripper centre
(workspace rectangle ∩ reach disc, both convex, so a segment is admissible iff its
endpoints are). Checks are exact (see :mod:`geometry`), so an RRT path reported
collision-free is collision-free for the ``collision`` evaluator too.
"""

from __future__ import annotations

import math
import random
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from stampc.worlds.plane2d.geometry import (EPS, Box, Point, point_segment_distance,
                                            segment_box_distance, segments_boxes_distance,
                                            segments_points_distance)
from stampc.worlds.plane2d.scene import Rect


@dataclass(frozen=True, eq=False)
class Checker:
    disc_names: tuple[str, ...]
    discs: np.ndarray            # (N, 3): x, y, radius
    box_names: tuple[str, ...]
    boxes: np.ndarray            # (K, 5): x, y, hx, hy, theta
    footprints: tuple[tuple[Point, float], ...]   # (offset, radius); the first is the mover
    workspace: Rect
    base: Point
    reach: float

    # ---------------------------------------------------------- admissibility
    def admissible(self, p: Point) -> bool:
        """Centre inside the workspace and within reach of the base."""
        return (self.workspace.contains(p[0], p[1])
                and math.dist(p, self.base) <= self.reach + EPS)

    def _hits(self, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per obstacle: is it hit by any footprint swept along segments a[i]–b[i]?"""
        disc_hit = np.zeros(len(self.discs), dtype=bool)
        box_hit = np.zeros(len(self.boxes), dtype=bool)
        for (ox, oy), r in self.footprints:
            off = np.array([ox, oy])
            sa, sb = a + off, b + off
            if len(self.discs):
                d = segments_points_distance(sa, sb, self.discs[:, :2])
                disc_hit |= np.any(d < r + self.discs[None, :, 2] - EPS, axis=0)
            if len(self.boxes):
                d = segments_boxes_distance(sa, sb, self.boxes)
                box_hit |= np.any(d < r - EPS, axis=0)
        return disc_hit, box_hit

    def __post_init__(self) -> None:
        # Plain-Python copies: one segment against a dozen obstacles is several times
        # faster without numpy's per-call overhead (the RRT's inner loop).
        object.__setattr__(self, "_disc_list", [tuple(map(float, d)) for d in self.discs])
        object.__setattr__(self, "_box_list", [Box(*map(float, b)) for b in self.boxes])

    def segment_free(self, a: Point, b: Point) -> bool:
        """The footprints swept along ``a``–``b`` touch no obstacle (scalar exact test)."""
        if not (self.admissible(a) and self.admissible(b)):
            return False
        for (ox, oy), r in self.footprints:
            sa, sb = (a[0] + ox, a[1] + oy), (b[0] + ox, b[1] + oy)
            for x, y, rad in self._disc_list:
                if point_segment_distance((x, y), sa, sb) < r + rad - EPS:
                    return False
            for box in self._box_list:
                if segment_box_distance(sa, sb, box) < r - EPS:
                    return False
        return True

    def point_free(self, p: Point) -> bool:
        return self.segment_free(p, p)

    def path_free(self, points: Sequence[Point]) -> bool:
        return all(self.admissible(p) for p in points) and not self.blockers(points)

    def blockers(self, points: Sequence[Point]) -> frozenset[str]:
        """Names of the obstacles the swept area of ``points`` overlaps."""
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        a, b = (pts[:-1], pts[1:]) if len(pts) > 1 else (pts, pts)
        disc_hit, box_hit = self._hits(a, b)
        return frozenset([n for n, h in zip(self.disc_names, disc_hit) if h]
                         + [n for n, h in zip(self.box_names, box_hit) if h])

    def sample(self, rng: random.Random) -> Point:
        """A uniform admissible point (rejection sampling in the workspace)."""
        w = self.workspace
        for _ in range(1000):
            p = (rng.uniform(w.x0, w.x1), rng.uniform(w.y0, w.y1))
            if self.admissible(p):
                return p
        return self.base


# ------------------------------------------------------------------ RRT-Connect
@dataclass
class _Tree:
    points: list[Point]
    parents: list[int]

    def nearest(self, p: Point) -> int:
        px, py = p
        best, best_d = 0, math.inf
        for i, (x, y) in enumerate(self.points):
            d = (x - px) ** 2 + (y - py) ** 2
            if d < best_d:
                best, best_d = i, d
        return best

    def add(self, p: Point, parent: int) -> int:
        self.points.append(p)
        self.parents.append(parent)
        return len(self.points) - 1

    def branch(self, i: int) -> list[Point]:
        out = []
        while i >= 0:
            out.append(self.points[i])
            i = self.parents[i]
        return out           # from node i back to the root


def _steer(a: Point, b: Point, step: float) -> Point:
    d = math.dist(a, b)
    if d <= step:
        return b
    return (a[0] + (b[0] - a[0]) * step / d, a[1] + (b[1] - a[1]) * step / d)


def rrt_connect(start: Point, goal: Point, checker: Checker, rng: random.Random, *,
                iterations: int = 400, step: float | None = None,
                shortcut_rounds: int = 40) -> list[Point] | None:
    """Bidirectional RRT (RRT-Connect); returns a shortcut path or ``None``."""
    if not (checker.point_free(start) and checker.point_free(goal)):
        return None
    if checker.segment_free(start, goal):
        return [start, goal]
    w = checker.workspace
    step = step or 0.08 * max(w.x1 - w.x0, w.y1 - w.y0)
    trees = (_Tree([start], [-1]), _Tree([goal], [-1]))
    free = checker.segment_free
    for k in range(iterations):
        grow, other = (trees[0], trees[1]) if k % 2 == 0 else (trees[1], trees[0])
        target = checker.sample(rng)
        i = grow.nearest(target)
        new = _steer(grow.points[i], target, step)
        if not free(grow.points[i], new):
            continue
        ni = grow.add(new, i)
        j = _connect(other, new, free, step)
        if j is not None:
            a, b = grow.branch(ni), other.branch(j)
            path = (a[::-1] + b) if grow is trees[0] else (b[::-1] + a)
            return shortcut(path, free, rng, shortcut_rounds)
    return None


def _connect(tree: _Tree, target: Point, free: Callable[[Point, Point], bool],
             step: float) -> int | None:
    """Extend ``tree`` greedily toward ``target``; index of the node reaching it, or None."""
    i = tree.nearest(target)
    while True:
        cur = tree.points[i]
        new = _steer(cur, target, step)
        if not free(cur, new):
            return None
        i = tree.add(new, i)
        if new == target:
            return i


def shortcut(path: list[Point], free: Callable[[Point, Point], bool], rng: random.Random,
             rounds: int) -> list[Point]:
    """Random shortcutting, then a greedy pass from the start (keeps endpoints)."""
    path = list(path)
    for _ in range(rounds):
        if len(path) <= 2:
            break
        i, j = sorted(rng.sample(range(len(path)), 2))
        if j - i > 1 and free(path[i], path[j]):
            path = path[: i + 1] + path[j:]
    out, i = [path[0]], 0
    while i < len(path) - 1:
        j = len(path) - 1
        while j > i + 1 and not free(path[i], path[j]):
            j -= 1
        out.append(path[j])
        i = j
    return out
