"""examples/warehouse: grid adjacency from comprehensions and a symmetric predicate,
racks excluded by a derived predicate; slipping drives refined on the 2-D world."""

from __future__ import annotations

from pathlib import Path

import pytest

import stampc
from stampc.refine import RefineOptions
from stampc.semantics.api import check

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "warehouse"
FILES = [EXAMPLE / "domain.stamp", EXAMPLE / "problem.stamp"]


@pytest.fixture(scope="module")
def run():
    return stampc.refine_policy(FILES, world="plane2d", options=RefineOptions(seed=0, time_limit=60))


def test_checks_clean_and_lists_no_adjacency_by_hand():
    assert check(*FILES) == []
    assert "adjacent(cell_" not in FILES[1].read_text()
    model = stampc.compile(*FILES)
    adjacent = {tuple(t.name for t in a.args) for a in model.problem.init if a.predicate == "adjacent"}
    assert len(adjacent) == 12  # one fact per edge of the 3 x 3 grid; symmetry does the rest


def test_refines_to_full_coverage_around_the_rack(run):
    assert run.result.coverage == pytest.approx(1.0, abs=1e-9)
    nodes = run.to_json()["nodes"]
    drives = [n for n in nodes if n.get("action_name") == "drive"]
    assert drives and all(n["refined"] for n in drives)
    visited = {n["args"]["b"] for n in drives}
    assert "cell_1_1" not in visited  # the rack cell is never open
    for n in drives:  # a slip loops back to the same node
        names = {o.get("name"): o["child"] for o in n["outcomes"]}
        assert names["slip"] == n["id"] and names["moved"] != n["id"]


def test_replays_of_the_refined_policy_deliver(run, replay_policy):
    report = replay_policy(run.to_json(), "plane2d", runs=30, seed=2, world_seed=0)
    assert report.on_refined == 30 and report.count("success") == 30
