"""The world decides: true probabilities other than the model's move the success rate
exactly as the policy tree predicts; unplanned outcomes never count as successes."""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import pytest

from stampc import api
from stampc.diagnostics import Span, StampcError
from stampc.execute.report import Z99
from stampc.execute.session import execute_file
from stampc.execute.truth import build_truth, predicted_success, true_lifted_model
from stampc.ir import lifted as L
from stampc.solvers.simulation import wilson_interval


def _risky_picks(policy: dict) -> int:
    """Picks along the nominal (uncrushed) path whose crushed outcome leads off it to a
    node that is not a goal (unrefined: crushing the target itself still holds it)."""
    nodes = {n["id"]: n for n in policy["nodes"]}
    node, picks = nodes[policy["root"]], 0
    while node["leaf"] is None and node["refined"]:
        crushed = [o for o in node["outcomes"]
                   if any(a["predicate"] == "crushed" for a in o["adds"])]
        nominal = [o for o in node["outcomes"] if o not in crushed]
        picks += any(nodes[o["child"]]["leaf"] != "goal" for o in crushed)
        node = nodes[nominal[0]["child"]]
    return picks


@pytest.mark.parametrize("crush", [0.1, 0.4])
def test_success_rate_follows_the_true_probabilities(shelf: Path, crush: float) -> None:
    path = shelf / "partial" / "policy.json"
    policy = json.loads(path.read_text())
    k = _risky_picks(policy)
    assert k >= 2 and policy["coverage"] < 1  # crushed branches are left unrefined
    expected = (1 - crush) ** k  # every crush leads to an unrefined branch
    runs = 300
    report = execute_file(path, runs=runs, seed=7, truth=[f"crushed={crush}"])
    assert report.predicted == pytest.approx(expected)
    lo, hi = wilson_interval(report.count("success"), runs, Z99)
    assert lo <= expected <= hi
    assert report.count("success") + report.count("unrefined") == runs
    pick = report.outcome_table()["pick"]
    (crushed,) = [name for name in pick if "crushed" in name]  # its `as` label, or +crushed
    assert pick[crushed]["truth"] == pytest.approx(crush)
    assert pick[crushed]["model"] == pytest.approx(0.1)


def test_model_mismatch_moves_the_rate_away_from_the_model(shelf: Path) -> None:
    path = shelf / "partial" / "policy.json"
    model_rate = execute_file(path, runs=200, seed=3)
    mismatched = execute_file(path, runs=200, seed=3, truth=["pick.crushed=0.5"])
    assert model_rate.predicted == pytest.approx(json.loads(path.read_text())["coverage"])
    assert wilson_interval(mismatched.count("success"), 200, Z99)[1] < \
        wilson_interval(model_rate.count("success"), 200, Z99)[0]


def test_unplanned_outcomes_end_on_an_unrefined_branch(shelf: Path) -> None:
    report = execute_file(shelf / "partial" / "policy.json", runs=50, seed=1,
                          truth=["crushed=1"])
    assert report.count("success") == 0 and report.count("unrefined") == 50
    assert report.predicted == 0.0


def test_same_seed_same_runs(shelf: Path) -> None:
    a = execute_file(shelf / "full" / "policy.json", runs=30, seed=5, truth=["crushed=0.5"])
    b = execute_file(shelf / "full" / "policy.json", runs=30, seed=5, truth=["crushed=0.5"])
    assert a.to_json() == b.to_json()


def test_reweighting_keeps_the_block_a_distribution(shelf: Path) -> None:
    model = api.load_model([shelf / "domain.stamp", shelf / "problem.stamp"])
    true = true_lifted_model(model, {"crushed": Fraction(3, 10)}, Span.point("t"))
    pick = next(a for a in true.domain.actions if a.name == "pick")
    blocks = [e for e in pick.effect.effects if isinstance(e, L.Probabilistic)]
    assert [o.probability for o in blocks[0].outcomes] == [Fraction(3, 10)]


@pytest.mark.parametrize("key, code", [("broken=0.5", "T001"), ("place.crushed=0.5", "T001"),
                                       ("crushed=1.5", "T002"), ("crushed", "T001")])
def test_bad_truth_keys_are_located(shelf: Path, key: str, code: str) -> None:
    with pytest.raises(StampcError) as info:
        execute_file(shelf / "full" / "policy.json", runs=1, seed=0, truth=[key])
    assert info.value.diagnostics[0].code == code
    assert "crushed" in (info.value.diagnostics[0].hint or "") or code == "T002"


def test_prediction_with_the_model_as_truth_is_the_goal_probability(shelf: Path) -> None:
    policy = json.loads((shelf / "full" / "policy.json").read_text())
    model = api.load_model([shelf / "domain.stamp", shelf / "problem.stamp"])
    truth = build_truth(model, {}, Span.point("t"))
    assert predicted_success(policy, truth) == pytest.approx(policy["goal_probability"])


def test_json_report_names_every_figure(shelf: Path, capsys) -> None:
    from stampc.cli import main

    code = main(["execute", str(shelf / "partial" / "policy.json"), "--runs", "40",
                 "--seed", "2", "--truth", "crushed=0.5", "--format", "json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0  # unrefined branches are not failures of the refined policy
    assert data["runs"] == 40 and data["success"] + data["unrefined"] == 40
    lo, hi = data["success_ci95"]
    assert lo <= data["success_rate"] <= hi
    assert data["truth"] == {"crushed": 0.5}
    (crushed,) = [name for name in data["outcomes"]["pick"] if "crushed" in name]
    assert data["outcomes"]["pick"][crushed]["truth"] == pytest.approx(0.5)
    assert {"collisions", "goal_check_failures", "predicted_success",
            "coverage_x_goal_probability"} <= set(data)


def test_an_outcome_missing_from_the_policy_is_unplanned(shelf: Path) -> None:
    policy = json.loads((shelf / "full" / "policy.json").read_text())
    for node in policy["nodes"]:  # forget every crushed branch
        if node.get("outcomes"):
            node["outcomes"] = [o for o in node["outcomes"]
                                if not any(a["predicate"] == "crushed" for a in o["adds"])]
    edited = shelf / "full" / "no-crush.json"
    edited.write_text(json.dumps(policy))
    try:
        report = execute_file(edited, runs=60, seed=4, truth=["crushed=0.5"])
    finally:
        edited.unlink()
    unplanned = [r for r in report.runs if "was not planned for" in r.detail]
    assert unplanned and all(r.status == "unrefined" for r in unplanned)
    assert report.count("success") + len(unplanned) == 60
    assert report.predicted < 0.5


def test_outcomes_list_only_deletes_of_true_facts_and_older_policies_still_match(
        shelf: Path, tmp_path: Path) -> None:
    """A policy's outcomes delete only facts true in their node's state (a `?` effect
    deletes collision(o, t) for every trajectory, nearly all already false). A policy
    written before, listing every delete, executes the same: the world matches its
    outcomes too."""
    path = shelf / "full" / "policy.json"
    policy = json.loads(path.read_text())
    gm = api.ground(api.load_model([shelf / "domain.stamp", shelf / "problem.stamp"]))
    facts = {str(f): i for i, f in enumerate(gm.facts)}
    actions = {a.label: a for a in gm.actions}
    names = lambda mask: sorted(str(gm.facts[i]) for i in range(len(gm.facts)) if mask >> i & 1)  # noqa: E731
    widened = 0
    for node in policy["nodes"]:
        state_names = set(node["state"])
        for outcome in node.get("outcomes", []):
            deleted = {f"{d['predicate']}({', '.join(d['args'])})" for d in outcome["deletes"]}
            assert deleted <= state_names, node["action"]
        if not node.get("outcomes"):
            continue
        # rewrite as the previous format did: every delete of the ground outcome
        state = sum(1 << facts[f] for f in node["state"] if f in facts)
        for outcome, ground in zip(node["outcomes"], actions[node["action"]].outcomes(state)):
            every = names(ground.delete & ~ground.add)
            widened += len(every) > len(outcome["deletes"])
            outcome["deletes"] = [{"predicate": f.split("(")[0],
                                   "args": f[f.index("(") + 1:-1].split(", ") if "(" in f else []}
                                  for f in every]
    assert widened  # the shelf's placements delete facts that were false
    old = tmp_path / "policy.json"
    old.write_text(json.dumps(policy))
    now = execute_file(path, runs=40, seed=5)
    before = execute_file(old, runs=40, seed=5)
    assert now.count("success") == before.count("success") == 40
