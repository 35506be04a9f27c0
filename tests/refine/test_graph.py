"""Policy-graph bookkeeping: coverage (incl. retry cycles), p/ĉ path selection, copies."""

from __future__ import annotations

from fractions import Fraction

import pytest

from stampc.ir.grounded import Successor
from stampc.refine.graph import (DEAD_END, GOAL, HORIZON, Edge, Node, PolicyGraph, coverage,
                                 count_covered_paths, dead_end_mass, goal_probability,
                                 iter_leaf_paths)
from stampc.refine.selection import path_is_covered, select_path

NOOP = Successor(Fraction(1), 0, 0, Fraction(1))


def edge(p: float, child: int, k: int = 0) -> Edge:
    return Edge(p, k, NOOP, child)


def build(spec: dict[int, tuple]) -> PolicyGraph:
    """spec: uid -> ("leaf", kind) | ("act", refined, [(p, child), ...])."""
    nodes = {}
    for uid, item in spec.items():
        if item[0] == "leaf":
            nodes[uid] = Node(uid, uid, 0, leaf=item[1])
        else:
            _, refined, kids = item
            nodes[uid] = Node(uid, uid, 0, action=0, sigma={} if refined else None,
                              edges=[edge(p, c, k) for k, (p, c) in enumerate(kids)])
    return PolicyGraph(0, nodes)


def merging_ladder(levels: int) -> dict[int, tuple]:
    """``levels`` two-way branches (0.8 / 0.2) whose arms re-join at the next level, then
    a goal leaf: 2^levels root-to-leaf paths over 3 * levels + 1 nodes."""
    spec: dict[int, tuple] = {}
    for level in range(levels):
        a, nxt = 3 * level, 3 * level + 3
        spec[a] = ("act", True, [(0.8, a + 1), (0.2, a + 2)])
        spec[a + 1] = ("act", True, [(1.0, nxt)])
        spec[a + 2] = ("act", True, [(1.0, nxt)])
    spec[3 * levels] = ("leaf", GOAL)
    return spec


def test_leaf_path_probabilities_sum_to_one():
    g = build({0: ("act", False, [(0.3, 1), (0.7, 2)]),
               1: ("act", False, [(0.5, 3), (0.5, 4)]),
               2: ("leaf", GOAL), 3: ("leaf", GOAL), 4: ("leaf", DEAD_END)})
    probs = [p for p, _ in iter_leaf_paths(g)]
    assert len(probs) == 3
    assert sum(probs) == pytest.approx(1.0)


def test_coverage_counts_only_refined_terminal_paths():
    g = build({0: ("act", True, [(0.3, 1), (0.7, 2)]),
               1: ("act", False, [(1.0, 3)]),
               2: ("leaf", GOAL), 3: ("leaf", GOAL)})
    assert coverage(g) == pytest.approx(0.7)
    g[1].sigma = {}
    assert coverage(g) == pytest.approx(1.0)


def test_horizon_leaves_are_not_covered_and_proven_dead_ends_are():
    g = build({0: ("act", True, [(0.2, 1), (0.5, 2), (0.3, 3)]),
               1: ("leaf", HORIZON), 2: ("leaf", GOAL), 3: ("leaf", DEAD_END)})
    g[3].proven = True
    assert coverage(g) == pytest.approx(0.8)
    assert goal_probability(g) == pytest.approx(0.5)
    assert dead_end_mass(g) == pytest.approx(0.3)


def test_a_given_up_leaf_is_not_covered():
    # the solver gave up at node 3 (e.g. a timed-out solve): not proven, not covered
    g = build({0: ("act", True, [(0.2, 1), (0.5, 2), (0.3, 3)]),
               1: ("leaf", GOAL), 2: ("leaf", GOAL), 3: ("leaf", DEAD_END)})
    g[3].given_up = True
    assert coverage(g) == pytest.approx(0.7)
    assert dead_end_mass(g) == 0.0
    assert not path_is_covered(g, (0, 3))
    # and path selection never returns to it (its cost is infinite)
    assert select_path(g, lambda n: float("inf") if n.given_up else 0.0) is None


def test_retry_cycle_counts_with_geometric_probability():
    # 0 --0.9--> goal, --0.1--> 0 (slip: same abstract and concrete state): p(goal) = 1
    g = build({0: ("act", True, [(0.9, 1), (0.1, 0)]), 1: ("leaf", GOAL)})
    assert coverage(g) == pytest.approx(1.0, abs=1e-9)
    # with a dead-end exit the cycle splits mass 0.9 : 0.05 in the limit
    g = build({0: ("act", True, [(0.9, 1), (0.05, 0), (0.05, 2)]), 1: ("leaf", GOAL),
               2: ("leaf", HORIZON)})
    assert goal_probability(g) == pytest.approx(0.9 / 0.95, rel=1e-9)


def test_select_path_prefers_probability_over_cost():
    # two unrefined branches: 0.6 with cost 10 (ratio .06) vs 0.4 with cost 2 (ratio .2)
    g = build({0: ("act", True, [(0.6, 1), (0.4, 2)]),
               1: ("act", False, [(1.0, 3)]), 2: ("act", False, [(1.0, 4)]),
               3: ("leaf", GOAL), 4: ("leaf", GOAL)})
    cost = {1: 10.0, 2: 2.0}
    p, c, path = select_path(g, lambda n: 0.0 if n.refined or n.is_leaf else cost[n.uid])
    assert path == (0, 2, 4)
    assert (p, c) == (pytest.approx(0.4), 2.0)
    cost[2] = 20.0
    _, _, path = select_path(g, lambda n: 0.0 if n.refined or n.is_leaf else cost[n.uid])
    assert path == (0, 1, 3)


def random_tree(rng, max_uid: int, refined_share: float) -> dict[int, tuple]:
    """A random policy tree spec for :func:`build`: 1–3 children per action, random
    outcome weights, leaves of every kind, about ``refined_share`` of the actions refined."""
    spec, frontier, uid = {}, [0], 1
    while frontier:
        u = frontier.pop()
        if uid > max_uid or rng.random() < 0.3:
            spec[u] = ("leaf", rng.choice([GOAL, DEAD_END, HORIZON]))
            continue
        k = rng.randint(1, 3)
        ws = [rng.random() + 0.01 for _ in range(k)]
        spec[u] = ("act", rng.random() < refined_share,
                   [(w / sum(ws), uid + i) for i, w in enumerate(ws)])
        frontier.extend(uid + i for i in range(k))
        uid += k
    return spec


def test_select_path_matches_brute_force_ratio_order():
    import random
    rng = random.Random(7)
    for _ in range(50):
        spec = random_tree(rng, 25, 0.5)
        g = build(spec)
        cost = {n: rng.randint(1, 9) for n in spec}

        def node_cost(n):
            if n.is_leaf:
                return 3.0 if n.leaf == HORIZON else 0.0
            return 0.0 if n.refined else float(cost[n.uid])

        def path_cost(path):
            return sum(node_cost(g[u]) for u in path)

        candidates = [(p / path_cost(path), path) for p, path in iter_leaf_paths(g)
                      if not (g[path[-1]].leaf in (GOAL, DEAD_END)
                              and all(g[u].refined for u in path[:-1])) and path_cost(path) > 0]
        chosen = select_path(g, node_cost)
        if not candidates:
            assert chosen is None
            continue
        best = max(r for r, _ in candidates)
        assert chosen is not None
        assert chosen[0] / chosen[1] == pytest.approx(best)


def test_copy_is_independent():
    g = build({0: ("act", False, [(1.0, 1)]), 1: ("leaf", GOAL)})
    h = g.copy()
    assert h[0] is g[0]  # copy-on-write: the node objects are shared until one changes
    h.own(0).sigma = {}
    h.own(0).edges.append(edge(0.0, 1))
    assert g[0].sigma is None and len(g[0].edges) == 1 and h[0] is not g[0]
    assert g[1] is h[1]  # the unchanged node stays shared
    assert coverage(g) == 0.0 and coverage(h) == pytest.approx(1.0)


def test_a_shared_node_refuses_changes_made_around_own():
    """A write to a node both graphs hold would change the other graph's policy too."""
    g = build({0: ("act", False, [(1.0, 1)]), 1: ("leaf", GOAL)})
    h = g.copy()
    with pytest.raises(AttributeError, match="shared"):
        g[0].sigma = {}
    with pytest.raises(AttributeError):
        h[0].edges.append(edge(0.0, 1))  # the edges of a shared node are a tuple
    assert g[0].sigma is None and len(h[0].edges) == 1
    g.own(0).sigma = {}  # the graph's own copy may change; the other graph's stays
    assert g[0].sigma == {} and h[0].sigma is None


def test_select_path_finds_the_open_leaf_under_exponentially_many_refined_paths():
    """A refined ladder of 40 two-way branches that merge again (2^40 root-to-leaf paths,
    like a Keva tower whose feed outcomes lead to the same concrete state) above a single
    horizon leaf: the search must skip covered subtrees rather than enumerate paths (it
    used to run out of its pop budget and report nothing left to refine)."""
    spec: dict[int, tuple] = {}
    for level in range(40):
        a, b, nxt = 3 * level, 3 * level + 1, 3 * level + 3
        spec[a] = ("act", True, [(0.8, b), (0.2, 3 * level + 2)])
        spec[b] = ("act", True, [(1.0, nxt)])
        spec[3 * level + 2] = ("act", True, [(1.0, nxt)])
    spec[120] = ("act", True, [(0.5, 121), (0.5, 122)])
    spec[121] = ("leaf", GOAL)
    spec[122] = ("leaf", HORIZON)
    g = build(spec)

    def node_cost(n):
        return 4.0 if n.leaf == HORIZON else 0.0

    chosen = select_path(g, node_cost, max_pops=10_000)
    assert chosen is not None
    p, c, path = chosen
    assert path[-1] == 122 and c == 4.0
    assert p == pytest.approx(0.5 * 0.8 ** 40)  # the most likely way down: every 0.8 edge


def test_count_covered_paths_matches_enumeration_and_scales():
    import random
    rng = random.Random(3)
    for _ in range(40):
        g = build(random_tree(rng, 20, 0.7))
        expected = sum(1 for _, p in iter_leaf_paths(g) if path_is_covered(g, p))
        assert count_covered_paths(g) == expected
    # the merging ladder of 40 two-way branches: 2^40 covered paths, counted at once
    assert count_covered_paths(build(merging_ladder(40))) == 2 ** 40


def test_reaches_leaf_sees_loops_with_and_without_a_way_out():
    closed = build({0: ("act", True, [(1.0, 1)]), 1: ("act", True, [(1.0, 0)])})
    assert not closed.reaches_leaf(0) and not closed.reaches_leaf(1)
    retry = build({0: ("act", True, [(0.2, 0), (0.8, 1)]), 1: ("leaf", GOAL)})
    assert retry.reaches_leaf(0)


def test_postorder_puts_children_first_and_flags_cycles():
    # a merging ladder: each child comes before every parent, and the graph is acyclic
    spec = merging_ladder(5)
    g = build(spec)
    order, acyclic = g.postorder()
    assert acyclic and sorted(order) == sorted(spec)
    position = {u: i for i, u in enumerate(order)}
    assert all(position[e.child] < position[u] for u in order for e in g[u].edges)
    assert coverage(g) == pytest.approx(1.0)
    # a retry loop back to an ancestor is a cycle; its mass still converges
    loop = build({0: ("act", True, [(1.0, 1)]), 1: ("act", True, [(0.3, 0), (0.7, 2)]),
                  2: ("leaf", GOAL)})
    assert loop.postorder()[1] is False
    assert goal_probability(loop) == pytest.approx(1.0)
    with_exit = build({0: ("act", True, [(1.0, 1)]),
                       1: ("act", True, [(0.3, 0), (0.6, 2), (0.1, 3)]),
                       2: ("leaf", GOAL), 3: ("leaf", DEAD_END)})
    assert goal_probability(with_exit) == pytest.approx(6 / 7)


def test_select_path_answers_when_the_open_mass_is_spread_over_exponentially_many_paths():
    """An unrefined ladder of 40 two-way branches (0.5 / 0.5) that merge again: every
    prefix has the same bound, so the best-first search alone goes breadth first and runs
    out of pops before any leaf. It used to answer None, and the engine took the PRG node
    for exhausted and backtracked (Keva tower-24 seed 6 for 557 s, with 0.072 of the mass
    open below an unrefined subtree). The answer must be an uncovered path, and no worse
    than any other one (all ratios are equal here)."""
    spec: dict[int, tuple] = {}
    for level in range(40):
        a, nxt = 3 * level, 3 * level + 3
        spec[a] = ("act", False, [(0.5, a + 1), (0.5, a + 2)])
        spec[a + 1] = ("act", False, [(1.0, nxt)])
        spec[a + 2] = ("act", False, [(1.0, nxt)])
    spec[120] = ("leaf", GOAL)
    g = build(spec)

    def node_cost(n):
        return 0.0 if n.is_leaf else 1.0

    chosen = select_path(g, node_cost, max_pops=10_000)
    assert chosen is not None
    p, c, path = chosen
    assert path[0] == 0 and path[-1] == 120 and not path_is_covered(g, path)
    assert p == pytest.approx(0.5 ** 40) and c == 80.0
