"""Path selection by unlocked mass (stampc/refine/unlocking.py), against brute force."""

from __future__ import annotations

import random

import pytest

from stampc.refine.graph import DEAD_END, GOAL, HORIZON, coverage
from stampc.refine.selection import select_path
from stampc.refine.unlocking import best_unlocking, better_ratio, select_unlocking

from test_graph import build, random_tree


def costs(table: dict[int, float]):
    """ĉ as the engine gives it: refined nodes and covered leaves 0, open leaves (a
    horizon, an unproven dead end) and unrefined actions their cost from ``table``."""
    return lambda n: 0.0 if n.refined or n.terminal else table[n.uid]


def test_a_branch_whose_continuations_are_refined_goes_first():
    """B (0.2 of the mass, cost 1) covers both its refined continuations at once, one of
    them shared with A: it adds 0.2. D adds 0.12 for the same cost. p/ĉ sees B's paths
    one by one (0.1 each) and takes D first; selection by unlocked mass takes B."""
    g = build({0: ("act", True, [(0.8, 1), (0.2, 2)]),
               1: ("act", True, [(0.85, 6), (0.15, 4)]),
               4: ("act", False, [(1.0, 5)]), 5: ("leaf", GOAL),
               2: ("act", False, [(0.5, 6), (0.5, 7)]),
               6: ("act", True, [(1.0, 8)]), 7: ("act", True, [(1.0, 9)]),
               8: ("leaf", GOAL), 9: ("leaf", GOAL)})
    cost = costs({2: 1.0, 4: 1.0})
    assert select_path(g, cost)[2] == (0, 1, 4, 5)
    gain, c, path = select_unlocking(g, cost, "k")
    assert path == (0, 2) and c == 1.0
    assert gain == pytest.approx(0.2)


def test_p_over_c_wins_where_the_sweep_stops_short():
    """Node 1 keeps its own best continuation: itself alone (0.3 for ĉ 1) over going on
    through 3 (1.0 for ĉ 5). Below the root's ĉ of 5 that choice is the worse one (0.3 / 6
    against 0.7 / 10 for p/ĉ's path alone), and the engine takes p/ĉ's path."""
    g = build({0: ("act", False, [(1.0, 1)]),
               1: ("act", False, [(0.3, 2), (0.7, 3)]),
               2: ("act", True, [(1.0, 4)]), 3: ("act", False, [(1.0, 4)]),
               4: ("leaf", GOAL)})
    cost = costs({0: 5.0, 1: 1.0, 3: 4.0})
    swept = select_unlocking(g, cost, "k")
    assert swept[1:] == (6.0, (0, 1)) and swept[0] == pytest.approx(0.3)
    by_path = select_path(g, cost)
    assert by_path[2] == (0, 1, 3, 4) and by_path[0] / by_path[1] == pytest.approx(0.07)
    assert better_ratio(swept, by_path) is by_path
    assert better_ratio(swept, None) is swept
    richer = (0.9, 6.0, (0, 1))  # had the sweep's path added 0.9, it would stay
    assert better_ratio(richer, by_path) is richer


def test_trees_are_left_to_p_over_c():
    """Without merged branches the exact p/ĉ search decides (False), even where the
    sweep would refine the same node (it stops at the unrefined branch, whose goal is
    covered with it; p/ĉ's path goes on to the leaf)."""
    g = build({0: ("act", True, [(0.6, 1), (0.4, 2)]),
               1: ("act", False, [(1.0, 3)]), 2: ("act", False, [(1.0, 4)]),
               3: ("leaf", GOAL), 4: ("leaf", GOAL)})
    cost = costs({1: 10.0, 2: 2.0})
    assert select_unlocking(g, cost, "k") is False
    assert best_unlocking(g, cost, "k")[2] == (0, 2)
    assert select_path(g, cost)[2] == (0, 2, 4)


def _refined_along(spec: dict, path: tuple[int, ...]) -> dict:
    """``spec`` with every action on ``path`` refined and its open leaf made a goal (the
    optimistic count both selections use for a leaf still to extend)."""
    out = dict(spec)
    for uid in path:
        item = out[uid]
        if item[0] == "act":
            out[uid] = ("act", True, item[2])
        elif item[1] in (HORIZON, DEAD_END):  # unproven: open, extended to the goal
            out[uid] = ("leaf", GOAL)
    return out


@pytest.mark.parametrize("seed", range(4))
def test_the_gain_is_the_coverage_the_path_adds(seed):
    """On trees the reported gain is exactly what refining the path's nodes (and
    extending its open leaf) adds to the coverage; on a refined prefix the choice is
    the best gain per ĉ over all paths (brute force)."""
    rng = random.Random(seed)
    for _ in range(40):
        spec = random_tree(rng, 25, 0.5)
        table = {uid: float(rng.randint(1, 9)) for uid in spec}
        g = build(spec)
        cost = costs(table)
        found = best_unlocking(g, cost, "k")
        before = coverage(g)
        if found is None:
            assert all(coverage(build(_refined_along(spec, path))) == pytest.approx(before)
                       for _, path in _leaf_paths(g))
            continue
        gain, c, path = found
        assert gain > 0
        assert coverage(build(_refined_along(spec, path))) - before == pytest.approx(gain)
        assert c == pytest.approx(sum(cost(g[u]) for u in path))


def _leaf_paths(g):
    from stampc.refine.graph import iter_leaf_paths
    return iter_leaf_paths(g)


def test_the_root_alone_or_a_refined_prefix_chooses_the_best_ratio():
    """Below a refined root the gains add up without interaction: the choice is the
    brute-force best gain / ĉ among the root's one-step branches."""
    rng = random.Random(3)
    for _ in range(30):
        k = rng.randint(2, 5)
        weights = [rng.random() + 0.05 for _ in range(k)]
        spec = {0: ("act", True, [(w / sum(weights), i + 1) for i, w in enumerate(weights)])}
        for i in range(k):
            spec[i + 1] = ("act", False, [(1.0, 100 + i)])
            spec[100 + i] = ("leaf", GOAL)
        table = {i + 1: float(rng.randint(1, 9)) for i in range(k)}
        g = build(spec)
        gain, c, path = best_unlocking(g, costs(table), "k")
        best = max(spec[0][2][i][0] / table[i + 1] for i in range(k))
        assert gain / c == pytest.approx(best)
        assert len(path) == 2  # stops at the unrefined branch: its goal is covered with it


def test_nothing_to_gain_and_cycles():
    covered = build({0: ("act", True, [(1.0, 1)]), 1: ("leaf", GOAL)})
    assert best_unlocking(covered, costs({}), "k") is None
    cyclic = build({0: ("act", True, [(0.9, 1), (0.1, 0)]), 1: ("act", False, [(1.0, 2)]),
                    2: ("leaf", GOAL)})
    assert select_unlocking(cyclic, costs({1: 1.0}), "k") is False  # p/ĉ decides there


def test_an_unknown_selection_rule_is_refused():
    from stampc.diagnostics import StampcError
    from stampc.refine import RefineOptions, check_refine_options

    with pytest.raises(StampcError) as err:
        check_refine_options(RefineOptions(selection="cheapest"))
    assert {d.code for d in err.value.diagnostics} == {"R003"}
    check_refine_options(RefineOptions(selection="path"))  # both rules are accepted
    check_refine_options(RefineOptions(selection="unlocked"))


def test_merges_follow_the_graph_as_it_changes():
    """A node with two parents makes the graph merged; once one parent lets it go (its
    edges replaced) or is pruned from the graph, it is a tree again."""
    from test_graph import edge

    g = build({0: ("act", True, [(0.5, 1), (0.5, 2)]),
               1: ("act", True, [(1.0, 3)]), 2: ("act", False, [(1.0, 3)]),
               3: ("act", False, [(1.0, 4)]), 4: ("leaf", GOAL), 5: ("leaf", GOAL)})
    cost = costs({2: 1.0, 3: 1.0})
    assert select_unlocking(g, cost, "k") is not False
    g.own(2).edges[:] = [edge(1.0, 5)]  # 2 now goes elsewhere: 3 has one parent
    g.touch(2)
    assert select_unlocking(g, cost, "k") is False
    g.own(2).edges[:] = [edge(1.0, 3)]
    g.touch(2)
    assert select_unlocking(g, cost, "k") is not False
    g.own(0).edges[:] = [edge(1.0, 1)]  # 2 is cut off and pruned
    g.touch(0)
    del g.nodes[2]
    assert select_unlocking(g, cost, "k") is False
