"""Writing a refinement run's outputs stays bounded on large policy graphs: policy.svg and
policy.dot show the nodes nearest the root and collapse the rest, and say so."""

from __future__ import annotations

import json
import re
from fractions import Fraction
from pathlib import Path

import pytest

import stampc
from stampc.ir.grounded import Successor
from stampc.refine.export import (SVG_MAX_NODES, bounded_view, policy_dot, write_outputs,
                                  write_policy_svg)
from stampc.refine.graph import GOAL, Edge, Node, PolicyGraph
from stampc.refine.options import ProgressEvent, RefineResult

REPO = Path(__file__).resolve().parents[2]
NOOP = Successor(Fraction(1), 0, 0, Fraction(1))


@pytest.fixture(scope="module")
def model():
    shelf = REPO / "examples" / "shelf2d"
    return stampc.ground(stampc.compile(shelf / "domain.stamp", shelf / "problem.stamp"))


def binary_tree(size: int) -> PolicyGraph:
    """A complete binary policy tree of ``size`` nodes (inner nodes act, leaves are goals)."""
    nodes = {}
    for uid in range(size):
        kids = [c for c in (2 * uid + 1, 2 * uid + 2) if c < size]
        depth = (uid + 1).bit_length() - 1
        if kids:
            edges = [Edge(1 / len(kids), k, NOOP, c) for k, c in enumerate(kids)]
            nodes[uid] = Node(uid, uid, depth, action=0, edges=edges, sigma={} if uid % 2 else None)
        else:
            nodes[uid] = Node(uid, uid, depth, leaf=GOAL)
    return PolicyGraph(0, nodes)


def result() -> RefineResult:
    done = ProgressEvent(1.0, 0.5, 0.5, 3, 1, 1, "done")
    return RefineResult(0.5, 0.5, 1.0, 1.0, {}, 1, 1, 3, 1, 0, "time limit", (done,))


def test_bounded_view_keeps_the_nodes_nearest_the_root():
    drawn, hidden = bounded_view(binary_tree(1000), 15)
    assert drawn == list(range(15))          # breadth-first: the first four levels
    assert hidden == {u: 2 for u in range(7, 15)}  # each of the fourth level's children


def test_large_policy_outputs_are_collapsed_and_say_so(model, tmp_path):
    graph = binary_tree(3_000)
    notes = write_outputs(tmp_path, model, graph, result(), {}, {"problem": "big"})
    svg = (tmp_path / "policy.svg").read_text()
    shown = re.findall(r"<text[^>]*>([^<]*)</text>", svg)
    markers = [t for t in shown if t.strip().endswith("more")]
    assert markers and len(shown) - len(markers) <= SVG_MAX_NODES
    assert len(svg) < 1_000_000
    assert any("policy.svg" in n and "3000" in n and "collapsed" in n for n in notes)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["notes"] == notes
    policy = json.loads((tmp_path / "policy.json").read_text())
    assert len(policy["nodes"]) == 3_000    # the policy itself is never cut


def test_dot_collapses_above_its_limit(model):
    graph = binary_tree(5_000)
    full, note = policy_dot(model, graph)
    assert note is None and len(re.findall(r"^  n\d+ \[label", full, re.M)) == 5_000
    cut, note = policy_dot(model, graph, limit=100)
    assert len(re.findall(r"^  n\d+ \[label", cut, re.M)) == 100
    assert len(re.findall(r"^  more\d+ \[", cut, re.M)) == len(bounded_view(graph, 100)[1])
    assert note is not None and "policy.dot" in note and "4900" in note


def test_small_policies_are_drawn_whole(model, tmp_path):
    graph = binary_tree(31)
    assert write_policy_svg(model, graph, tmp_path / "policy.svg") is None
    svg = (tmp_path / "policy.svg").read_text()
    assert "more" not in svg and svg.count("<text") >= 31
