"""`stampc solve` end to end on PPDDL input."""

from __future__ import annotations

import json

import pytest

from stampc.cli import main

# A coin that lands heads with probability 1/4; reaching "heads" needs 4 flips on average.
COIN = """
(define (domain coin)
  (:requirements :probabilistic-effects)
  (:predicates (heads) (broken))
  (:action flip :precondition (not (broken))
    :effect (probabilistic 1/4 (heads) 1/4 (broken))))
(define (problem toss) (:domain coin) (:init) (:goal (heads)))
"""


@pytest.fixture
def coin(tmp_path):
    path = tmp_path / "coin.pddl"
    path.write_text(COIN)
    return path


def test_json_report_and_policy_outputs(coin, tmp_path, capsys):
    policy, dot = tmp_path / "policy.json", tmp_path / "policy.dot"
    rc = main(["solve", str(coin), "--format", "json", "--dead-end-cost", "10",
               "-o", str(policy), "--dot", str(dot), "--simulate", "300", "--seed", "3"])
    assert rc == 0
    report = json.loads(capsys.readouterr().out)
    for key in ("expected_cost", "goal_probability", "solve_time_s", "total_time_s",
                "states_expanded"):
        assert key in report
    # Each flip: 1/4 heads, 1/4 broken (dead end, 10), 1/2 again: V = (1 + 2.5) / (1/2) = 7.
    assert report["expected_cost"] == pytest.approx(7.0)
    assert report["goal_probability"] == pytest.approx(0.5)
    assert report["simulation"]["runs"] == 300
    data = json.loads(policy.read_text())
    statuses = {tuple(e["state"]): (e["action"], e["status"]) for e in data["policy"]}
    assert statuses[()] == ("flip", "act")
    assert statuses[("heads()",)] == (None, "goal")
    assert statuses[("broken()",)] == (None, "dead_end")
    text = dot.read_text()
    assert text.startswith("digraph policy") and 'label="flip p=0.25"' in text


def test_text_report_and_unit_cost(coin, capsys):
    assert main(["solve", str(coin), "--algorithm", "lrtdp", "--dead-end-cost", "100"]) == 0
    out = capsys.readouterr().out
    assert "expected cost     52.000000" in out  # (1 + 25) / (1/2)
    assert "goal probability  0.500000" in out


def test_finite_horizon_option(coin, tmp_path, capsys):
    policy = tmp_path / "policy.json"
    assert main(["solve", str(coin), "--horizon", "1", "--dead-end-cost", "10",
                 "--format", "json", "-o", str(policy)]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["horizon"] == 1
    assert report["goal_probability"] == pytest.approx(0.25)
    assert report["expected_cost"] == pytest.approx(1 + 0.75 * 10)
    entries = {(tuple(e["state"]), e["t"]): e["status"]
               for e in json.loads(policy.read_text())["policy"]}
    # At t = H the horizon takes precedence over "dead end" (as in policy trees).
    assert entries == {((), 0): "act", ((), 1): "horizon", (("heads()",), 1): "goal",
                       (("broken()",), 1): "horizon"}


def test_input_errors_have_exit_codes(tmp_path, capsys):
    assert main(["solve", str(tmp_path / "missing.pddl")]) == 2
    bad = tmp_path / "bad.pddl"
    bad.write_text("(define (domain d) (:predicates (p)) (:action a :effect (q)))\n"
                   "(define (problem x) (:domain d) (:init) (:goal (p)))\n")
    assert main(["solve", str(bad)]) == 1
    err = capsys.readouterr().err
    assert "bad.pddl:1:" in err
    assert main(["solve", str(bad), "--epsilon", "0"]) == 2


def test_benchmark_matches_reference_solver(ppddl_benchmarks, capsys):
    """ippc2006-tireworld/p03 under the MDP-Lib conventions: the C++ LAO* reports
    V0 = 3.799976 (eps = 1e-4), see anchors-mdplib.csv."""
    rc = main(["solve", str(ppddl_benchmarks / "ippc2006-tireworld" / "p03.pddl"),
               "--unit-cost", "--dead-end-cost", "500", "--format", "json"])
    assert rc == 0
    report = json.loads(capsys.readouterr().out)
    assert report["expected_cost"] == pytest.approx(3.799976, abs=1e-3)
    assert report["goal_probability"] == pytest.approx(1.0)
