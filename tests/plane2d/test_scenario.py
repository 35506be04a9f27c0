"""The ATM-MDP loop the engine runs, driven by hand through the bound functions: the
reach to the target is blocked, ``collision`` names the blockers, moving them to the
tray (pick/place with collision-free motions) makes the target's approach free."""

from __future__ import annotations

import itertools
import math

import pytest

from stampc.worlds.base import ConcreteAction
from stampc.worlds.plane2d import open_world
from stampc.worlds.plane2d import manipulation as m
from stampc.worlds.plane2d.geometry import distance
from stampc.worlds.plane2d.scenes import cluttered

from .conftest import make_ctx


def _free_motion(w, q, seed):
    for (t,) in m.motion(make_ctx(w, seed, budget=4), q):
        if not m.blocking_objects(make_ctx(w), t):
            return t
    return None


def _no_overlaps(w) -> bool:
    shapes = [w.shape(n) for n in w.poses()]
    return all(distance(a, b) > -1e-9 for a, b in itertools.combinations(shapes, 2))


def _move_to_tray(w, b: str, seed: int) -> bool:
    for g, q in m.grasp(make_ctx(w, seed), b, w.pose(b)):
        t = _free_motion(w, q, seed)
        if t is None:
            continue
        m.pick(make_ctx(w), ConcreteAction("pick", {"o": b, "p": w.pose(b), "g": g, "q": q,
                                                    "t": t}, adds=(("holding", (b,)),)))
        for p, qp in m.placement(make_ctx(w, seed, budget=4), b, "tray"):
            tp = _free_motion(w, qp, seed)
            if tp is not None:
                m.place(make_ctx(w), ConcreteAction(
                    "place", {"o": b, "s": "tray", "p": p, "q": qp, "t": tp},
                    adds=(("at", (b, p)),), deletes=(("holding", (b,)),)))
                return True
        return False
    return False


@pytest.mark.parametrize("seed", range(3))
def test_clearing_the_blockers_frees_the_target(seed):
    w = open_world(cluttered(6, seed, shelf=True), seed=0)
    _, q = next(m.grasp(make_ctx(w), "can0", w.pose("can0")))
    (t,) = next(m.motion(make_ctx(w, budget=2), q))
    blockers = m.blocking_objects(make_ctx(w), t)
    assert blockers == {"can1", "can2"}
    base = w.scene.robot.base
    for b in sorted(blockers, key=lambda n: math.dist(w.pose(n).xy, base)):
        assert _move_to_tray(w, b, seed), b
        assert w.scene.surface("tray").contains(*w.pose(b).xy) and w.held is None
        assert _no_overlaps(w)
    t2 = _free_motion(w, q, seed)
    assert t2 is not None and not m.blocking_objects(make_ctx(w), t2)
    m.pick(make_ctx(w), ConcreteAction("pick", {"o": "can0", "q": q, "t": t2},
                                       adds=(("holding", ("can0",)),)))
    assert w.held == "can0"
