"""examples/kitchen: a cup behind others, grasps that slip, and first-contact discovery
(a cup may turn out to be dirty when first grasped), refined on the 2-D world."""

from __future__ import annotations

from pathlib import Path

import pytest

import stampc
from stampc.refine import RefineOptions
from stampc.semantics.api import check

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "kitchen"
FILES = [EXAMPLE / "domain.stamp", EXAMPLE / "problem.stamp"]


@pytest.fixture(scope="module")
def run():
    return stampc.refine_policy(FILES, world="plane2d", options=RefineOptions(seed=0, time_limit=60))


def test_checks_clean():
    assert check(*FILES) == []


def test_refines_to_full_coverage_moving_the_blockers(run):
    assert run.result.coverage == pytest.approx(1.0, abs=1e-9)
    nodes = run.to_json()["nodes"]
    learned = {f["fact"] for n in nodes for f in n.get("learned", ())}
    assert any(f.startswith("collision(cup_1, t_pick_cup_0") for f in learned)  # behind cup_1
    moved = {n["args"]["o"] for n in nodes if n.get("action_name") == "pick"}
    assert {"cup_0", "cup_1"} <= moved


def test_the_first_grasp_reveals_dirt_and_a_dirty_cup_is_washed(run):
    nodes = {n["id"]: n for n in run.to_json()["nodes"]}
    first = [n for n in nodes.values() if n.get("action_name") == "pick"
             and n["args"]["o"] == "cup_0" and n["args"]["p"] == "pose_cup_0"]
    assert first
    for n in first:
        outcomes = {o.get("name"): o for o in n["outcomes"]}
        assert set(outcomes) == {"grasped", "grasped+dirty", "slip"}
        assert outcomes["grasped+dirty"]["probability"] == pytest.approx(0.8 * 0.3)
        after = nodes[outcomes["grasped+dirty"]["child"]]
        assert after["action_name"] == "wash" and after["refined"]
        # the cup is grasped again from the sink: already checked, so no second discovery
        again = nodes[after["outcomes"][0]["child"]]
        assert again["action_name"] == "pick" and {o.get("name") for o in again["outcomes"]} == {
            "grasped", "slip"}
