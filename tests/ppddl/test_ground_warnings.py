"""Grounding warnings (G201 no actions, G202 all costs 0, G203 add/delete conflicts) and
the conflicting-effects rule (add-wins, PDDL/MDPSim; delete-wins, mini-gpt)."""

from __future__ import annotations

from pathlib import Path

import pytest

from stampc.api import compile as compile_stamp
from stampc.api import ground, import_ppddl, solve
from stampc.backends.ppddl import import_ppddl_text
from stampc.diagnostics import Severity
from stampc.ir.grounded import GroundAtom
from stampc.solvers import SolverOptions

BENCHMARKS = Path(__file__).resolve().parents[3] / "shared" / "benchmarks" / "ppddl"

# `flip` adds and deletes (lit) in one outcome when ?a = ?b. Under add-wins (lit) is
# reached at once (cost 1); under delete-wins flipping a lamp onto itself never lights it,
# so the only way is the costlier `light` (cost 5).
TOGGLE = """(define (domain toggle) (:requirements :typing :rewards)
  (:types lamp)
  (:predicates (lit ?l - lamp))
  (:action flip :parameters (?a ?b - lamp)
    :effect (and (not (lit ?a)) (lit ?b) (decrease (reward) 1)))
  (:action light :parameters (?a - lamp)
    :effect (and (lit ?a) (decrease (reward) 5))))
(define (problem one) (:domain toggle) (:objects l1 - lamp) (:init) (:goal (lit l1)))
"""


def _codes(gm) -> list[str]:
    assert all(d.severity is Severity.WARNING for d in gm.diagnostics)
    return [d.code for d in gm.diagnostics]


def test_conflict_rules_give_different_values_on_a_tiny_instance():
    model = import_ppddl_text(TOGGLE, "toggle.pddl")
    add_wins = ground(model)
    delete_wins = ground(model, conflicting_effects="delete-wins")
    assert solve(add_wins).expected_cost == 1.0
    assert solve(delete_wins).expected_cost == 5.0
    flip = next(a for a in delete_wins.actions if a.name == "flip")
    lit = delete_wins.fact_index(GroundAtom("lit", ("l1",)))
    (outcome,) = flip.outcomes(0)
    assert outcome.apply(0) == 0 and outcome.apply(1 << lit) == 0  # the delete wins
    (outcome,) = next(a for a in add_wins.actions if a.name == "flip").outcomes(0)
    assert outcome.apply(0) == 1 << lit


@pytest.mark.parametrize("rule, words", [("add-wins", "add wins"),
                                         ("delete-wins", "delete wins")])
def test_conflict_warning_names_the_rule_once_per_schema_located(rule, words):
    text = TOGGLE.replace("(:objects l1 - lamp)", "(:objects l1 l2 l3 - lamp)")
    gm = ground(import_ppddl_text(text, "toggle.pddl"), conflicting_effects=rule)
    (d,) = [d for d in gm.diagnostics if d.code == "G203"]  # 3 conflicting flips, 1 warning
    assert words in d.message and "'flip'" in d.message and "lit(l1)" in d.message
    other = "delete-wins" if rule == "add-wins" else "add-wins"
    assert f"--conflicting-effects {other}" in d.hint
    assert (d.span.file, d.span.line) == ("toggle.pddl", 4)  # the (:action flip line


def test_conflicts_across_when_and_probabilistic_parts_are_found():
    text = TOGGLE.replace("(and (not (lit ?a)) (lit ?b) (decrease (reward) 1))",
                          "(and (probabilistic 1/2 (not (lit ?a))) (when (lit ?a) (lit ?b)) "
                          "(decrease (reward) 1))")
    assert "G203" in _codes(ground(import_ppddl_text(text, "t.pddl")))
    exclusive = TOGGLE.replace("(and (not (lit ?a)) (lit ?b) (decrease (reward) 1))",
                               "(and (probabilistic 1/2 (not (lit ?a)) 1/2 (lit ?b)) "
                               "(decrease (reward) 1))")
    assert "G203" not in _codes(ground(import_ppddl_text(exclusive, "t.pddl")))


def test_unknown_rule_is_rejected():
    with pytest.raises(ValueError, match="delete-wins"):
        ground(import_ppddl_text(TOGGLE, "t.pddl"), conflicting_effects="mini-gpt")


def test_no_actions_warning():
    text = TOGGLE.replace("(:init)", "(:init)").replace(
        ":effect (and (not (lit ?a))", ":precondition (lit ?a) :effect (and (not (lit ?a))")
    text = text.replace(":parameters (?a - lamp)\n    :effect",
                        ":parameters (?a - lamp) :precondition (lit ?a)\n    :effect")
    gm = ground(import_ppddl_text(text, "t.pddl"))
    assert not gm.actions and _codes(gm) == ["G201"]
    assert gm.diagnostics[0].span.file == "t.pddl"


def test_all_costs_zero_warning_ppddl_and_stamp(tmp_path):
    free = TOGGLE.replace("(decrease (reward) 1)", "").replace("(decrease (reward) 5)", "")
    free = free.replace(
        "(:goal (lit l1))", "(:goal (lit l1)) (:goal-reward 10) (:metric maximize (reward))")
    gm = ground(import_ppddl_text(free, "t.pddl"))
    (d,) = [d for d in gm.diagnostics if d.code == "G202"]
    assert "--unit-cost" in d.hint
    assert "G202" not in _codes(ground(import_ppddl_text(TOGGLE, "t.pddl")))
    stamp = tmp_path / "free.stamp"
    stamp.write_text(
        "domain free\n\npredicate done()\n\naction finish()\n    cost 0\n    eff  done\n\n"
        "problem p for free\n\ngoal done\n")
    assert _codes(ground(compile_stamp(stamp))) == ["G202"]


def test_benchmarks_without_conflicts_ground_without_g203():
    path = BENCHMARKS / "ippc2006-tireworld" / "p01.pddl"
    if not path.is_file():
        pytest.skip("shared benchmarks not present")
    assert "G203" not in _codes(ground(import_ppddl(path)))


def test_drive_p06_delete_wins_reproduces_mdplib_value():
    """mdp-lib (mini-gpt) reports V0 = 153.259588 on drive p06 (anchors-mdplib.csv);
    stampc's default add-wins gives 131.64: the rule is the whole difference."""
    path = BENCHMARKS / "ippc2006-drive" / "p06.pddl"
    if not path.is_file():
        pytest.skip("shared benchmarks not present")
    model = import_ppddl(path)
    options = SolverOptions(unit_cost=True, dead_end_cost=500.0)
    delete_wins = solve(ground(model, conflicting_effects="delete-wins"), options)
    add_wins = solve(ground(model), options)
    assert delete_wins.expected_cost == pytest.approx(153.259588, abs=1e-3)
    assert add_wins.expected_cost == pytest.approx(131.637, abs=1e-2)


def test_conflicts_across_parts_match_the_pairwise_definition():
    """The linear-time check equals "some part adds f and another part deletes f"."""
    import random

    from stampc.ir.ground_checks import _across_parts

    rng = random.Random(5)
    for _ in range(2000):
        parts = [(rng.getrandbits(6), rng.getrandbits(6)) for _ in range(rng.randint(1, 5))]
        pairwise = 0
        for i, (adds, _) in enumerate(parts):
            for j, (_, deletes) in enumerate(parts):
                if i != j:
                    pairwise |= adds & deletes
        assert _across_parts(parts) == pairwise, parts
