"""The engine's bookkeeping kept between steps (incremental.py): path-selection bounds and
coverage / goal masses updated over the changed nodes' ancestors only must equal a
computation from scratch, bit for bit, after every kind of change the engine makes."""

from __future__ import annotations

import random
from pathlib import Path

import pytest

import stampc
from stampc.refine import Engine, RefineOptions
from stampc.refine.graph import (DEAD_END, GOAL, HORIZON, Edge, Node, PolicyGraph, adopt,
                                 coverage_and_goal, detach_subtree, tracked_coverage_and_goal)
from stampc.refine.incremental import IncrementalValues
from stampc.refine.unlocking import unlock_local
from stampc.refine.selection import (_swept_bounds, path_bounds, select_path,
                                     tracked_bounds)
from stampc.worlds.bindings import resolve_model
from stampc.worlds.loading import load_scene, open_world

from test_graph import NOOP, build, merging_ladder

DATA = Path(__file__).parent / "data"
REPO = Path(__file__).resolve().parents[2]


def cost_for(horizon: float):
    def node_cost(n: Node) -> float:
        if n.is_leaf:
            if n.leaf == HORIZON or (n.leaf == DEAD_END and not n.proven):
                return float("inf") if n.given_up else horizon
            return 0.0
        return 0.0 if n.refined else float(1 + n.uid % 4)
    return node_cost


def random_dag(rng: random.Random, levels: int) -> PolicyGraph:
    """Levels of 1-3 nodes; each action's 1-3 outcomes go to nodes of lower levels, so
    outcomes rejoin (as Keva's feeds do); the last level is leaves of every kind."""
    rows, uid = [], 0
    for _ in range(levels):
        rows.append(list(range(uid, uid + rng.randint(1, 3))))
        uid = rows[-1][-1] + 1
    nodes = {}
    for i, row in enumerate(rows):
        for u in row:
            if i == levels - 1 or (i > 1 and rng.random() < 0.15):
                nodes[u] = Node(u, u, i, leaf=rng.choice([GOAL, GOAL, DEAD_END, HORIZON]))
                continue
            below = [v for r in rows[i + 1:] for v in r]
            kids = rng.sample(below, min(len(below), rng.randint(1, 3)))
            ws = [rng.random() + 0.01 for _ in kids]
            nodes[u] = Node(u, u, i, action=0, sigma={} if rng.random() < 0.4 else None,
                            edges=[Edge(w / sum(ws), k, NOOP, c)
                                   for k, (w, c) in enumerate(zip(ws, kids))])
    graph = PolicyGraph(rows[0][0], nodes)
    graph.prune()
    return graph


def mutate(rng: random.Random, graph: PolicyGraph, uids) -> PolicyGraph:
    """One change of a kind the engine makes: refine, merge an outcome into another node,
    split a child off (copy-on-write), extend or give up a leaf, re-sample (unrefine a
    subtree copy), or replan on a copy of the graph."""
    kind = rng.choice(["refine", "merge", "split", "extend", "give_up", "resample", "replan"])
    actions = [n for n in graph.nodes.values() if not n.is_leaf]
    leaves = [n for n in graph.nodes.values() if n.is_leaf]
    if kind == "refine" and actions:
        node = graph.own(rng.choice(actions).uid)
        graph.touch(node.uid)
        node.sigma = {}
    elif kind in ("merge", "split") and actions:
        node = graph.own(rng.choice(actions).uid)
        k = rng.randrange(len(node.edges))
        graph.touch(node.uid)
        if kind == "merge":  # into a node at least as deep: stays acyclic
            deeper = [n.uid for n in graph.nodes.values()
                      if n.depth > node.depth and n.uid != node.edges[k].child]
            if not deeper:
                return graph
            target = rng.choice(deeper)
        else:
            child = graph.nodes[node.edges[k].child]
            target = next(uids)
            graph.nodes[target] = Node(target, child.state, child.depth, action=child.action,
                                       leaf=child.leaf, edges=list(child.edges))
        e = node.edges[k]
        node.edges[k] = Edge(e.probability, e.outcome, e.successor, target)
        graph.prune()
    elif kind == "extend" and leaves:
        leaf = rng.choice(leaves)
        a, g, h = next(uids), next(uids), next(uids)
        graph.nodes[a] = Node(a, a, leaf.depth, action=0,
                              edges=[Edge(0.7, 0, NOOP, g), Edge(0.3, 1, NOOP, h)])
        graph.nodes[g] = Node(g, g, leaf.depth + 1, leaf=GOAL)
        graph.nodes[h] = Node(h, h, leaf.depth + 1, leaf=rng.choice([HORIZON, DEAD_END]))
        adopt(graph, leaf, graph.nodes[a])
    elif kind == "give_up" and leaves:
        leaf = graph.own(rng.choice(leaves).uid)
        graph.touch(leaf.uid)
        leaf.given_up = True
    elif kind == "resample" and actions:
        graph = graph.copy()
        target = graph.own(rng.choice(actions).uid)
        graph.touch(target.uid)
        target.sigma = None
        detach_subtree(graph, target.uid, uids)
    elif kind == "replan" and leaves:
        graph = graph.copy()
        leaf = graph.nodes[rng.choice(leaves).uid]
        s = next(uids)
        graph.nodes[s] = Node(s, s, leaf.depth, leaf=GOAL)
        adopt(graph, leaf, graph.nodes[s])
        graph.prune()
    return graph


def assert_same_as_scratch(graph: PolicyGraph, horizon: float) -> None:
    fresh = path_bounds(graph, cost_for(horizon)).values
    kept = tracked_bounds(graph, cost_for(horizon), horizon).values
    assert {u: kept[u] for u in fresh} == fresh
    assert tracked_coverage_and_goal(graph) == coverage_and_goal(graph)


def test_kept_values_equal_scratch_after_every_kind_of_change():
    rng = random.Random(11)
    for trial in range(60):
        graph = random_dag(rng, rng.randint(3, 9))
        uids = iter(range(1000, 10_000))
        horizon = 4.0
        assert_same_as_scratch(graph, horizon)
        for _ in range(12):
            graph = mutate(rng, graph, uids)
            if rng.random() < 0.1:
                horizon += 1.0  # a new key: the bounds start afresh
            assert_same_as_scratch(graph, horizon)


def test_the_comparison_sees_a_change_nobody_recorded():
    # the check above can fail: refining a node in place without touch() leaves the kept
    # values stale (the engine touches every node it changes in place)
    graph = build({0: ("act", True, [(0.6, 1), (0.4, 2)]), 1: ("act", False, [(1.0, 3)]),
                   2: ("leaf", GOAL), 3: ("leaf", GOAL)})
    assert tracked_coverage_and_goal(graph) == pytest.approx((0.4, 0.4))
    graph.nodes[1].sigma = {}
    assert tracked_coverage_and_goal(graph) != coverage_and_goal(graph)
    graph.touch(1)
    assert tracked_coverage_and_goal(graph) == coverage_and_goal(graph) == (1.0, 1.0)


def test_cyclic_graphs_are_computed_from_scratch():
    # a retry loop (slip back to the same node): the bounds are the swept fixed point
    graph = build({0: ("act", True, [(1.0, 1)]), 1: ("act", False, [(0.3, 0), (0.7, 2)]),
                   2: ("leaf", HORIZON)})
    assert tracked_bounds(graph, cost_for(3.0), 3.0) == path_bounds(graph, cost_for(3.0))
    assert tracked_coverage_and_goal(graph) == coverage_and_goal(graph)
    graph.touch(1)
    graph.nodes[1].sigma = {}
    assert tracked_coverage_and_goal(graph) == coverage_and_goal(graph)


def test_one_sweep_equals_the_swept_fixed_point_on_acyclic_graphs():
    rng = random.Random(5)
    for _ in range(40):
        graph = random_dag(rng, rng.randint(2, 10))
        order, acyclic = graph.postorder()
        assert acyclic
        assert path_bounds(graph, cost_for(5.0)).values == \
            _swept_bounds(graph, order, cost_for(5.0))
    ladder = build(merging_ladder(12))
    assert select_path(ladder, cost_for(2.0)) is None  # all refined down to the goal


def test_taken_nodes_are_computed_aside():
    # a parallel batch's further paths: the taken nodes cost infinity, the kept bounds stay
    rng = random.Random(3)
    for _ in range(30):
        graph = random_dag(rng, 7)
        base = cost_for(4.0)
        tracked_bounds(graph, base, 4.0)
        taken = set(rng.sample(sorted(graph.nodes), 2))

        def cost(n: Node) -> float:
            return float("inf") if n.uid in taken else base(n)

        aside = tracked_bounds(graph, cost, 4.0, changed=taken).values
        fresh = path_bounds(graph, cost).values
        assert {u: aside[u] for u in fresh} == fresh
        kept = tracked_bounds(graph, base, 4.0).values
        assert {u: kept[u] for u in fresh} == path_bounds(graph, base).values
        # with a key nothing is kept for, the variant is computed from scratch, and kept not
        other = tracked_bounds(graph, cost, 5.0, changed=taken).values
        assert {u: other[u] for u in fresh} == fresh and graph.caches["bounds"][0] == 4.0


class CheckedEngine(Engine):
    """The engine, checking its kept bounds and masses against scratch at every step."""

    checks = 0
    unlocking_checks = 0  # the unlocked-mass values (unlocking.py), on acyclic graphs

    def _select(self, graph):
        kept = tracked_bounds(graph, self._node_cost, self.horizon).values
        fresh = path_bounds(graph, self._node_cost).values
        assert {u: kept[u] for u in fresh} == fresh
        self.checks += 1
        selected = super()._select(graph)
        kept_unlocking = graph.caches.get("unlocking")
        fresh_unlocking = IncrementalValues(unlock_local(self._node_cost))
        if kept_unlocking is not None and fresh_unlocking.refresh(graph):  # acyclic
            self.unlocking_checks += 1
            assert {u: kept_unlocking[1].values[u] for u in fresh_unlocking.values} \
                == fresh_unlocking.values
        return selected

    def _track(self, prg_node, graph):
        assert tracked_coverage_and_goal(graph) == coverage_and_goal(graph)
        super()._track(prg_node, graph)


@pytest.mark.parametrize("files,world,options", [
    (["shelf.stamp", "shelf5.stamp"], "plane2d", dict(seed=1)),            # learn, replan
    (["pack.stamp", "pack2.stamp"], "plane2d", dict(seed=0, explore_probability=0.0)),  # re-sample
    (["store.stamp", "store1.stamp"], "plane2d", dict(seed=3)),
    ("keva", "pybullet", dict(seed=0)),                                      # merging feeds
])
def test_the_engine_keeps_them_right_on_real_runs(files, world, options, tmp_path):
    if files == "keva":
        from examples.keva.scene import write_problem
        problem = write_problem(tmp_path / "tower3.stamp", seed=0, structure="tower", levels=3)
        files = [REPO / "examples" / "keva" / "domain.stamp", problem]
    else:
        files = [DATA / f for f in files]
    model = stampc.load_model(files)
    w = open_world(world, load_scene(model.problem, Path(files[-1]).parent), seed=0)
    try:
        engine = CheckedEngine(stampc.ground(model), w, resolve_model(model, w.package),
                               RefineOptions(time_limit=60, **options))
        list(engine.run())
    finally:
        w.close()
    assert engine.checks > 3 and engine.result().coverage > 0.0
    assert engine.unlocking_checks > 0
